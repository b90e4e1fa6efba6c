//! Textures: an 8-bit image looked up at texture coordinates with
//! bilinear filtering, as glTF's textures are (glTF 2.0 §3.8: texel
//! centres at half-integers, the sampler's wrap modes), from a pyramid of
//! averaged levels (a MIP map, Williams 1983, "Pyramidal parametrics")
//! where a footprint spans many texels: trilinear filtering between the
//! two levels whose texels are nearest the footprint's size.
//!
//! A colour texture's codes are sRGB-encoded (glTF: base colour and
//! emissive textures) and are decoded through a 256-entry table when
//! looked up, and blended in linear RGB; a data texture's are linear
//! (normal, metallic-roughness maps). Texels stay 8-bit, three bytes
//! each, in every level: a 4096² texture takes 64 MiB with its pyramid
//! instead of 256 MiB of linear floats. An image's alpha channel, if it
//! has one, is kept as a fourth byte per texel of the full-resolution
//! level for the surface's coverage (glTF `alphaMode`, §3.9.4: alpha is
//! linear coverage, not sRGB; [`crate::coverage`]), looked up with
//! bilinear filtering: coverage decides per ray where a surface is, and
//! the rays' own spread averages it.

use crate::color::{Rgb, linear_to_srgb, srgb_to_linear};
use glam::{Vec2, Vec3};
use std::hash::Hasher;
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

/// How a texture's 8-bit codes encode its values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Encoding {
    /// Colour, by the sRGB transfer function (glTF's base colour and
    /// emissive textures).
    #[default]
    Srgb,
    /// Data, `code/255` (glTF's normal and metallic-roughness textures).
    Linear,
}

/// One level of a texture's pyramid: `width × height` texels, row by row
/// from the top.
#[derive(Clone, Debug, PartialEq)]
struct Level {
    width: u32,
    height: u32,
    texels: Vec<[u8; 3]>,
}

/// An 8-bit image of `width × height` texels, row by row from the top
/// (texture coordinate v = 0 is the first row, as in glTF), with its
/// pyramid of averaged levels.
#[derive(Clone, PartialEq)]
pub struct Texture {
    /// The image, then each level half the last's size (rounded down,
    /// at least 1) down to 1 × 1.
    levels: Vec<Level>,
    encoding: Encoding,
    /// Linear coverage `code/255` per texel of the image, if it has it.
    alpha: Option<Vec<u8>>,
    wrap: [Wrap; 2],
    mean: Rgb,
    mean_alpha: f32,
    /// [`content_digest`] of the image's texels and alpha, for the
    /// `Debug` form: a rig's heads share one image and print it once each.
    digest: u64,
}

/// A summary, not the texels (render parts and checkpoints hash a scene
/// through its `Debug` form, `parts::scene_hash`, and a material holding
/// a 4096² image would print 50 million numbers into each hash): the
/// size, encoding and wrap modes, and the image's [`content_digest`].
/// The pyramid and means follow from those.
impl std::fmt::Debug for Texture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Texture")
            .field("size", &(self.width(), self.height()))
            .field("encoding", &self.encoding)
            .field("wrap", &self.wrap)
            .field("alpha", &self.alpha.is_some())
            .field("digest", &format_args!("{:016x}", self.digest))
            .finish()
    }
}

/// A 64-bit digest (Fx hashing) of an image's texels and alpha codes in
/// order: every changed code changes it (with the odds of a 64-bit
/// hash), as the voxel grids' digests do for their values.
fn content_digest(texels: &[[u8; 3]], alpha: Option<&[u8]>) -> u64 {
    let mut h = rustc_hash::FxHasher::default();
    h.write(texels.as_flattened());
    if let Some(alpha) = alpha {
        h.write(alpha);
    }
    h.finish()
}

/// The linear value of each 8-bit sRGB code.
fn decode(code: u8) -> f32 {
    static TABLE: OnceLock<[f32; 256]> = OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|c| srgb_to_linear(c as f32 / 255.0)))[code as usize]
}

impl Texture {
    /// A colour texture of `width × height` sRGB texels with wrap modes
    /// `[u, v]`; an error if the sizes disagree or it is empty.
    pub fn new(
        width: u32,
        height: u32,
        texels: Vec<[u8; 3]>,
        wrap: [Wrap; 2],
    ) -> Result<Self, String> {
        Self::encoded(width, height, texels, wrap, Encoding::Srgb)
    }

    /// A texture of `width × height` texels of `encoding` with wrap modes
    /// `[u, v]`, and its pyramid; an error if the sizes disagree or it is
    /// empty.
    pub fn encoded(
        width: u32,
        height: u32,
        texels: Vec<[u8; 3]>,
        wrap: [Wrap; 2],
        encoding: Encoding,
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
                *s += f64::from(encoding.decode(c));
            }
        }
        let n = texels.len() as f64;
        let mean = Rgb::new(
            (sum[0] / n) as f32,
            (sum[1] / n) as f32,
            (sum[2] / n) as f32,
        );
        let digest = content_digest(&texels, None);
        let mut levels = vec![Level {
            width,
            height,
            texels,
        }];
        while let Some(next) = levels.last().and_then(|l| l.halved(encoding)) {
            levels.push(next);
        }
        Ok(Self {
            levels,
            encoding,
            alpha: None,
            wrap,
            mean,
            mean_alpha: 1.0,
            digest,
        })
    }

    /// The texture with an alpha channel: one linear 8-bit coverage code
    /// per texel, in the texels' order; an error if the count differs.
    pub fn with_alpha(mut self, alpha: Vec<u8>) -> Result<Self, String> {
        let texels = self.levels[0].texels.len();
        if alpha.len() != texels {
            return Err(format!(
                "a {}×{} texture needs {texels} alpha values, got {}",
                self.width(),
                self.height(),
                alpha.len()
            ));
        }
        let sum: u64 = alpha.iter().map(|&a| u64::from(a)).sum();
        self.mean_alpha = (sum as f64 / (255.0 * alpha.len() as f64)) as f32;
        self.digest = content_digest(&self.levels[0].texels, Some(&alpha));
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
        self.levels[0].width
    }

    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    /// How the texels' codes encode the texture's values.
    pub fn encoding(&self) -> Encoding {
        self.encoding
    }

    /// How many levels the pyramid has, the image included.
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// The mean linear colour of all texels (for surfaces that have no
    /// texture coordinates).
    pub fn mean(&self) -> Rgb {
        self.mean
    }

    /// The value at texture coordinates `uv` (decoded by the texture's
    /// encoding): the four nearest texel centres of the image (at
    /// `(i + ½)/width`, `(j + ½)/height`) blended bilinearly after
    /// decoding. Non-finite coordinates give the mean.
    pub fn lookup(&self, uv: Vec2) -> Rgb {
        self.filtered(uv, f32::NEG_INFINITY).unwrap_or(self.mean)
    }

    /// The value at texture coordinates `uv` over a footprint of level of
    /// detail `lod`: log₂ of its width in texels of the image. Up to 0
    /// the image itself, as [`Texture::lookup`]; beyond, trilinear
    /// filtering: the levels ⌊lod⌋ and ⌊lod⌋ + 1, each bilinear, blended
    /// by lod's fraction, up to the 1 × 1 level. Non-finite coordinates
    /// give the mean.
    pub fn lookup_lod(&self, uv: Vec2, lod: f32) -> Rgb {
        self.filtered(uv, lod).unwrap_or(self.mean)
    }

    /// The texels' codes read as data, not colour (`code/255` per channel,
    /// no sRGB decoding: a normal map's vectors), at texture coordinates
    /// `uv` over a footprint of level of detail `lod`, filtered as
    /// [`Texture::lookup_lod`] filters; `None` at non-finite coordinates.
    pub fn lookup_data(&self, uv: Vec2, lod: f32) -> Option<Vec3> {
        let codes = |level: &Level, x: i64, y: i64| {
            let [r, g, b] = level.texels[self.index(level, x, y)];
            Vec3::new(f32::from(r), f32::from(g), f32::from(b)) / 255.0
        };
        self.trilinear(uv, lod, codes)
    }

    /// [`Texture::lookup_lod`] with `None` at non-finite coordinates.
    #[inline]
    fn filtered(&self, uv: Vec2, lod: f32) -> Option<Rgb> {
        let decoded = |level: &Level, x: i64, y: i64| {
            let [r, g, b] = level.texels[self.index(level, x, y)];
            let e = self.encoding;
            Rgb::new(e.decode(r), e.decode(g), e.decode(b))
        };
        self.trilinear(uv, lod, decoded)
    }

    /// The values `texel` gives, filtered bilinearly at `uv` in the level
    /// of detail `lod` (trilinearly between levels; the image up to 0).
    #[inline]
    fn trilinear(
        &self,
        uv: Vec2,
        lod: f32,
        texel: impl Fn(&Level, i64, i64) -> Vec3,
    ) -> Option<Vec3> {
        let bilinear = |level: &Level| -> Option<Vec3> {
            let corners = bilinear_corners(uv, level.width, level.height)?;
            Some(
                corners
                    .into_iter()
                    .map(|(x, y, w)| texel(level, x, y) * w)
                    .sum(),
            )
        };
        let last = (self.levels.len() - 1) as f32;
        // Not above 0 (NaN included): the image.
        if lod.is_nan() || lod <= 0.0 {
            return bilinear(&self.levels[0]);
        }
        let lod = lod.min(last);
        let below = lod.floor();
        let fraction = lod - below;
        let fine = bilinear(&self.levels[below as usize])?;
        if fraction == 0.0 {
            return Some(fine);
        }
        let coarse = bilinear(&self.levels[below as usize + 1])?;
        Some(fine + (coarse - fine) * fraction)
    }

    /// The coverage (alpha, in `[0, 1]`) at texture coordinates `uv`,
    /// filtered bilinearly in the image as [`Texture::lookup`] filters
    /// colour; 1 where the image has no alpha channel, and at non-finite
    /// coordinates.
    pub fn alpha(&self, uv: Vec2) -> f32 {
        let Some(alpha) = &self.alpha else {
            return 1.0;
        };
        let image = &self.levels[0];
        match bilinear_corners(uv, image.width, image.height) {
            Some(corners) => corners
                .into_iter()
                .map(|(x, y, w)| f32::from(alpha[self.index(image, x, y)]) / 255.0 * w)
                .sum(),
            None => 1.0,
        }
    }

    /// The position in `level`'s texel array of its texel (`x`, `y`),
    /// wrapped.
    #[inline]
    fn index(&self, level: &Level, x: i64, y: i64) -> usize {
        let x = self.wrap[0].index(x, level.width);
        let y = self.wrap[1].index(y, level.height);
        y * level.width as usize + x
    }
}

impl Encoding {
    /// The value of code `code`.
    #[inline]
    pub fn decode(self, code: u8) -> f32 {
        match self {
            Encoding::Srgb => decode(code),
            Encoding::Linear => f32::from(code) / 255.0,
        }
    }

    /// The nearest code of value `value` (clamped to `[0, 1]`).
    fn encode(self, value: f32) -> u8 {
        let v = value.clamp(0.0, 1.0);
        let code = match self {
            Encoding::Srgb => linear_to_srgb(v),
            Encoding::Linear => v,
        };
        (code * 255.0).round() as u8
    }
}

impl Level {
    /// The next level of the pyramid, half the size along each side
    /// (rounded down, at least 1), each of its texels the mean of the
    /// image area it covers — whole texels and the shares of those cut
    /// by its edge where a side is odd (a box filter, so the level's mean
    /// is this one's) — in the encoding's linear values; `None` for
    /// 1 × 1.
    fn halved(&self, encoding: Encoding) -> Option<Level> {
        if self.width == 1 && self.height == 1 {
            return None;
        }
        let (width, height) = ((self.width / 2).max(1), (self.height / 2).max(1));
        let across = box_weights(self.width, width);
        let down = box_weights(self.height, height);
        let linear: Vec<Vec3> = self
            .texels
            .iter()
            .map(|t| Vec3::from_array(t.map(|c| encoding.decode(c))))
            .collect();
        // Rows first, then columns: the box filter is separable.
        let mut rows = vec![Vec3::ZERO; width as usize * self.height as usize];
        for y in 0..self.height as usize {
            for (x, weights) in across.iter().enumerate() {
                rows[y * width as usize + x] = weights
                    .iter()
                    .map(|&(i, w)| linear[y * self.width as usize + i] * w)
                    .sum();
            }
        }
        let mut texels = Vec::with_capacity(width as usize * height as usize);
        for weights in &down {
            for x in 0..width as usize {
                let v: Vec3 = weights
                    .iter()
                    .map(|&(j, w)| rows[j * width as usize + x] * w)
                    .sum();
                texels.push(v.to_array().map(|c| encoding.encode(c)));
            }
        }
        Some(Level {
            width,
            height,
            texels,
        })
    }
}

/// For each of `to` texels along a side that had `from`, the texels of
/// `from` it covers and the share of its width each takes (a box filter:
/// texel i of `to` covers `[i, i + 1)·from/to`; the shares sum to 1).
fn box_weights(from: u32, to: u32) -> Vec<Vec<(usize, f32)>> {
    let scale = f64::from(from) / f64::from(to);
    (0..to)
        .map(|i| {
            let (a, b) = (f64::from(i) * scale, f64::from(i + 1) * scale);
            let first = a.floor() as u32;
            let last = (b.ceil() as u32).min(from);
            (first..last)
                .map(|j| {
                    let overlap = b.min(f64::from(j + 1)) - a.max(f64::from(j));
                    (j as usize, (overlap / scale) as f32)
                })
                .filter(|&(_, w)| w > 0.0)
                .collect()
        })
        .collect()
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

    /// The pyramid of a 37 × 23 image: each level half the last (rounded
    /// down) to 1 × 1, each the box-filtered image, so every level's mean
    /// is the image's — in linear values, up to the 8-bit rounding of the
    /// levels made so far (half a code a level, through the sRGB decode's
    /// steepest slope, 2.3, for colour).
    #[test]
    fn pyramid_levels_keep_the_mean() {
        let texels: Vec<[u8; 3]> = (0..37 * 23)
            .map(|i: u32| {
                [
                    (i * 37 % 256) as u8,
                    (i * 101 % 256) as u8,
                    (i * i % 251) as u8,
                ]
            })
            .collect();
        for encoding in [Encoding::Srgb, Encoding::Linear] {
            let t = Texture::encoded(37, 23, texels.clone(), [Wrap::Clamp; 2], encoding).unwrap();
            let sizes: Vec<(u32, u32)> = t.levels.iter().map(|l| (l.width, l.height)).collect();
            assert_eq!(sizes, [(37, 23), (18, 11), (9, 5), (4, 2), (2, 1), (1, 1)]);
            assert_eq!(t.levels(), 6);
            let step = match encoding {
                Encoding::Srgb => 2.3 * 0.5 / 255.0,
                Encoding::Linear => 0.5 / 255.0,
            };
            for (k, level) in t.levels.iter().enumerate() {
                let n = level.texels.len() as f32;
                let mean = level
                    .texels
                    .iter()
                    .map(|c| Vec3::from_array(c.map(|v| encoding.decode(v))))
                    .sum::<Vec3>()
                    / n;
                let error = (mean - t.mean()).abs().max_element();
                assert!(
                    error <= step * k as f32 + 1e-5,
                    "{encoding:?} level {k}: {mean} vs {}",
                    t.mean()
                );
            }
        }
        for (from, to) in [(37, 18), (5, 2), (4, 2), (2, 1)] {
            for weights in box_weights(from, to) {
                let sum: f32 = weights.iter().map(|&(_, w)| w).sum();
                assert!((sum - 1.0).abs() < 1e-6, "{from} → {to}: {weights:?}");
            }
        }
    }

    /// Trilinear filtering: at a level of detail up to 0 the image as
    /// [`Texture::lookup`] filters it; at 1 (a footprint of two texels)
    /// the 2 × 2 checker's 1 × 1 level, its mean (to 8 bits), everywhere;
    /// halfway, the
    /// two blended; beyond the last level, the last.
    #[test]
    fn levels_of_detail_blend_levels() {
        let t = checker(Wrap::Repeat);
        let white = Vec2::new(0.75, 0.25);
        assert_eq!(t.lookup_lod(white, f32::NEG_INFINITY), t.lookup(white));
        assert_eq!(t.lookup_lod(white, 0.0), Rgb::ONE);
        // The mean, linear 0.5, is sRGB code 188 (0.7354 · 255 = 187.5,
        // rounded up): 0.5029 decoded.
        let half = decode(188);
        for lod in [1.0, 1.7, 40.0] {
            assert!(
                (t.lookup_lod(white, lod) - Rgb::splat(half))
                    .abs()
                    .max_element()
                    < 1e-6
            );
        }
        let blended = t.lookup_lod(white, 0.5).x;
        assert!((blended - (1.0 + half) / 2.0).abs() < 1e-6, "{blended}");
        let data = t.lookup_data(white, 0.5).unwrap();
        assert!(
            (data.x - (1.0 + 188.0 / 255.0) / 2.0).abs() < 1e-6,
            "{data}"
        );
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
