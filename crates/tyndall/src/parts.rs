//! Render parts: a tile, a sample range or a checkpoint of a render, and
//! merging them into the whole.
//!
//! A [`Part`] is an [`Accumulation`] (the exact per-pixel sums of the
//! samples it holds) with the [`PartIdentity`] of the render it belongs
//! to. [`merge`] adds the sums of parts of the same render: merged sample
//! ranges differ from the single render only by the f64 rounding of the
//! additions, merged tiles not at all. Parts are stored in OpenEXR files
//! by the `tyndall-image` crate (`tyndall_image::parts`), which keeps the
//! sums exact.

use crate::camera::CameraSpec;
use crate::region::PixelRect;
use crate::render::Accumulation;
use crate::scene::Scene;
use crate::settings::RenderSettings;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;

/// Why parts could not be merged: they do not fit together.
#[derive(Debug, thiserror::Error)]
#[error("the parts do not fit together: {0}")]
pub struct MergeError(pub String);

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

/// A part of a render: its sums and the render it belongs to.
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
/// (shortest round-trip floats), streamed, never held as a string; voxel
/// grids print a digest of their values in a canonical order in place of
/// the values ([`crate::media::sparse::SparseGrid::content_digest`]), so
/// a cloud of millions of voxels hashes in milliseconds and the same
/// file hashes alike on every load.
pub fn scene_hash(scene: &Scene, settings: &RenderSettings) -> u64 {
    let mut h = Fnv1a::new();
    let camera: &CameraSpec = &scene.camera;
    let s = settings;
    // Writing into a hasher cannot fail.
    let _ = write!(
        h,
        "{}|{camera:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?}|",
        env!("CARGO_PKG_VERSION"),
        scene.geometry.primitives(),
        scene.materials,
        scene.lights,
        scene.light_groups,
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
    h.finish()
}

/// FNV-1a, 64-bit (Fowler, Noll & Vo; the parameters of IETF draft
/// `draft-eastlake-fnv`): fed bytes by [`Fnv1a::update`] or text by
/// `fmt::Write`. Scene hashes and the checksums of part files use it; it
/// detects accidental change (every flipped bit changes the hash), not
/// tampering.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fnv1a(u64);

impl Fnv1a {
    /// The FNV-1a offset basis.
    pub const fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }

    pub fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }

    pub fn finish(self) -> u64 {
        self.0
    }
}

impl Default for Fnv1a {
    fn default() -> Self {
        Self::new()
    }
}

impl std::fmt::Write for Fnv1a {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.update(s.as_bytes());
        Ok(())
    }
}

/// Assembles parts into one: all must come from the same render (scene
/// hash, seed, image size, light paths); parts of the same rectangle must
/// hold consecutive sample ranges (no gap, no overlap), added in order;
/// the rectangles must not overlap, must cover the whole image, and must
/// all end up with the same sample range. Each part comes with its path,
/// which errors name. Parts of one rectangle are summed in sample order.
pub fn merge(parts: Vec<(PathBuf, Part)>) -> Result<Part, MergeError> {
    let mismatch = MergeError;
    let Some((first_path, first)) = parts.first() else {
        return Err(mismatch("no parts given".into()));
    };
    let (identity, width, height, light, kept) = (
        first.identity,
        first.accumulation.width,
        first.accumulation.height,
        first.accumulation.light.is_some(),
        first.accumulation.kept(),
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
            || a.kept() != kept
        {
            return Err(mismatch(format!(
                "{} and {} differ in seed, image size, light paths, guides, radiance components or light groups (AOVs)",
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
    let mut whole = Accumulation::new((width, height), full, samples.start, light, kept);
    whole.region.samples = samples;
    for (_, piece) in &pieces {
        let r = piece.region.rect;
        for y in r.y0..r.y1 {
            let from = (y - r.y0) as usize * r.width() as usize;
            let to = full.index(r.x0, y).expect("inside");
            let n = r.width() as usize;
            whole.camera[to..to + n].copy_from_slice(&piece.camera[from..from + n]);
            if let (Some(w), Some(p)) = (&mut whole.guides, &piece.guides) {
                w[to..to + n].copy_from_slice(&p[from..from + n]);
            }
            if let (Some(w), Some(p)) = (&mut whole.components, &piece.components) {
                w[to..to + n].copy_from_slice(&p[from..from + n]);
            }
            if let (Some(w), Some(p)) = (&mut whole.light_groups, &piece.light_groups) {
                let g = w.groups();
                w.sums_mut()[to * g..(to + n) * g]
                    .copy_from_slice(&p.sums()[from * g..(from + n) * g]);
            }
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
