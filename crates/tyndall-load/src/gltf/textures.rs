//! glTF textures (glTF 2.0 §3.8): images decoded from PNG or JPEG, their
//! size checked from the header first, made into the scene's textures
//! with their samplers' wrap modes.

use super::GltfLoader;
use crate::source::SceneError;
use ::gltf::image::Format;
use ::gltf::texture::WrappingMode;
use std::sync::Arc;
use tyndall::color::Rgb;
use tyndall::description::SceneDesc;
use tyndall::texture::{Encoding, Texture, TextureId, Wrap};

/// Most texels a texture may have (a 16384² image): larger ones are
/// refused rather than decoded (the size is read from the image's header
/// first).
pub const MAX_TEXELS: u64 = 1 << 28;

/// Most texels decoded from one glTF file's images altogether (an image
/// used with two samplers counts twice), so that many textures naming one
/// large image cannot multiply it.
pub const MAX_DECODED_TEXELS: u64 = 1 << 28;

impl GltfLoader<'_> {
    /// The scene's texture for a glTF texture (its image, 8-bit codes of
    /// `encoding` — sRGB for colour, linear for data — with its sampler's
    /// wrap modes and its MIP pyramid; added on first use) and its mean
    /// linear value. Sixteen-bit images keep their high bytes; one and
    /// two channels are grey; the alpha of two- and four-channel images
    /// is kept as linear coverage.
    pub(super) fn texture(
        &mut self,
        element: &str,
        texture: &::gltf::Texture,
        encoding: Encoding,
        scene: &mut SceneDesc,
    ) -> Result<(TextureId, Rgb), SceneError> {
        let index = texture.source().index();
        let key = (index, texture.sampler().index(), encoding);
        if let Some(&id) = self.textures.get(&key) {
            return Ok((id, scene.textures[id as usize].value.mean()));
        }
        let image = &self.decode_image(element, &texture.source())?;
        let (channels, bytes) = match image.format {
            Format::R8 => (1, 1),
            Format::R8G8 => (2, 1),
            Format::R8G8B8 => (3, 1),
            Format::R8G8B8A8 => (4, 1),
            Format::R16 => (1, 2),
            Format::R16G16 => (2, 2),
            Format::R16G16B16 => (3, 2),
            Format::R16G16B16A16 => (4, 2),
            other => {
                return Err(self.err(
                    element,
                    format!(
                        "images[{index}]: pixel format {other:?} is not supported for a base colour"
                    ),
                ));
            }
        };
        let stride = channels * bytes;
        if image.pixels.len() as u64
            != u64::from(image.width) * u64::from(image.height) * stride as u64
        {
            return Err(self.err(
                element,
                format!("images[{index}]: the decoded image has the wrong size"),
            ));
        }
        // The high byte of channel `c` of `pixel` (16-bit channels are
        // stored native-endian by the gltf crate).
        let channel = |pixel: &[u8], c: usize| -> u8 {
            let c = c.min(channels - 1);
            if bytes == 1 {
                pixel[c]
            } else {
                (u16::from_ne_bytes([pixel[2 * c], pixel[2 * c + 1]]) >> 8) as u8
            }
        };
        // Grey + alpha or RGBA: the last channel is linear coverage.
        let alpha: Option<Vec<u8>> = matches!(channels, 2 | 4).then(|| {
            image
                .pixels
                .chunks_exact(stride)
                .map(|pixel| channel(pixel, channels - 1))
                .collect()
        });
        let texels = image
            .pixels
            .chunks_exact(stride)
            .map(|pixel| {
                if channels <= 2 {
                    [channel(pixel, 0); 3]
                } else {
                    [channel(pixel, 0), channel(pixel, 1), channel(pixel, 2)]
                }
            })
            .collect();
        let sampler = texture.sampler();
        let wrap = |mode: WrappingMode| match mode {
            WrappingMode::Repeat => Wrap::Repeat,
            WrappingMode::ClampToEdge => Wrap::Clamp,
            WrappingMode::MirroredRepeat => Wrap::Mirror,
        };
        let made = Texture::encoded(
            image.width,
            image.height,
            texels,
            [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())],
            encoding,
        )
        .and_then(|t| match alpha {
            Some(alpha) => t.with_alpha(alpha),
            None => Ok(t),
        })
        .map_err(|m| self.err(element, format!("images[{index}]: {m}")))?;
        let mean = made.mean();
        let id = scene.add_texture(Arc::new(made), self.origin(format!("images[{index}]")));
        self.textures.insert(key, id);
        Ok((id, mean))
    }
}

impl GltfLoader<'_> {
    /// Decodes image `image` (glTF 2.0 §3.8.3: PNG or JPEG, from a buffer
    /// view or a `uri`), refusing one over [`MAX_TEXELS`] texels, or past
    /// [`MAX_DECODED_TEXELS`] with those decoded before, from its header
    /// before any pixel is decoded.
    fn decode_image(
        &mut self,
        element: &str,
        image: &::gltf::Image,
    ) -> Result<::gltf::image::Data, SceneError> {
        use ::gltf::image::Source;
        use image::{DynamicImage, ImageFormat};
        use std::borrow::Cow;
        let at = format!("images[{}]", image.index());
        let fail = |m: String| self.err(element, format!("{at}: {m}"));
        let (bytes, mime, file): (Cow<[u8]>, Option<&str>, Option<String>) = match image.source() {
            Source::View { view, mime_type } => {
                let data = self
                    .buffers
                    .get(view.buffer().index())
                    .and_then(|d| {
                        d.0.get(view.offset()..view.offset().checked_add(view.length())?)
                    })
                    .ok_or_else(|| fail("its bufferView lies outside its buffer".into()))?;
                (Cow::Borrowed(data), Some(mime_type), None)
            }
            Source::Uri { uri, mime_type } => {
                let (bytes, file) =
                    super::sources::read_image(uri, self.base, super::MAX_IMAGE_FILE_BYTES)
                        .map_err(fail)?;
                (Cow::Owned(bytes), mime_type, file)
            }
        };
        let extension = file
            .as_deref()
            .and_then(|f| f.rsplit('.').next())
            .map(str::to_ascii_lowercase);
        let format = match (mime, extension.as_deref()) {
            (Some("image/png"), _) | (None, Some("png")) => ImageFormat::Png,
            (Some("image/jpeg"), _) | (None, Some("jpg" | "jpeg")) => ImageFormat::Jpeg,
            _ => match image::guess_format(&bytes) {
                Ok(f @ (ImageFormat::Png | ImageFormat::Jpeg)) => f,
                _ => {
                    return Err(fail(format!(
                        "the image is not PNG or JPEG (mimeType {})",
                        mime.unwrap_or("not given")
                    )));
                }
            },
        };
        let decoded_before = self.decoded_texels;
        let decoded = crate::images::decode_checked(&bytes, format, |width, height| {
            let texels = u64::from(width) * u64::from(height);
            if texels > MAX_TEXELS {
                return Err(format!(
                    "the image is {width}×{height}: at most {MAX_TEXELS} texels are supported"
                ));
            }
            if decoded_before + texels > MAX_DECODED_TEXELS {
                return Err(format!(
                    "the file's images add up to more than {MAX_DECODED_TEXELS} texels"
                ));
            }
            Ok(())
        })
        .map_err(fail)?;
        let texels = u64::from(decoded.width()) * u64::from(decoded.height());
        drop(bytes);
        let format = match &decoded {
            DynamicImage::ImageLuma8(_) => Format::R8,
            DynamicImage::ImageLumaA8(_) => Format::R8G8,
            DynamicImage::ImageRgb8(_) => Format::R8G8B8,
            DynamicImage::ImageRgba8(_) => Format::R8G8B8A8,
            DynamicImage::ImageLuma16(_) => Format::R16,
            DynamicImage::ImageLumaA16(_) => Format::R16G16,
            DynamicImage::ImageRgb16(_) => Format::R16G16B16,
            DynamicImage::ImageRgba16(_) => Format::R16G16B16A16,
            _ => {
                return Err(self.err(
                    element,
                    format!("{at}: the image's pixel format is not supported for a base colour"),
                ));
            }
        };
        self.decoded_texels += texels;
        Ok(::gltf::image::Data {
            width: decoded.width(),
            height: decoded.height(),
            pixels: decoded.into_bytes(),
            format,
        })
    }
}
