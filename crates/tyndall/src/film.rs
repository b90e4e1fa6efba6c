//! The film a render produces: an image of linear-RGB radiance
//! (docs/physics.md §1.2).
//!
//! Plain data, with no file format: writing and reading PNG and OpenEXR
//! files, and comparing images, are the `tyndall-image` crate's.

use crate::color::Rgb;

/// A linear-RGB image, rows top to bottom: each pixel is the box-filtered
/// mean of the radiance over its footprint (docs/physics.md §1.2).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    width: u32,
    height: u32,
    pixels: Vec<Rgb>,
}

impl Image {
    /// # Panics
    /// If `pixels.len() != width·height` (a programming error).
    pub fn from_pixels(width: u32, height: u32, pixels: Vec<Rgb>) -> Self {
        assert_eq!(pixels.len(), width as usize * height as usize);
        Self {
            width,
            height,
            pixels,
        }
    }

    /// The image at `1/k` of the resolution: the mean of each `k`×`k`
    /// block (in f64). A pixel being the box-filtered mean of the radiance
    /// over its footprint, this is exactly the image a `k`-times coarser
    /// render converges to. Trailing rows and columns that do not fill a
    /// block are dropped.
    pub fn box_downsample(&self, k: u32) -> Image {
        let k = k.max(1);
        let (w, h) = (self.width / k, self.height / k);
        let mut pixels = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            for x in 0..w {
                let mut sum = glam::DVec3::ZERO;
                for dy in 0..k {
                    for dx in 0..k {
                        sum += self.pixel(x * k + dx, y * k + dy).as_dvec3();
                    }
                }
                pixels.push((sum / f64::from(k * k)).as_vec3());
            }
        }
        Image::from_pixels(w, h, pixels)
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    pub fn pixels(&self) -> &[Rgb] {
        &self.pixels
    }

    pub fn pixel(&self, x: u32, y: u32) -> Rgb {
        self.pixels[y as usize * self.width as usize + x as usize]
    }
}
