//! Images: the film a render produces, and writing/reading image files.
//!
//! PNG is display-referred: radiance is scaled by `2^exposure`, clamped to
//! [0, 1] and sRGB-encoded to 8 bits. OpenEXR is scene-referred: linear
//! float radiance, unscaled. The file ending chooses the format.

use crate::color::{Rgb, linear_to_srgb};
use std::fs::File;
use std::io::{BufWriter, Seek, Write};
use std::path::{Path, PathBuf};

/// How every OpenEXR file is laid out: run-length-encoded scan lines
/// stored in increasing order. The order matters: `exr` compresses blocks
/// in parallel, and with its default (`LineOrder::Unspecified`, 64² tiles)
/// it stores them in the order they finish, so the same image gave
/// different files from run to run on a loaded machine (issue 9). With
/// `Increasing` the writer sorts them: the file's bytes depend on the
/// pixels alone. RLE, as `exr`'s default: ZIP made writing a 640×360
/// image take about 0.7 s longer.
pub const EXR_ENCODING: exr::prelude::Encoding = exr::prelude::Encoding {
    compression: exr::prelude::Compression::RLE,
    blocks: exr::prelude::Blocks::ScanLines,
    line_order: exr::prelude::LineOrder::Increasing,
};

/// A linear-RGB image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    width: u32,
    height: u32,
    pixels: Vec<Rgb>,
}

/// Image file formats, chosen by the file ending.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    Png,
    Exr,
}

/// Why an image could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("{path}: unknown image format: the file name must end in .png or .exr")]
    UnknownFormat { path: PathBuf },
    #[error("{path}: {message}")]
    Io { path: PathBuf, message: String },
}

impl ImageFormat {
    pub fn from_path(path: &Path) -> Result<Self, ImageError> {
        match path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
        {
            Some("png") => Ok(ImageFormat::Png),
            Some("exr") => Ok(ImageFormat::Exr),
            _ => Err(ImageError::UnknownFormat {
                path: path.to_owned(),
            }),
        }
    }
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

    /// 8-bit sRGB bytes (RGB, row-major) after `2^exposure` scaling.
    pub fn to_srgb8(&self, exposure: f32) -> Vec<u8> {
        let scale = exposure.exp2();
        self.pixels
            .iter()
            .flat_map(|p| (*p * scale).to_array())
            .map(|v| (linear_to_srgb(v.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8)
            .collect()
    }

    /// Writes the image in the format its ending names; `exposure` (stops)
    /// applies to PNG only. The file appears complete or not at all (see
    /// [`OutputFile`]).
    pub fn write(&self, path: &Path, exposure: f32) -> Result<(), ImageError> {
        OutputFile::create(path)?.finish(self, exposure)
    }

    /// Encodes the image into `out` in `format`.
    fn encode(
        &self,
        format: ImageFormat,
        exposure: f32,
        out: &mut (impl Write + Seek),
    ) -> Result<(), String> {
        match format {
            ImageFormat::Png => {
                use image::ImageEncoder;
                image::codecs::png::PngEncoder::new(&mut *out)
                    .write_image(
                        &self.to_srgb8(exposure),
                        self.width,
                        self.height,
                        image::ExtendedColorType::Rgb8,
                    )
                    .map_err(|e| e.to_string())
            }
            ImageFormat::Exr => {
                use exr::prelude::*;
                let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                    let p: Rgb = self.pixels[y * self.width as usize + x];
                    (p.x, p.y, p.z)
                });
                let size = (self.width as usize, self.height as usize);
                let layer = Layer::new(size, LayerAttributes::default(), EXR_ENCODING, channels);
                exr::prelude::Image::from_layer(layer)
                    .write()
                    .to_buffered(&mut *out)
                    .map_err(|e| e.to_string())
            }
        }
    }

    /// Reads the first RGB(A) layer of an OpenEXR file as linear radiance.
    pub fn read_exr(path: &Path) -> Result<Self, ImageError> {
        use exr::prelude::*;
        let image = read_first_rgba_layer_from_file(
            path,
            |resolution, _| {
                (
                    resolution.width(),
                    vec![Rgb::ZERO; resolution.width() * resolution.height()],
                )
            },
            |(width, pixels): &mut (usize, Vec<Rgb>),
             position,
             (r, g, b, _a): (f32, f32, f32, f32)| {
                pixels[position.y() * *width + position.x()] = Rgb::new(r, g, b);
            },
        )
        .map_err(|e| ImageError::Io {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
        let size = image.layer_data.size;
        let (_, pixels) = image.layer_data.channel_data.pixels;
        Ok(Self::from_pixels(
            size.width() as u32,
            size.height() as u32,
            pixels,
        ))
    }
}

/// An image file being written: a temporary file beside the target,
/// created up front (so an unwritable destination is found before a
/// render), then written, flushed, synced to disk and renamed onto the
/// target. Until [`OutputFile::finish`] succeeds the target is untouched;
/// dropped unfinished, the temporary file is removed.
pub struct OutputFile {
    target: PathBuf,
    temp: PathBuf,
    format: ImageFormat,
    file: Option<File>,
}

impl OutputFile {
    /// Checks the format and creates the temporary file
    /// (`.<name>.<pid>.tmp` in the target's directory).
    pub fn create(target: &Path) -> Result<Self, ImageError> {
        let format = ImageFormat::from_path(target)?;
        let io = |message: String| ImageError::Io {
            path: target.to_owned(),
            message,
        };
        let name = target
            .file_name()
            .ok_or_else(|| io("the output path names no file".into()))?;
        if target.is_dir() {
            return Err(io("the output path is a directory".into()));
        }
        let mut temp_name = std::ffi::OsString::from(".");
        temp_name.push(name);
        temp_name.push(format!(".{}.tmp", std::process::id()));
        let temp = target.with_file_name(temp_name);
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp)
            .map_err(|e| io(format!("cannot create the output file: {e}")))?;
        Ok(Self {
            target: target.to_owned(),
            temp,
            format,
            file: Some(file),
        })
    }

    /// The file the image will be written to.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Encodes `image`, flushes and syncs the temporary file and renames
    /// it onto the target. Any failure (a full disk, a size limit) is an
    /// error and leaves the target as it was.
    pub fn finish(mut self, image: &Image, exposure: f32) -> Result<(), ImageError> {
        let io = |message: String| ImageError::Io {
            path: self.target.clone(),
            message,
        };
        let file = self.file.take().expect("an unfinished output has its file");
        let mut out = BufWriter::new(file);
        image
            .encode(self.format, exposure, &mut out)
            .map_err(|e| io(format!("cannot write the image: {e}")))?;
        let file = out
            .into_inner()
            .map_err(|e| io(format!("cannot write the image: {}", e.error())))?;
        file.sync_all()
            .map_err(|e| io(format!("cannot write the image to disk: {e}")))?;
        drop(file);
        std::fs::rename(&self.temp, &self.target)
            .map_err(|e| io(format!("cannot move the finished image into place: {e}")))?;
        self.temp = PathBuf::new();
        Ok(())
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        if !self.temp.as_os_str().is_empty() {
            self.file.take();
            let _ = std::fs::remove_file(&self.temp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_appears_whole_and_leaves_no_temporary_file() {
        let dir = std::env::temp_dir().join(format!("tyndall-film-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let image = Image::from_pixels(2, 1, vec![Rgb::new(0.5, 0.25, 1.0); 2]);
        for name in ["a.png", "a.exr"] {
            let target = dir.join(name);
            let out = OutputFile::create(&target).unwrap();
            assert!(!target.exists(), "the target appears only when finished");
            out.finish(&image, 0.0).unwrap();
            assert!(target.exists());
        }
        let back = Image::read_exr(&dir.join("a.exr")).unwrap();
        assert_eq!(back, image);
        // An abandoned output leaves nothing behind.
        drop(OutputFile::create(&dir.join("b.png")).unwrap());
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Regression (issue 11): a full disk lost the PNG's flush error and
    /// exited 0. `/dev/full` fails every write; the error must surface.
    #[test]
    fn write_errors_are_reported() {
        let full = Path::new("/dev/full");
        if !full.exists() {
            return;
        }
        let image = Image::from_pixels(1, 1, vec![Rgb::ONE]);
        let mut file = std::fs::OpenOptions::new().write(true).open(full).unwrap();
        let mut out = BufWriter::new(&mut file);
        let written = image
            .encode(ImageFormat::Png, 0.0, &mut out)
            .and_then(|()| out.flush().map_err(|e| e.to_string()));
        assert!(written.is_err());
    }
}
