//! The two image file formats and their encodings.
//!
//! PNG is display-referred: radiance is scaled by `2^exposure`, clamped to
//! [0, 1] and sRGB-encoded to 8 bits. OpenEXR is scene-referred: linear
//! float radiance, unscaled (docs/physics.md §1.3). The file ending
//! chooses the format.

use std::io::{Seek, Write};
use std::path::{Path, PathBuf};
use tyndall::Image;
use tyndall::Rgb;
use tyndall::aov::Aov;
use tyndall::color::linear_to_srgb;

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

/// Image file formats, chosen by the file ending.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// `.png`: display-referred 8-bit sRGB.
    Png,
    /// `.exr`: scene-referred linear f32 radiance.
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
    /// The format the file name's ending (`.png` or `.exr`, any case) names.
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

/// 8-bit sRGB bytes (RGB, row-major) of `image` after `2^exposure`
/// scaling and clamping to [0, 1]: what a PNG holds.
pub fn to_srgb8(image: &Image, exposure: f32) -> Vec<u8> {
    let scale = exposure.exp2();
    image
        .pixels()
        .iter()
        .flat_map(|p| (*p * scale).to_array())
        .map(|v| (linear_to_srgb(v.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8)
        .collect()
}

/// An image written beside the radiance as channels `{name}.{channel}`
/// of an OpenEXR file (the convention compositors read as a layer named
/// `name`): an AOV.
#[derive(Clone, Copy)]
pub struct AovLayer<'a> {
    pub name: &'a str,
    /// One name per channel written, taken from the image's first channels.
    pub channels: &'a [&'a str],
    pub image: &'a Image,
}

impl<'a> AovLayer<'a> {
    /// The layer of `aov`, whose image is `image`: `albedo.{R,G,B}`,
    /// `normal.{X,Y,Z}`, `depth.Z`, `position.{X,Y,Z}` and, for a
    /// radiance component, `{name}.{R,G,B}` (`direct.R`, ...). A light
    /// group's layer is [`AovLayer::radiance`]'s.
    pub fn new(aov: Aov, image: &'a Image) -> Self {
        let channels: &[&str] = match aov {
            Aov::Albedo | Aov::Component(_) | Aov::LightGroups => &["R", "G", "B"],
            Aov::Normal | Aov::Position => &["X", "Y", "Z"],
            Aov::Depth => &["Z"],
        };
        AovLayer {
            name: aov.name(),
            channels,
            image,
        }
    }
}

impl<'a> AovLayer<'a> {
    /// A radiance layer `{name}.{R,G,B}`: a light group's
    /// (`light_group.key.R`, ...).
    pub fn radiance(name: &'a str, image: &'a Image) -> Self {
        AovLayer {
            name,
            channels: &["R", "G", "B"],
            image,
        }
    }
}

/// Encodes `image`, and the layers `aovs` (OpenEXR only), into `out` in
/// `format`; `exposure` (stops) applies to PNG only.
pub(crate) fn encode(
    image: &Image,
    aovs: &[AovLayer],
    format: ImageFormat,
    exposure: f32,
    out: &mut (impl Write + Seek),
) -> Result<(), String> {
    if !aovs.is_empty() {
        if format != ImageFormat::Exr {
            return Err(
                "AOVs are written as OpenEXR layers: the output must be an .exr file".into(),
            );
        }
        return encode_exr_layers(image, aovs, out);
    }
    match format {
        ImageFormat::Png => {
            use image::ImageEncoder;
            image::codecs::png::PngEncoder::new(&mut *out)
                .write_image(
                    &to_srgb8(image, exposure),
                    image.width(),
                    image.height(),
                    image::ExtendedColorType::Rgb8,
                )
                .map_err(|e| e.to_string())
        }
        ImageFormat::Exr => {
            use exr::prelude::*;
            let (width, pixels) = (image.width() as usize, image.pixels());
            let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
                let p: Rgb = pixels[y * width + x];
                (p.x, p.y, p.z)
            });
            let size = (width, image.height() as usize);
            let layer = Layer::new(size, LayerAttributes::default(), EXR_ENCODING, channels);
            exr::prelude::Image::from_layer(layer)
                .write()
                .to_buffered(&mut *out)
                .map_err(|e| e.to_string())
        }
    }
}

/// Writes `image` as the `R`, `G`, `B` channels of one OpenEXR layer and
/// each of `aovs` as its named channels beside them.
fn encode_exr_layers(
    image: &Image,
    aovs: &[AovLayer],
    out: &mut (impl Write + Seek),
) -> Result<(), String> {
    use exr::prelude::*;
    let size = (image.width() as usize, image.height() as usize);
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    let mut push = |name: String, image: &tyndall::Image, c: usize| {
        let values = image.pixels().iter().map(|p| p[c]).collect();
        channels.push(AnyChannel::new(name.as_str(), FlatSamples::F32(values)));
    };
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        push(name.to_string(), image, c);
    }
    for aov in aovs {
        if (aov.image.width(), aov.image.height()) != (image.width(), image.height()) {
            return Err(format!("the {} AOV is not the image's size", aov.name));
        }
        for (c, channel) in aov.channels.iter().enumerate().take(3) {
            push(format!("{}.{channel}", aov.name), aov.image, c);
        }
    }
    let layer = Layer::new(
        size,
        LayerAttributes::default(),
        EXR_ENCODING,
        AnyChannels::sort(channels),
    );
    exr::prelude::Image::from_layer(layer)
        .write()
        .to_buffered(&mut *out)
        .map_err(|e| e.to_string())
}

/// Reads the first RGB(A) layer of an OpenEXR file as linear radiance.
pub fn read_exr(path: &Path) -> Result<Image, ImageError> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| {
            (
                resolution.width(),
                vec![Rgb::ZERO; resolution.width() * resolution.height()],
            )
        },
        |(width, pixels): &mut (usize, Vec<Rgb>), position, (r, g, b, _a): (f32, f32, f32, f32)| {
            pixels[position.y() * *width + position.x()] = Rgb::new(r, g, b);
        },
    )
    .map_err(|e| ImageError::Io {
        path: path.to_owned(),
        message: e.to_string(),
    })?;
    let size = image.layer_data.size;
    let (_, pixels) = image.layer_data.channel_data.pixels;
    Ok(tyndall::Image::from_pixels(
        size.width() as u32,
        size.height() as u32,
        pixels,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::BufWriter;

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
        let written = encode(&image, &[], ImageFormat::Png, 0.0, &mut out)
            .and_then(|()| out.flush().map_err(|e| e.to_string()));
        assert!(written.is_err());
    }
}
