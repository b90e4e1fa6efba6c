//! Image files a scene names directly: a spot's `gobo` and a principled
//! material's `base_color_texture` (PNG or JPEG, decoded to 8-bit sRGB
//! texels) and an environment's `map` (OpenEXR or
//! Radiance HDR, linear radiance), each with its size checked from the
//! header before any pixel is decoded.

use std::path::Path;
use tyndall::color::Rgb;
use tyndall::lights::EnvironmentMap;
use tyndall::texture::{Texture, Wrap};

/// Most texels an image file may hold (as glTF images, 2²⁸).
pub const MAX_IMAGE_TEXELS: u64 = 1 << 28;

/// Most texels an environment map may hold: 2²⁷, a 16384 × 8192 sky, the
/// largest HDRIs published. A texel takes 20 bytes in memory (its radiance
/// and its sampling weights), so this is 2.7 GB at most.
pub const MAX_ENVIRONMENT_TEXELS: u64 = 1 << 27;

/// Reads the PNG or JPEG at `path` as a texture (8-bit sRGB; 16-bit
/// channels rounded to 8 bits, grey images become grey RGB, alpha is
/// dropped), coordinates beyond its edges treated by `wrap` (u, v).
/// Errors name the file.
pub fn load_texture(path: &Path, wrap: [Wrap; 2]) -> Result<Texture, String> {
    let fail = |m: String| format!("{}: {m}", path.display());
    let bytes =
        crate::files::read_capped(path, crate::files::MAX_IMAGE_FILE_BYTES).map_err(fail)?;
    let format = match image::guess_format(&bytes) {
        Ok(f @ (image::ImageFormat::Png | image::ImageFormat::Jpeg)) => f,
        _ => return Err(fail("not a PNG or JPEG image".into())),
    };
    let rgb = decode_checked(&bytes, format, |width, height| {
        let texels = u64::from(width) * u64::from(height);
        if texels > MAX_IMAGE_TEXELS {
            return Err(format!(
                "the image is {width}×{height}: at most {MAX_IMAGE_TEXELS} texels are supported"
            ));
        }
        Ok(())
    })
    .map_err(fail)?
    .into_rgb8();
    let (width, height) = rgb.dimensions();
    let texels = rgb.pixels().map(|p| p.0).collect();
    Texture::new(width, height, texels, wrap).map_err(fail)
}

/// Decodes `bytes` as an image of `format`, its size read from the header
/// first for `check(width, height)` to refuse before any pixel is decoded,
/// the decoder's allocations then limited to what that size needs (16-bit
/// RGBA and the decoder's own buffers).
pub(crate) fn decode_checked(
    bytes: &[u8],
    format: image::ImageFormat,
    check: impl FnOnce(u32, u32) -> Result<(), String>,
) -> Result<image::DynamicImage, String> {
    let reader = || image::ImageReader::with_format(std::io::Cursor::new(bytes), format);
    let (width, height) = reader()
        .into_dimensions()
        .map_err(|e| format!("cannot read the image: {e}"))?;
    check(width, height)?;
    let mut decoder = reader();
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(u64::from(width) * u64::from(height) * 8 + (64 << 20));
    decoder.limits(limits);
    decoder
        .decode()
        .map_err(|e| format!("cannot decode the image: {e}"))
}

/// Reads the equirectangular environment map at `path`: an OpenEXR file
/// (its first layer's R, G and B, any precision) or a Radiance HDR
/// (`.hdr`, RGBE), linear radiance, the top row looking up (see
/// [`tyndall::lights::environment`]). Errors name the file: one that is
/// neither, too many texels, a texel that is negative or not finite.
pub fn load_environment_map(path: &Path) -> Result<EnvironmentMap, String> {
    let fail = |m: String| format!("{}: {m}", path.display());
    let bytes =
        crate::files::read_capped(path, crate::files::MAX_IMAGE_FILE_BYTES).map_err(fail)?;
    let check = |width: usize, height: usize| {
        let texels = width as u64 * height as u64;
        if texels > MAX_ENVIRONMENT_TEXELS {
            return Err(format!(
                "the map is {width}×{height}: at most {MAX_ENVIRONMENT_TEXELS} texels \
                 (16384 × 8192) are supported"
            ));
        }
        Ok(())
    };
    let (width, height, texels) = if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
        read_exr_rgb(&bytes, check).map_err(fail)?
    } else if bytes.starts_with(b"#?") {
        let image = decode_checked(&bytes, image::ImageFormat::Hdr, |w, h| {
            check(w as usize, h as usize)
        })
        .map_err(fail)?
        .into_rgb32f();
        let (w, h) = image.dimensions();
        let texels = image.pixels().map(|p| Rgb::from_array(p.0)).collect();
        (w as usize, h as usize, texels)
    } else {
        return Err(fail(
            "not an OpenEXR or Radiance HDR image (an environment map holds linear radiance)"
                .into(),
        ));
    };
    EnvironmentMap::new(width as u32, height as u32, texels).map_err(fail)
}

/// The R, G and B of the first layer of the OpenEXR file `bytes`, its
/// size passed to `check` before any texel storage is made.
fn read_exr_rgb(
    bytes: &[u8],
    check: impl Fn(usize, usize) -> Result<(), String>,
) -> Result<(usize, usize, Vec<Rgb>), String> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |resolution, _| {
                let (w, h) = (resolution.width(), resolution.height());
                // A refused size stores nothing; it is reported below.
                match check(w, h) {
                    Ok(()) => (w, vec![Rgb::ZERO; w * h]),
                    Err(_) => (0, Vec::new()),
                }
            },
            |(width, texels): &mut (usize, Vec<Rgb>), position, (r, g, b): (f32, f32, f32)| {
                if let Some(texel) = texels.get_mut(position.y() * *width + position.x()) {
                    *texel = Rgb::new(r, g, b);
                }
            },
        )
        .first_valid_layer()
        .all_attributes()
        .non_parallel()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| format!("cannot read the OpenEXR image: {e}"))?;
    let size = image.layer_data.size;
    check(size.width(), size.height())?;
    let (_, texels) = image.layer_data.channel_data.pixels;
    Ok((size.width(), size.height(), texels))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Radiance HDR written by the `image` crate reads back as its
    /// radiance (to RGBE's 8-bit mantissa), rows from the top; a file that
    /// is neither map format is refused naming it.
    #[test]
    fn radiance_hdr_maps_read_back() {
        let dir = std::env::temp_dir().join(format!("tyndall-hdr-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("sky.hdr");
        let texels: Vec<image::Rgb<f32>> = (0..8)
            .map(|i| image::Rgb([0.5 + i as f32, 2.0, 0.25]))
            .collect();
        let mut bytes = Vec::new();
        image::codecs::hdr::HdrEncoder::new(&mut bytes)
            .encode(&texels, 4, 2)
            .expect("encode");
        std::fs::write(&path, bytes).expect("write");
        let map = load_environment_map(&path).expect("map");
        assert_eq!((map.width(), map.height()), (4, 2));
        // Texel (1, 1), the second row's second, at its centre.
        let texel = map.lookup(glam::Vec2::new(1.5 / 4.0, 1.5 / 2.0));
        let expected = Rgb::new(5.5, 2.0, 0.25);
        assert!(
            (texel - expected).abs().max_element() < 0.02 * 5.5,
            "{texel}"
        );
        // A header claiming more texels than a map may hold is refused
        // before any pixel is read (the file has none).
        let huge = dir.join("huge.hdr");
        std::fs::write(
            &huge,
            "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8193 +X 16384\n",
        )
        .expect("write");
        let e = load_environment_map(&huge).unwrap_err();
        assert!(e.contains("huge.hdr") && e.contains("16384×8193"), "{e}");
        let text = dir.join("sky.txt");
        std::fs::write(&text, "not an image").expect("write");
        let e = load_environment_map(&text).unwrap_err();
        assert!(
            e.contains("sky.txt") && e.contains("OpenEXR or Radiance HDR"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).ok();
    }
}
