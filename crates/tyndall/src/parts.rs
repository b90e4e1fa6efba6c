//! Render parts on disk: OpenEXR files holding a tile, a sample range or a
//! checkpoint of a render, and merging them into the whole.
//!
//! A part file is an OpenEXR image in the full image's display window with
//! two layers:
//! - `part`, the part's pixel rectangle (its data window placed at the
//!   rectangle's origin): `R`, `G`, `B` (f32), the part's own image (the
//!   mean of the samples it holds; see [`Accumulation::resolve`]), and
//!   `sum.camera.{R,G,B}.{hi,lo}` (u32), the f64 per-pixel sums of the
//!   camera samples, each stored exactly as the high and low 32 bits of its
//!   IEEE-754 bit pattern (OpenEXR has no f64 channels; two f32s would
//!   round). Merging adds these exact sums, so merged sample ranges differ
//!   from the single render only by the f64 rounding of the additions,
//!   and merged tiles not at all. Its text attribute `tyndall` records what
//!   the part holds, one `key value` per line: `tyndall-part 1` (the
//!   format), `scene-hash` (see [`scene_hash`]), `image W H`,
//!   `rect x0 y0 x1 y1` (pixels `[x0, x1) × [y0, y1)`), `samples A B`
//!   (sample indices `A..B`), `seed`, `light-paths 0|1`;
//! - `light`, only for renders that trace light paths: the whole image,
//!   `sum.light.{R,G,B}.{0,1,2,3}` (u32), the exact fixed-point sums
//!   ([`ExactRgb`]) of the splats of the part's share of the light paths,
//!   each i128 as four 32-bit words, least significant first.
//!
//! Files are written atomically: to a temporary file in the same folder,
//! synced, then renamed over the target, so a reader (or a render killed
//! mid-write) never sees a partial file.

use crate::camera::CameraSpec;
use crate::exact_sum::ExactRgb;
use crate::film::EXR_ENCODING;
use crate::region::{PixelRect, RenderRegion};
use crate::render::Accumulation;
use crate::scene::Scene;
use crate::settings::{MAX_IMAGE_SIDE, RenderSettings};
use glam::DVec3;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Name of the layer of the part's pixels (data window: its rectangle).
const PART_LAYER: &str = "part";
/// Name of the layer of the light-path sums (data window: the image).
const LIGHT_LAYER: &str = "light";
/// Name of the header attribute that records what a part holds.
const ATTRIBUTE: &str = "tyndall";
/// First line of the attribute: the format and its version.
const FORMAT: &str = "tyndall-part 1";

/// Why a part could not be written, read or merged.
#[derive(Debug, thiserror::Error)]
pub enum PartError {
    #[error("{path}: {message}")]
    Io { path: PathBuf, message: String },
    #[error("{path}: not a Tyndall render part: {message}")]
    Format { path: PathBuf, message: String },
    #[error("the parts do not fit together: {0}")]
    Mismatch(String),
}

/// What identifies the render a part belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PartIdentity {
    /// [`scene_hash`] of the scene and settings.
    pub scene_hash: u64,
    pub seed: u64,
}

impl PartIdentity {
    pub fn new(scene: &Scene, settings: &RenderSettings) -> Self {
        Self {
            scene_hash: scene_hash(scene, settings),
            seed: settings.seed,
        }
    }
}

/// A part read from a file.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    pub identity: PartIdentity,
    pub accumulation: Accumulation,
}

/// A 64-bit FNV-1a hash of everything that determines a render's samples:
/// the Tyndall version, the runtime scene (camera, every primitive,
/// material, light, fog, volume, background, glass settings) and the
/// settings that change a sample's value (size, seed, integrator, step,
/// volume samples, interleaving, visibility, bounce and depth limits).
/// Not hashed: samples per pixel, threads and exposure, which do not
/// change any sample. The scene is hashed through its `Debug` form
/// (shortest round-trip floats), streamed, never held as a string.
pub fn scene_hash(scene: &Scene, settings: &RenderSettings) -> u64 {
    let mut h = Fnv1a(0xcbf2_9ce4_8422_2325);
    let camera: &CameraSpec = &scene.camera;
    let s = settings;
    // Writing into a hasher cannot fail.
    let _ = write!(
        h,
        "{}|{camera:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|",
        env!("CARGO_PKG_VERSION"),
        scene.geometry.primitives(),
        scene.materials,
        scene.lights,
        scene.fog,
        scene.volumes,
        scene.background,
        scene.glass,
    );
    let _ = write!(
        h,
        "{}x{}|{}|{:?}|{:?}|{}|{}|{:?}|{}|{}",
        s.width,
        s.height,
        s.seed,
        s.integrator,
        s.step,
        s.volume_samples,
        s.interleave,
        s.visibility,
        s.max_bounces,
        s.max_depth
    );
    h.0
}

/// FNV-1a, 64-bit, fed by `fmt::Write`.
struct Fnv1a(u64);

impl std::fmt::Write for Fnv1a {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        for b in s.bytes() {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
        Ok(())
    }
}

/// How a part file is compressed: run-length encoded (as every EXR Tyndall
/// writes, [`EXR_ENCODING`]) for parts, none for checkpoints written often.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PartCompression {
    Rle,
    None,
}

/// Writes `part` to `path` atomically (see the module docs).
pub fn write_part(
    path: &Path,
    part: &Part,
    compression: PartCompression,
) -> std::result::Result<(), PartError> {
    use exr::prelude::*;
    let a = &part.accumulation;
    let rect = a.region.rect;
    let image = a.resolve();
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        let values = image.pixels().iter().map(|p| p[c]).collect();
        channels.push(AnyChannel::new(*name, FlatSamples::F32(values)));
    }
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        let bits = || a.camera.iter().map(move |s| s[c].to_bits());
        let hi = bits().map(|b| (b >> 32) as u32).collect();
        let lo = bits().map(|b| b as u32).collect();
        channels.push(AnyChannel::new(
            format!("sum.camera.{name}.hi").as_str(),
            FlatSamples::U32(hi),
        ));
        channels.push(AnyChannel::new(
            format!("sum.camera.{name}.lo").as_str(),
            FlatSamples::U32(lo),
        ));
    }
    let encoding = match compression {
        PartCompression::Rle => EXR_ENCODING,
        PartCompression::None => Encoding {
            compression: Compression::Uncompressed,
            ..EXR_ENCODING
        },
    };
    let mut attributes = LayerAttributes {
        layer_position: Vec2(rect.x0 as i32, rect.y0 as i32),
        ..LayerAttributes::named(PART_LAYER)
    };
    let text = describe(part);
    attributes.other.insert(
        Text::from(ATTRIBUTE),
        AttributeValue::Text(Text::new_or_none(&text).expect("ASCII")),
    );
    let mut layers: SmallVec<[Layer<AnyChannels<FlatSamples>>; 2]> = SmallVec::new();
    layers.push(Layer::new(
        (rect.width() as usize, rect.height() as usize),
        attributes,
        encoding,
        AnyChannels::sort(channels),
    ));
    if let Some(light) = &a.light {
        // Each i128 fixed-point channel as four u32 words, least
        // significant first.
        let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
        for (c, name) in ["R", "G", "B"].iter().enumerate() {
            for word in 0..4 {
                let values = light
                    .iter()
                    .map(|s| (s.0[c] as u128 >> (32 * word)) as u32)
                    .collect();
                channels.push(AnyChannel::new(
                    format!("sum.light.{name}.{word}").as_str(),
                    FlatSamples::U32(values),
                ));
            }
        }
        layers.push(Layer::new(
            (a.width as usize, a.height as usize),
            LayerAttributes::named(LIGHT_LAYER),
            encoding,
            AnyChannels::sort(channels),
        ));
    }
    let display = IntegerBounds::from_dimensions((a.width as usize, a.height as usize));
    let exr_image = Image::from_layers(ImageAttributes::new(display), layers);
    write_atomically(path, |tmp| {
        exr_image.write().to_file(tmp).map_err(|e| e.to_string())
    })
}

/// The `tyndall` attribute's text.
fn describe(part: &Part) -> String {
    let a = &part.accumulation;
    let r = a.region.rect;
    format!(
        "{FORMAT}\nscene-hash {:016x}\nimage {} {}\nrect {} {} {} {}\nsamples {} {}\nseed {}\nlight-paths {}\n",
        part.identity.scene_hash,
        a.width,
        a.height,
        r.x0,
        r.y0,
        r.x1,
        r.y1,
        a.region.samples.start,
        a.region.samples.end,
        part.identity.seed,
        a.light.is_some() as u8,
    )
}

/// Reads a part written by [`write_part`].
pub fn read_part(path: &Path) -> std::result::Result<Part, PartError> {
    use exr::prelude::*;
    let format = |message: String| PartError::Format {
        path: path.to_owned(),
        message,
    };
    let image = read_all_flat_layers_from_file(path).map_err(|e| PartError::Io {
        path: path.to_owned(),
        message: e.to_string(),
    })?;
    let layer_named = |name: &str| {
        image
            .layer_data
            .iter()
            .find(|l| l.attributes.layer_name.as_ref() == Some(&Text::from(name)))
    };
    let layer =
        layer_named(PART_LAYER).ok_or_else(|| format(format!("no `{PART_LAYER}` layer")))?;
    let text = match layer.attributes.other.get(&Text::from(ATTRIBUTE)) {
        Some(AttributeValue::Text(t)) => t.to_string(),
        _ => return Err(format(format!("no `{ATTRIBUTE}` header attribute"))),
    };
    let header = parse_description(&text).map_err(format)?;
    let rect = header.rect;
    let size = (rect.width() as usize, rect.height() as usize);
    let side_ok = |s: u32| (1..=MAX_IMAGE_SIDE).contains(&s);
    if !side_ok(header.width)
        || !side_ok(header.height)
        || header.rect.check(header.width, header.height).is_err()
        || (layer.size.width(), layer.size.height()) != size
        || header.samples.start > header.samples.end
    {
        return Err(format(format!(
            "the header's rectangle {rect} of a {}×{} image, samples {:?}, does not fit its {}×{} pixels",
            header.width,
            header.height,
            header.samples,
            layer.size.width(),
            layer.size.height()
        )));
    }
    fn u32_channel<'l>(
        layer: &'l Layer<AnyChannels<FlatSamples>>,
        name: &str,
    ) -> std::result::Result<&'l [u32], String> {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name == *name)
            .and_then(|c| match &c.sample_data {
                FlatSamples::U32(v) => Some(v.as_slice()),
                _ => None,
            })
            .ok_or_else(|| format!("no u32 channel `{name}`"))
    }
    let channel = |layer, name: &str| u32_channel(layer, name).map_err(format);
    let mut camera = vec![DVec3::ZERO; rect.area()];
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        let hi = channel(layer, &format!("sum.camera.{name}.hi"))?;
        let lo = channel(layer, &format!("sum.camera.{name}.lo"))?;
        for ((o, h), l) in camera.iter_mut().zip(hi).zip(lo) {
            o[c] = f64::from_bits((*h as u64) << 32 | *l as u64);
        }
    }
    let light = if header.light {
        let full = header.width as usize * header.height as usize;
        let layer = layer_named(LIGHT_LAYER)
            .filter(|l| l.size.width() * l.size.height() == full)
            .ok_or_else(|| format(format!("no full-image `{LIGHT_LAYER}` layer")))?;
        let mut light = vec![ExactRgb::ZERO; full];
        for (c, name) in ["R", "G", "B"].iter().enumerate() {
            for word in 0..4 {
                let values = channel(layer, &format!("sum.light.{name}.{word}"))?;
                for (o, v) in light.iter_mut().zip(values) {
                    o.0[c] = (o.0[c] as u128 | (*v as u128) << (32 * word)) as i128;
                }
            }
        }
        Some(light)
    } else {
        None
    };
    Ok(Part {
        identity: PartIdentity {
            scene_hash: header.scene_hash,
            seed: header.seed,
        },
        accumulation: Accumulation {
            width: header.width,
            height: header.height,
            region: RenderRegion {
                rect,
                samples: header.samples,
            },
            camera,
            light,
        },
    })
}

/// The parsed `tyndall` attribute.
struct Description {
    scene_hash: u64,
    width: u32,
    height: u32,
    rect: PixelRect,
    samples: std::ops::Range<u32>,
    seed: u64,
    light: bool,
}

fn parse_description(text: &str) -> Result<Description, String> {
    let mut fields: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let mut words = line.split_whitespace();
        let key = words.next().unwrap_or_default();
        fields.insert(key, words.collect());
    }
    if fields.get("tyndall-part").map(Vec::as_slice) != Some(&["1"]) {
        return Err(format!(
            "the `{ATTRIBUTE}` attribute does not start with `{FORMAT}`"
        ));
    }
    fn numbers<T: TryFrom<u64>>(
        fields: &BTreeMap<&str, Vec<&str>>,
        key: &str,
        n: usize,
        radix16: bool,
    ) -> Result<Vec<T>, String> {
        let words = fields
            .get(key)
            .filter(|w| w.len() == n)
            .ok_or_else(|| format!("the header needs `{key}` with {n} number(s)"))?;
        words
            .iter()
            .map(|w| {
                let v = if radix16 {
                    u64::from_str_radix(w, 16).ok()
                } else {
                    w.parse::<u64>().ok()
                };
                v.and_then(|v| T::try_from(v).ok())
                    .ok_or_else(|| format!("`{key}`: `{w}` is not a valid number"))
            })
            .collect()
    }
    let hash: Vec<u64> = numbers(&fields, "scene-hash", 1, true)?;
    let image: Vec<u32> = numbers(&fields, "image", 2, false)?;
    let rect: Vec<u32> = numbers(&fields, "rect", 4, false)?;
    let samples: Vec<u32> = numbers(&fields, "samples", 2, false)?;
    let seed: Vec<u64> = numbers(&fields, "seed", 1, false)?;
    let light: Vec<u8> = numbers(&fields, "light-paths", 1, false)?;
    Ok(Description {
        scene_hash: hash[0],
        width: image[0],
        height: image[1],
        rect: PixelRect {
            x0: rect[0],
            y0: rect[1],
            x1: rect[2],
            y1: rect[3],
        },
        samples: samples[0]..samples[1],
        seed: seed[0],
        light: light[0] != 0,
    })
}

/// Assembles parts into one: all must come from the same render (scene
/// hash, seed, image size, light paths); parts of the same rectangle must
/// hold consecutive sample ranges (no gap, no overlap), added in order;
/// the rectangles must not overlap, must cover the whole image, and must
/// all end up with the same sample range. Each part comes with its path,
/// which errors name. Parts of one rectangle are summed in sample order.
pub fn merge(parts: Vec<(PathBuf, Part)>) -> Result<Part, PartError> {
    let mismatch = PartError::Mismatch;
    let Some((first_path, first)) = parts.first() else {
        return Err(mismatch("no parts given".into()));
    };
    let (identity, width, height, light) = (
        first.identity,
        first.accumulation.width,
        first.accumulation.height,
        first.accumulation.light.is_some(),
    );
    for (path, part) in &parts[1..] {
        let a = &part.accumulation;
        if part.identity.scene_hash != identity.scene_hash {
            return Err(mismatch(format!(
                "{} and {} are renders of different scenes or settings (scene hashes {:016x} and {:016x})",
                first_path.display(),
                path.display(),
                identity.scene_hash,
                part.identity.scene_hash
            )));
        }
        if part.identity.seed != identity.seed
            || (a.width, a.height) != (width, height)
            || a.light.is_some() != light
        {
            return Err(mismatch(format!(
                "{} and {} differ in seed, image size or light paths",
                first_path.display(),
                path.display()
            )));
        }
    }
    // Parts by rectangle, each rectangle's parts by first sample.
    let mut by_rect: BTreeMap<PixelRect, Vec<(PathBuf, Part)>> = BTreeMap::new();
    for (path, part) in parts {
        by_rect
            .entry(part.accumulation.region.rect)
            .or_default()
            .push((path, part));
    }
    let mut pieces: Vec<(PathBuf, Accumulation)> = Vec::new();
    for (_, mut group) in by_rect {
        group.sort_by_key(|(_, p)| {
            (
                p.accumulation.region.samples.start,
                p.accumulation.region.samples.end,
            )
        });
        let mut group = group.into_iter();
        let (path, part) = group.next().expect("groups are not empty");
        let mut sum = part.accumulation;
        let mut last = path.clone();
        for (next_path, next) in group {
            let (have, next_samples) = (
                sum.region.samples.clone(),
                next.accumulation.region.samples.clone(),
            );
            if next_samples.start != have.end {
                let what = if next_samples.start < have.end {
                    "overlap"
                } else {
                    "leave a gap"
                };
                return Err(mismatch(format!(
                    "{} (samples {}..{}) and {} (samples {}..{}) of the same pixels {what}",
                    last.display(),
                    have.start,
                    have.end,
                    next_path.display(),
                    next_samples.start,
                    next_samples.end
                )));
            }
            sum.append(&next.accumulation).map_err(mismatch)?;
            last = next_path;
        }
        pieces.push((path, sum));
    }
    for (i, (path_a, a)) in pieces.iter().enumerate() {
        for (path_b, b) in &pieces[i + 1..] {
            if a.region.rect.overlaps(&b.region.rect) {
                return Err(mismatch(format!(
                    "{} (pixels {}) and {} (pixels {}) overlap",
                    path_a.display(),
                    a.region.rect,
                    path_b.display(),
                    b.region.rect
                )));
            }
        }
        let (first_path, first) = &pieces[0];
        if a.region.samples != first.region.samples {
            return Err(mismatch(format!(
                "{} holds samples {:?} but {} holds {:?}: every pixel needs the same samples",
                path_a.display(),
                a.region.samples,
                first_path.display(),
                first.region.samples
            )));
        }
    }
    if light
        && let Some((path, _)) = pieces
            .iter()
            .find(|(_, a)| (a.region.rect.x0, a.region.rect.x1) != (0, width))
    {
        return Err(mismatch(format!(
            "{} is not a band of whole rows, which parts with light paths must be",
            path.display()
        )));
    }
    let covered: usize = pieces.iter().map(|(_, a)| a.region.rect.area()).sum();
    let full = PixelRect::full(width, height);
    if pieces.len() == 1 {
        // One rectangle (sample ranges of it): it need not be the image.
        let (_, accumulation) = pieces.pop().expect("one piece");
        return Ok(Part {
            identity,
            accumulation,
        });
    }
    if covered != full.area() {
        return Err(mismatch(format!(
            "the parts cover {covered} of the image's {} pixels: some tiles are missing",
            full.area()
        )));
    }
    let samples = pieces[0].1.region.samples.clone();
    let mut whole = Accumulation::new((width, height), full, samples.start, light);
    whole.region.samples = samples;
    for (_, piece) in &pieces {
        let r = piece.region.rect;
        for y in r.y0..r.y1 {
            let from = (y - r.y0) as usize * r.width() as usize;
            let to = full.index(r.x0, y).expect("inside");
            let n = r.width() as usize;
            whole.camera[to..to + n].copy_from_slice(&piece.camera[from..from + n]);
        }
        // The bands' light-path shares partition each pass's paths.
        if let (Some(w), Some(p)) = (&mut whole.light, &piece.light) {
            for (w, p) in w.iter_mut().zip(p) {
                w.add_exact(p);
            }
        }
    }
    Ok(Part {
        identity,
        accumulation: whole,
    })
}

/// Writes a file through `write(temporary path)`, then renames the
/// temporary over `path`: readers see the old file or the whole new one.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), PartError> {
    let io = |message: String| PartError::Io {
        path: path.to_owned(),
        message,
    };
    let name = path
        .file_name()
        .ok_or_else(|| io("not a file name".into()))?
        .to_string_lossy();
    let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let result = write(&tmp)
        .and_then(|()| {
            std::fs::File::open(&tmp)
                .and_then(|f| f.sync_all())
                .map_err(|e| e.to_string())
        })
        .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| e.to_string()));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "tyndall-part 1\nscene-hash 00ff\nimage 8 6\nrect 0 2 8 4\nsamples 3 5\nseed 7\nlight-paths 1\n";

    #[test]
    fn descriptions_parse_and_bad_ones_say_what_is_wrong() {
        let d = parse_description(GOOD).expect("good");
        assert_eq!((d.scene_hash, d.width, d.height, d.seed), (0xff, 8, 6, 7));
        assert_eq!(
            d.rect,
            PixelRect {
                x0: 0,
                y0: 2,
                x1: 8,
                y1: 4
            }
        );
        assert_eq!((d.samples, d.light), (3..5, true));
        for (bad, says) in [
            (
                GOOD.replace("tyndall-part 1", "tyndall-part 2"),
                "does not start",
            ),
            (GOOD.replace("image 8 6", "image 8"), "`image` with 2"),
            (GOOD.replace("seed 7", "seed -7"), "`seed`: `-7`"),
            (GOOD.replace("samples 3 5\n", ""), "`samples`"),
            (
                GOOD.replace("light-paths 1", "light-paths 300"),
                "`light-paths`",
            ),
        ] {
            match parse_description(&bad) {
                Err(e) => assert!(e.contains(says), "{e} should say {says}"),
                Ok(_) => panic!("accepted {bad:?}"),
            }
        }
    }
}
