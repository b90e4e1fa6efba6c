//! Image files a scene names directly (a spot's `gobo`): PNG or JPEG,
//! decoded to 8-bit sRGB texels with their size checked from the header
//! before any pixel is decoded.

use std::path::Path;
use tyndall::texture::{Texture, Wrap};

/// Most texels an image file may hold (as glTF images, 2²⁸).
pub const MAX_IMAGE_TEXELS: u64 = 1 << 28;

/// Reads the PNG or JPEG at `path` as a texture (8-bit sRGB; 16-bit
/// channels rounded to 8 bits, grey images become grey RGB, alpha is
/// dropped), coordinates clamped at its edges. Errors name the file.
pub fn load_texture(path: &Path) -> Result<Texture, String> {
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
    Texture::new(width, height, texels, [Wrap::Clamp, Wrap::Clamp]).map_err(fail)
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
