//! Render parts on disk: OpenEXR files holding a tile, a sample range or
//! a checkpoint of a render ([`tyndall::parts::Part`]).
//!
//! A part file is an OpenEXR image in the full image's display window with
//! two layers:
//! - `part`, the part's pixel rectangle (its data window placed at the
//!   rectangle's origin): `R`, `G`, `B` (f32), the part's own image (the
//!   mean of the samples it holds; see [`Accumulation::resolve`]), and
//!   `sum.camera.{R,G,B}.{hi,lo}` (u32), the f64 per-pixel sums of the
//!   camera samples, each stored exactly as the high and low 32 bits of its
//!   IEEE-754 bit pattern (OpenEXR has no f64 channels; two f32s would
//!   round). Merging ([`tyndall::parts::merge`]) adds these exact sums.
//!   A part that keeps the first-surface guides ([`GuideSum`]) also has,
//!   stored the same way, `sum.guide.{albedo,normal,position}.{X,Y,Z}`
//!   and `sum.guide.depth` (each `.hi`/`.lo`), and `sum.guide.hits`
//!   (u32), and its header says `guides 1`. One that keeps the radiance's
//!   components has `sum.{emission,direct,indirect,volume}.{R,G,B}`
//!   (`.hi`/`.lo`) and says `components 1`. One that keeps the
//!   radiance of its N light groups has `sum.group.{k}.{R,G,B}`
//!   (`.hi`/`.lo`, k = 0 … N − 1, the scene's group numbers, which its
//!   hash fixes) and says `light-groups N` and, for each group,
//!   `light-group-k NAME`.
//!   Its text attribute `tyndall` records what the part holds, one
//!   `key value` per line: `tyndall-part 1` (the format), `scene-hash`
//!   (see [`tyndall::parts::scene_hash`]), `image W H`, `rect x0 y0 x1 y1`
//!   (pixels `[x0, x1) × [y0, y1)`), `samples A B` (sample indices
//!   `A..B`), `seed`, `light-paths 0|1`, `guides 1` (only when it
//!   keeps them), and last `checksum`, the
//!   64-bit FNV-1a hash ([`tyndall::parts::Fnv1a`]) of the lines before
//!   it and of every sum of both layers (see [`checksum`]): a part or
//!   checkpoint with a flipped bit in its header or its sums is refused
//!   instead of being merged or resumed into NaN, infinite or negative
//!   pixels;
//! - `light`, only for renders that trace light paths: the whole image,
//!   `sum.light.{R,G,B}.{0,1,2,3}` (u32), the exact fixed-point sums
//!   ([`ExactRgb`]) of the splats of the part's share of the light paths,
//!   each i128 as four 32-bit words, least significant first.
//!
//! Files are written atomically: to a temporary file in the same folder,
//! synced, then renamed over the target, so a reader (or a render killed
//! mid-write) never sees a partial file.

use crate::format::EXR_ENCODING;
use glam::DVec3;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use tyndall::aov::{Component, ComponentSum};
use tyndall::exact_sum::ExactRgb;
use tyndall::guides::GuideSum;
use tyndall::light_groups::{LightGroupSums, MAX_LIGHT_GROUPS, is_group_name};
use tyndall::parts::{Fnv1a, Part, PartIdentity};
use tyndall::region::{PixelRect, RenderRegion};
use tyndall::render::Accumulation;
use tyndall::settings::MAX_IMAGE_SIDE;

/// Name of the layer of the part's pixels (data window: its rectangle).
const PART_LAYER: &str = "part";
/// Name of the layer of the light-path sums (data window: the image).
const LIGHT_LAYER: &str = "light";
/// Name of the header attribute that records what a part holds.
const ATTRIBUTE: &str = "tyndall";
/// First line of the attribute: the format and its version.
/// (Format 2 added the checksum; a format-1 part is refused by name.)
const FORMAT: &str = "tyndall-part 2";
/// The key of the header's last line.
const CHECKSUM: &str = "checksum";

/// Why a part file could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum PartFileError {
    #[error("{path}: {message}")]
    Io { path: PathBuf, message: String },
    #[error("{path}: not a Tyndall render part: {message}")]
    Format { path: PathBuf, message: String },
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
) -> std::result::Result<(), PartFileError> {
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
        push_f64(
            &mut channels,
            &format!("sum.camera.{name}"),
            a.camera.iter().map(|s| s[c]),
        );
    }
    if let Some(guides) = &a.guides {
        for (c, name) in ["X", "Y", "Z"].iter().enumerate() {
            for (k, field) in GuideSum::VECTORS.iter().enumerate() {
                push_f64(
                    &mut channels,
                    &format!("sum.guide.{field}.{name}"),
                    guides.iter().map(|g| g.vectors()[k][c]),
                );
            }
        }
        push_f64(
            &mut channels,
            "sum.guide.depth",
            guides.iter().map(|g| g.depth),
        );
        channels.push(AnyChannel::new(
            "sum.guide.hits",
            FlatSamples::U32(guides.iter().map(|g| g.hits).collect()),
        ));
    }
    if let Some(components) = &a.components {
        for component in Component::ALL {
            for (c, name) in ["R", "G", "B"].iter().enumerate() {
                push_f64(
                    &mut channels,
                    &format!("sum.{}.{name}", component.name()),
                    components.iter().map(|s| s[component.index()][c]),
                );
            }
        }
    }
    if let Some(groups) = &a.light_groups {
        let n = groups.groups();
        for k in 0..n {
            for (c, name) in ["R", "G", "B"].iter().enumerate() {
                push_f64(
                    &mut channels,
                    &format!("sum.group.{k}.{name}"),
                    groups.sums().iter().skip(k).step_by(n).map(|s| s[c]),
                );
            }
        }
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
    let mut text = describe(part);
    let sum = checksum(&text, a);
    text.push_str(&format!("{CHECKSUM} {sum:016x}\n"));
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

/// Adds the f64 `values` as the u32 channels `{name}.hi` and `{name}.lo`,
/// the high and low halves of their bit patterns.
fn push_f64(
    channels: &mut exr::prelude::SmallVec<[exr::prelude::AnyChannel<exr::prelude::FlatSamples>; 4]>,
    name: &str,
    values: impl Iterator<Item = f64> + Clone,
) {
    use exr::prelude::*;
    let bits = values.map(f64::to_bits);
    let hi = bits.clone().map(|b| (b >> 32) as u32).collect();
    let lo = bits.map(|b| b as u32).collect();
    channels.push(AnyChannel::new(
        format!("{name}.hi").as_str(),
        FlatSamples::U32(hi),
    ));
    channels.push(AnyChannel::new(
        format!("{name}.lo").as_str(),
        FlatSamples::U32(lo),
    ));
}

/// The `tyndall` attribute's text.
fn describe(part: &Part) -> String {
    let a = &part.accumulation;
    let r = a.region.rect;
    let mut text = format!(
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
    );
    // Said only when present: parts written before guides existed keep
    // their header, and so their checksum.
    if a.guides.is_some() {
        text.push_str("guides 1\n");
    }
    if a.components.is_some() {
        text.push_str("components 1\n");
    }
    if let Some(groups) = &a.light_groups {
        text.push_str(&format!("light-groups {}\n", groups.groups()));
        for (k, name) in groups.names().iter().enumerate() {
            text.push_str(&format!("light-group-{k} {name}\n"));
        }
    }
    text
}

/// The checksum of a part: FNV-1a over the header lines `description`
/// (everything before the `checksum` line, as stored) and then each
/// camera sum's f64 bit pattern and each light sum's i128, little-endian,
/// in storage order.
fn checksum(description: &str, a: &Accumulation) -> u64 {
    let mut h = Fnv1a::new();
    h.update(description.as_bytes());
    for s in &a.camera {
        for c in 0..3 {
            h.update(&s[c].to_bits().to_le_bytes());
        }
    }
    for s in a.light.iter().flatten() {
        for c in s.0 {
            h.update(&c.to_le_bytes());
        }
    }
    for g in a.guides.iter().flatten() {
        for v in g.vectors() {
            for c in 0..3 {
                h.update(&v[c].to_bits().to_le_bytes());
            }
        }
        h.update(&g.depth.to_bits().to_le_bytes());
        h.update(&g.hits.to_le_bytes());
    }
    for s in a.components.iter().flatten() {
        for v in s {
            for c in 0..3 {
                h.update(&v[c].to_bits().to_le_bytes());
            }
        }
    }
    for v in a.light_groups.iter().flat_map(|g| g.sums()) {
        for c in 0..3 {
            h.update(&v[c].to_bits().to_le_bytes());
        }
    }
    h.finish()
}

/// Reads a part written by [`write_part`], checking its checksum.
pub fn read_part(path: &Path) -> std::result::Result<Part, PartFileError> {
    use exr::prelude::*;
    let format = |message: String| PartFileError::Format {
        path: path.to_owned(),
        message,
    };
    let image = read_all_flat_layers_from_file(path).map_err(|e| PartFileError::Io {
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
    let f64_channel = |name: &str| -> std::result::Result<Vec<f64>, PartFileError> {
        let hi = channel(layer, &format!("{name}.hi"))?;
        let lo = channel(layer, &format!("{name}.lo"))?;
        Ok(hi
            .iter()
            .zip(lo)
            .map(|(h, l)| f64::from_bits((*h as u64) << 32 | *l as u64))
            .collect())
    };
    let mut camera = vec![DVec3::ZERO; rect.area()];
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        let values = f64_channel(&format!("sum.camera.{name}"))?;
        for (o, v) in camera.iter_mut().zip(values) {
            o[c] = v;
        }
    }
    let guides = if header.guides {
        let mut guides = vec![GuideSum::default(); rect.area()];
        for (c, name) in ["X", "Y", "Z"].iter().enumerate() {
            for (k, field) in GuideSum::VECTORS.iter().enumerate() {
                let values = f64_channel(&format!("sum.guide.{field}.{name}"))?;
                for (g, v) in guides.iter_mut().zip(values) {
                    g.vectors_mut()[k][c] = v;
                }
            }
        }
        for (g, v) in guides.iter_mut().zip(f64_channel("sum.guide.depth")?) {
            g.depth = v;
        }
        for (g, v) in guides.iter_mut().zip(channel(layer, "sum.guide.hits")?) {
            g.hits = *v;
        }
        Some(guides)
    } else {
        None
    };
    let components = if header.components {
        let mut components = vec![ComponentSum::default(); rect.area()];
        for component in Component::ALL {
            for (c, name) in ["R", "G", "B"].iter().enumerate() {
                let values = f64_channel(&format!("sum.{}.{name}", component.name()))?;
                for (s, v) in components.iter_mut().zip(values) {
                    s[component.index()][c] = v;
                }
            }
        }
        Some(components)
    } else {
        None
    };
    let light_groups = match header.light_groups.len() {
        0 => None,
        n => {
            let mut sums = vec![DVec3::ZERO; rect.area() * n];
            for k in 0..n {
                for (c, name) in ["R", "G", "B"].iter().enumerate() {
                    let values = f64_channel(&format!("sum.group.{k}.{name}"))?;
                    for (s, v) in sums.iter_mut().skip(k).step_by(n).zip(values) {
                        s[c] = v;
                    }
                }
            }
            Some(
                LightGroupSums::from_sums(header.light_groups.clone(), sums)
                    .ok_or_else(|| format(format!("`light-groups {n}` is out of range")))?,
            )
        }
    };
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
    let accumulation = Accumulation {
        width: header.width,
        height: header.height,
        region: RenderRegion {
            rect,
            samples: header.samples,
        },
        camera,
        light,
        guides,
        components,
        light_groups,
    };
    // The checksum covers the header as stored, up to its own line.
    let described = text
        .find(&format!("\n{CHECKSUM} "))
        .map_or(text.as_str(), |end| &text[..=end]);
    let computed = checksum(described, &accumulation);
    if computed != header.checksum {
        return Err(format(format!(
            "its checksum is {:016x} but its header and sums hash to {computed:016x}: the file was changed or damaged after it was written",
            header.checksum
        )));
    }
    Ok(Part {
        identity: PartIdentity {
            scene_hash: header.scene_hash,
            seed: header.seed,
        },
        accumulation,
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
    /// Whether the part holds the guides' sums (absent: it does not).
    guides: bool,
    /// Whether the part holds the components' sums (absent: it does not).
    components: bool,
    /// The names of the light groups whose sums the part holds (absent:
    /// none).
    light_groups: Vec<String>,
    checksum: u64,
}

fn parse_description(text: &str) -> Result<Description, String> {
    let mut fields: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let mut words = line.split_whitespace();
        let key = words.next().unwrap_or_default();
        fields.insert(key, words.collect());
    }
    if fields.get("tyndall-part").map(Vec::as_slice) == Some(&["1"]) {
        return Err(
            "it is a format-1 part, written before parts carried a checksum: render it again"
                .into(),
        );
    }
    if fields.get("tyndall-part").map(Vec::as_slice) != Some(&["2"]) {
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
    let checksum: Vec<u64> = numbers(&fields, CHECKSUM, 1, true)?;
    let flag = |key: &str| -> Result<bool, String> {
        match fields.contains_key(key) {
            true => Ok(numbers::<u8>(&fields, key, 1, false)?[0] != 0),
            false => Ok(false),
        }
    };
    let (guides, components) = (flag("guides")?, flag("components")?);
    let groups = match fields.contains_key("light-groups") {
        true => numbers::<usize>(&fields, "light-groups", 1, false)?[0],
        false => 0,
    };
    if groups > MAX_LIGHT_GROUPS {
        return Err(format!(
            "`light-groups {groups}`: a render keeps at most {MAX_LIGHT_GROUPS}"
        ));
    }
    let light_groups = (0..groups)
        .map(|k| {
            let key = format!("light-group-{k}");
            match fields.get(key.as_str()).map(Vec::as_slice) {
                Some([name]) if is_group_name(name) => Ok(name.to_string()),
                _ => Err(format!(
                    "the header needs `{key}` with the group's name (ASCII letters, digits, `_`, `-`)"
                )),
            }
        })
        .collect::<Result<Vec<String>, String>>()?;
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
        guides,
        components,
        light_groups,
        checksum: checksum[0],
    })
}

/// Writes a file through `write(temporary path)`, then renames the
/// temporary over `path`: readers see the old file or the whole new one.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), PartFileError> {
    let io = |message: String| PartFileError::Io {
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

    const GOOD: &str = "tyndall-part 2\nscene-hash 00ff\nimage 8 6\nrect 0 2 8 4\nsamples 3 5\nseed 7\nlight-paths 1\nchecksum 0123456789abcdef\n";

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
                GOOD.replace("tyndall-part 2", "tyndall-part 3"),
                "does not start",
            ),
            (
                GOOD.replace("tyndall-part 2", "tyndall-part 1"),
                "format-1 part",
            ),
            (
                GOOD.replace("checksum 0123456789abcdef\n", ""),
                "`checksum`",
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
