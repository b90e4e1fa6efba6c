//! Colour textures: an sRGB-encoded 8-bit image looked up at texture
//! coordinates with bilinear filtering in linear RGB, as a glTF base
//! colour texture is (glTF 2.0 §3.8: sRGB transfer function, texel centres
//! at half-integers, the sampler's wrap modes).
//!
//! Texels stay 8-bit sRGB, three bytes each, and are decoded through a
//! 256-entry table when looked up: a 4096² texture takes 48 MiB instead of
//! the 192 MiB of linear floats. An image's alpha channel, if it has one,
//! is kept as a fourth byte per texel for the surface's coverage (glTF
//! `alphaMode`, §3.9.4: alpha is linear coverage, not sRGB;
//! [`crate::coverage`]), looked up with the same filtering.

use crate::color::{Rgb, srgb_to_linear};
use glam::{Vec2, Vec3};
use std::sync::OnceLock;

/// Index of a texture in a scene's texture list.
pub type TextureId = u32;

/// How texture coordinates outside `[0, 1]` map into the image along one
/// axis (glTF sampler `wrapS`/`wrapT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The image tiles (glTF's default, REPEAT).
    #[default]
    Repeat,
    /// Coordinates clamp to the edge texels (CLAMP_TO_EDGE).
    Clamp,
    /// The image tiles, every other copy mirrored (MIRRORED_REPEAT).
    Mirror,
}

impl Wrap {
    /// Texel index `i` (any integer) mapped into `0..n`.
    #[inline]
    pub(crate) fn index(self, i: i64, n: u32) -> usize {
        let n = i64::from(n);
        let wrapped = match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let k = i.rem_euclid(2 * n);
                if k < n { k } else { 2 * n - 1 - k }
            }
        };
        wrapped as usize
    }
}

/// An sRGB-encoded colour image of `width × height` texels, row by row
/// from the top (texture coordinate v = 0 is the first row, as in glTF).
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    width: u32,
    height: u32,
    texels: Vec<[u8; 3]>,
    /// Linear coverage `code/255` per texel, if the image has it.
    alpha: Option<Vec<u8>>,
    wrap: [Wrap; 2],
    mean: Rgb,
    mean_alpha: f32,
}

/// The linear value of each 8-bit sRGB code.
fn decode(code: u8) -> f32 {
    static TABLE: OnceLock<[f32; 256]> = OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|c| srgb_to_linear(c as f32 / 255.0)))[code as usize]
}

impl Texture {
    /// A texture of `width × height` sRGB texels with wrap modes
    /// `[u, v]`; an error if the sizes disagree or it is empty.
    pub fn new(
        width: u32,
        height: u32,
        texels: Vec<[u8; 3]>,
        wrap: [Wrap; 2],
    ) -> Result<Self, String> {
        if width == 0 || height == 0 || texels.len() as u64 != u64::from(width) * u64::from(height)
        {
            return Err(format!(
                "a {width}×{height} texture needs {} texels, got {}",
                u64::from(width) * u64::from(height),
                texels.len()
            ));
        }
        let mut sum = [0.0f64; 3];
        for texel in &texels {
            for (s, &c) in sum.iter_mut().zip(texel) {
                *s += f64::from(decode(c));
            }
        }
        let n = texels.len() as f64;
        let mean = Rgb::new(
            (sum[0] / n) as f32,
            (sum[1] / n) as f32,
            (sum[2] / n) as f32,
        );
        Ok(Self {
            width,
            height,
            texels,
            alpha: None,
            wrap,
            mean,
            mean_alpha: 1.0,
        })
    }

    /// The texture with an alpha channel: one linear 8-bit coverage code
    /// per texel, in the texels' order; an error if the count differs.
    pub fn with_alpha(mut self, alpha: Vec<u8>) -> Result<Self, String> {
        if alpha.len() != self.texels.len() {
            return Err(format!(
                "a {}×{} texture needs {} alpha values, got {}",
                self.width,
                self.height,
                self.texels.len(),
                alpha.len()
            ));
        }
        let sum: u64 = alpha.iter().map(|&a| u64::from(a)).sum();
        self.mean_alpha = (sum as f64 / (255.0 * alpha.len() as f64)) as f32;
        self.alpha = Some(alpha);
        Ok(self)
    }

    /// The mean coverage of all texels (1 without an alpha channel), for
    /// surfaces that have no texture coordinates.
    pub fn mean_alpha(&self) -> f32 {
        self.mean_alpha
    }

    /// Whether the image has an alpha channel.
    pub fn has_alpha(&self) -> bool {
        self.alpha.is_some()
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    /// The mean linear colour of all texels (for surfaces that have no
    /// texture coordinates).
    pub fn mean(&self) -> Rgb {
        self.mean
    }

    /// The linear colour of texel (`x`, `y`), wrapped.
    #[inline]
    fn texel(&self, x: i64, y: i64) -> Rgb {
        let [r, g, b] = self.texels[self.index(x, y)];
        Rgb::new(decode(r), decode(g), decode(b))
    }

    /// The linear colour at texture coordinates `uv`: the four nearest
    /// texel centres (at `(i + ½)/width`, `(j + ½)/height`) blended
    /// bilinearly after decoding. Non-finite coordinates give the mean.
    pub fn lookup(&self, uv: Vec2) -> Rgb {
        match self.bilinear(uv) {
            Some(corners) => corners
                .into_iter()
                .map(|(x, y, w)| self.texel(x, y) * w)
                .sum(),
            None => self.mean,
        }
    }

    /// The texels' codes read as data, not colour (`code/255` per channel,
    /// no sRGB decoding: a normal map's vectors), at texture coordinates
    /// `uv`, filtered as [`Texture::lookup`] filters colour; `None` at
    /// non-finite coordinates.
    pub fn lookup_data(&self, uv: Vec2) -> Option<Vec3> {
        let corners = self.bilinear(uv)?;
        Some(
            corners
                .into_iter()
                .map(|(x, y, w)| {
                    let [r, g, b] = self.texels[self.index(x, y)];
                    Vec3::new(f32::from(r), f32::from(g), f32::from(b)) * (w / 255.0)
                })
                .sum(),
        )
    }

    /// The coverage (alpha, in `[0, 1]`) at texture coordinates `uv`,
    /// filtered as [`Texture::lookup`] filters colour; 1 where the image
    /// has no alpha channel, and at non-finite coordinates.
    pub fn alpha(&self, uv: Vec2) -> f32 {
        let Some(alpha) = &self.alpha else {
            return 1.0;
        };
        match self.bilinear(uv) {
            Some(corners) => corners
                .into_iter()
                .map(|(x, y, w)| f32::from(alpha[self.index(x, y)]) / 255.0 * w)
                .sum(),
            None => 1.0,
        }
    }

    #[inline]
    fn bilinear(&self, uv: Vec2) -> Option<[(i64, i64, f32); 4]> {
        bilinear_corners(uv, self.width, self.height)
    }

    /// The position in the texel array of texel (`x`, `y`), wrapped.
    #[inline]
    fn index(&self, x: i64, y: i64) -> usize {
        let x = self.wrap[0].index(x, self.width);
        let y = self.wrap[1].index(y, self.height);
        y * self.width as usize + x
    }
}

/// The four texels of a `width × height` image nearest the image
/// coordinates `uv` (texel centres at `((i + ½)/width, (j + ½)/height)`;
/// unwrapped indices, for a [`Wrap`] to place) and their bilinear
/// weights, which sum to 1; `None` for non-finite `uv`.
#[inline]
pub(crate) fn bilinear_corners(uv: Vec2, width: u32, height: u32) -> Option<[(i64, i64, f32); 4]> {
    if !uv.is_finite() {
        return None;
    }
    // Far outside [0, 1] (beyond 2⁵² texels, where f64 holds no
    // fraction) the position is held there, so the texel indices stay
    // far from i64's limits.
    const FAR: f64 = 4_503_599_627_370_496.0;
    let x = (f64::from(uv.x) * f64::from(width) - 0.5).clamp(-FAR, FAR);
    let y = (f64::from(uv.y) * f64::from(height) - 0.5).clamp(-FAR, FAR);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
    let (x0, y0) = (x0 as i64, y0 as i64);
    Some([
        (x0, y0, (1.0 - fx) * (1.0 - fy)),
        (x0 + 1, y0, fx * (1.0 - fy)),
        (x0, y0 + 1, (1.0 - fx) * fy),
        (x0 + 1, y0 + 1, fx * fy),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2×2 checker of codes 0 and 255 (linear 0 and 1).
    fn checker(wrap: Wrap) -> Texture {
        let (k, w) = ([0u8; 3], [255u8; 3]);
        Texture::new(2, 2, vec![k, w, w, k], [wrap; 2]).unwrap()
    }

    /// At texel centres the texel's own decoded colour; halfway between
    /// two the mean of both; the sRGB code 128 decodes to 0.2158.
    #[test]
    fn bilinear_between_texel_centres() {
        let t = checker(Wrap::Clamp);
        assert_eq!(t.lookup(Vec2::new(0.25, 0.25)), Rgb::ZERO);
        assert_eq!(t.lookup(Vec2::new(0.75, 0.25)), Rgb::ONE);
        assert!(
            (t.lookup(Vec2::new(0.5, 0.25)) - Rgb::splat(0.5))
                .abs()
                .max_element()
                < 1e-6
        );
        assert!((t.mean() - Rgb::splat(0.5)).abs().max_element() < 1e-6);
        let grey = Texture::new(1, 1, vec![[128; 3]], [Wrap::Repeat; 2]).unwrap();
        assert!((grey.lookup(Vec2::new(3.7, -2.2)).x - 0.215_861).abs() < 1e-5);
    }

    /// Repeat tiles, mirror reflects every other tile, clamp holds the
    /// edge texel.
    #[test]
    fn wrap_modes() {
        let u = Vec2::new(1.25, 0.25);
        assert_eq!(checker(Wrap::Repeat).lookup(u), Rgb::ZERO);
        assert_eq!(checker(Wrap::Mirror).lookup(u), Rgb::ONE);
        assert_eq!(checker(Wrap::Clamp).lookup(u), Rgb::ONE);
        assert_eq!(Wrap::Mirror.index(-1, 3), 0);
        assert_eq!(Wrap::Mirror.index(3, 3), 2);
        assert_eq!(Wrap::Repeat.index(-1, 3), 2);
        assert!(Texture::new(2, 2, vec![[0; 3]; 3], [Wrap::Repeat; 2]).is_err());
    }

    /// Alpha is linear (code 128 is 0.502, not sRGB's 0.216) and filtered
    /// as colour is; a 2×2 checker of coverage 1 and 0 is at least ½
    /// exactly on the quadrants of its own texels (clamped); without a
    /// channel, coverage is 1.
    #[test]
    fn alpha_is_linear_and_filtered_bilinearly() {
        let t = checker(Wrap::Clamp)
            .with_alpha(vec![255, 0, 0, 255])
            .unwrap();
        assert!(t.has_alpha());
        assert!((t.mean_alpha() - 0.5).abs() < 1e-6);
        assert_eq!(t.alpha(Vec2::new(0.25, 0.25)), 1.0);
        assert_eq!(t.alpha(Vec2::new(0.75, 0.25)), 0.0);
        assert!((t.alpha(Vec2::new(0.5, 0.3)) - 0.5).abs() < 1e-6);
        for (uv, solid) in [
            ((0.1, 0.2), true),
            ((0.45, 0.45), true),
            ((0.55, 0.45), false),
            ((0.9, 0.1), false),
            ((0.2, 0.8), false),
            ((0.55, 0.55), true),
        ] {
            let a = t.alpha(Vec2::new(uv.0, uv.1));
            assert_eq!(a >= 0.5, solid, "{uv:?}: {a}");
        }
        let half = Texture::new(1, 1, vec![[0; 3]], [Wrap::Repeat; 2])
            .unwrap()
            .with_alpha(vec![128])
            .unwrap();
        assert!((half.alpha(Vec2::new(0.3, 0.3)) - 128.0 / 255.0).abs() < 1e-6);
        assert_eq!(checker(Wrap::Clamp).alpha(Vec2::new(0.75, 0.25)), 1.0);
        assert!(checker(Wrap::Clamp).with_alpha(vec![0; 3]).is_err());
    }
}
