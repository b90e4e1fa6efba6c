//! Emitting volumes as lights: next event estimation towards them
//! (docs/physics.md §2.5). A volume's emission is split over its
//! majorant cells (8³-voxel bricks of a sparse grid); a cell is chosen
//! with probability proportional to its power bound — an upper bound of
//! the emission coefficient in it times its volume — and a point
//! uniformly in it, so the density of a point `y` of volume `v` is
//! `P(v)·P(cell)/|cell|`, known for any `y` ([`MediaEmitters::pdf`]).
//!
//! Emission found by tracking along a sampled direction is weighted
//! against this density by the balance heuristic ([`HitWeighting`]); the
//! weights of the two strategies sum to 1 at every (volume, point), so the
//! pair is unbiased whatever the heuristic's densities, which are:
//! `p_nee(v, y)` above, and for the hit `p_dir(ω)·σt_v(y)/|y − x|²`, the
//! direction's density times the rate at which the walk stops near `y`,
//! per unit volume (σt_v the emitting volume's own extinction: a quantity
//! both sides evaluate identically). Only box-bounded volumes are
//! sampled; emission of others counts in full when hit.

use super::volume::Volume;
use crate::shapes::Bounds;
use glam::{UVec3, Vec3};

/// One sampled emitting volume: its cells and their probabilities.
#[derive(Debug)]
struct EmitterVolume {
    volume: usize,
    bounds: Bounds,
    cells: UVec3,
    /// Cumulative probabilities of the cells (x fastest), ending at 1.
    cdf: Vec<f32>,
    /// Volume of one cell.
    cell_volume: f32,
}

/// The scene's emitting volumes as NEE light sources.
#[derive(Debug, Default)]
pub struct MediaEmitters {
    volumes: Vec<EmitterVolume>,
    /// Cumulative probabilities of the volumes, ending at 1.
    cdf: Vec<f32>,
    /// For each scene volume, its index in `volumes`.
    index: Vec<Option<usize>>,
}

impl MediaEmitters {
    pub(crate) fn new(volumes: &[Volume]) -> Self {
        let mut out = Self {
            index: vec![None; volumes.len()],
            ..Self::default()
        };
        let mut powers = Vec::new();
        for (i, v) in volumes.iter().enumerate() {
            let Some((bounds, cells, weights)) = v.emission_cells() else {
                continue;
            };
            let total: f64 = weights.iter().map(|&w| w as f64).sum();
            if !(total > 0.0 && total.is_finite()) {
                continue;
            }
            let mut acc = 0.0f64;
            let cdf = weights
                .iter()
                .map(|&w| {
                    acc += w as f64;
                    (acc / total) as f32
                })
                .collect();
            let cell_volume = (bounds.extent() / cells.as_vec3()).element_product();
            out.index[i] = Some(out.volumes.len());
            out.volumes.push(EmitterVolume {
                volume: i,
                bounds,
                cells,
                cdf,
                cell_volume,
            });
            powers.push(total);
        }
        let total: f64 = powers.iter().sum();
        let mut acc = 0.0f64;
        out.cdf = powers
            .iter()
            .map(|&p| {
                acc += p;
                (acc / total) as f32
            })
            .collect();
        out
    }

    /// Whether any volume is sampled.
    pub(crate) fn is_empty(&self) -> bool {
        self.volumes.is_empty()
    }

    /// A point of an emitting volume from uniform numbers (`u_volume`
    /// picks the volume, `u_cell` its cell, `w` the point in the cell):
    /// the scene volume's index, the point and its density `p_nee` (per
    /// unit volume).
    pub(crate) fn sample(&self, u_volume: f32, u_cell: f32, w: Vec3) -> Option<(usize, Vec3, f32)> {
        let (e, _) = pick(&self.cdf, u_volume)?;
        let emitter = &self.volumes[e];
        let (cell, _) = pick(&emitter.cdf, u_cell)?;
        let n = emitter.cells;
        let c = UVec3::new(
            cell as u32 % n.x,
            (cell as u32 / n.x) % n.y,
            cell as u32 / (n.x * n.y),
        );
        let size = emitter.bounds.extent() / n.as_vec3();
        let y = emitter.bounds.min + (c.as_vec3() + w) * size;
        let pdf = self.pdf(emitter.volume, y);
        (pdf > 0.0).then_some((emitter.volume, y, pdf))
    }

    /// The density (per unit volume) with which [`Self::sample`] draws
    /// `y` in scene volume `volume`; 0 where it never does.
    pub(crate) fn pdf(&self, volume: usize, y: Vec3) -> f32 {
        let Some(Some(e)) = self.index.get(volume) else {
            return 0.0;
        };
        let emitter = &self.volumes[*e];
        let n = emitter.cells;
        let g = (y - emitter.bounds.min) / emitter.bounds.extent() * n.as_vec3();
        if !(g.cmpge(Vec3::ZERO).all() && g.cmplt(n.as_vec3()).all()) {
            return 0.0;
        }
        let c = g.as_uvec3().min(n - 1);
        let cell = (c.x + n.x * (c.y + n.y * c.z)) as usize;
        let p_cell = emitter.cdf[cell]
            - if cell == 0 {
                0.0
            } else {
                emitter.cdf[cell - 1]
            };
        let p_volume = self.cdf[*e] - if *e == 0 { 0.0 } else { self.cdf[*e - 1] };
        p_volume * p_cell / emitter.cell_volume
    }
}

/// The first index whose cumulative probability exceeds `u`, and that
/// entry's probability (`None` for an empty table).
fn pick(cdf: &[f32], u: f32) -> Option<(usize, f32)> {
    let last = cdf.len().checked_sub(1)?;
    let i = cdf.partition_point(|&c| c <= u).min(last);
    // Entries of probability 0 are never chosen: step to a positive one.
    let i = (i..=last)
        .find(|&k| cdf[k] > if k == 0 { 0.0 } else { cdf[k - 1] })
        .or_else(|| {
            (0..i)
                .rev()
                .find(|&k| cdf[k] > if k == 0 { 0.0 } else { cdf[k - 1] })
        })?;
    Some((i, cdf[i] - if i == 0 { 0.0 } else { cdf[i - 1] }))
}

/// How emission found by tracking along a sampled direction is weighted
/// against next event estimation towards emitting media (module doc).
#[derive(Clone, Copy)]
pub struct HitWeighting<'a> {
    pub(crate) emitters: &'a MediaEmitters,
    /// The vertex the direction was sampled at.
    pub(crate) from: Vec3,
    /// The direction's solid-angle density.
    pub(crate) pdf_dir: f32,
    /// Whether the vertex estimated emission by NEE.
    pub(crate) nee: bool,
    /// Whether found emission counts (off: NEE alone, where it reaches).
    pub(crate) hits: bool,
}

impl HitWeighting<'_> {
    /// The balance-heuristic weight of emission of scene volume `volume`
    /// found at `y`, where that volume's extinction is `sigma_t` (its
    /// largest channel).
    #[inline]
    pub(crate) fn weight(&self, volume: usize, y: Vec3, sigma_t: f32) -> f32 {
        let p_nee = if self.nee {
            self.emitters.pdf(volume, y)
        } else {
            0.0
        };
        if p_nee <= 0.0 {
            return 1.0;
        }
        if !self.hits {
            return 0.0;
        }
        let p_hit = hit_density(self.pdf_dir, sigma_t, self.from.distance_squared(y));
        p_hit / (p_hit + p_nee)
    }
}

/// The hit strategy's density of `y` for the MIS weights (module doc).
#[inline]
pub(crate) fn hit_density(pdf_dir: f32, sigma_t: f32, distance_squared: f32) -> f32 {
    if distance_squared > 0.0 {
        pdf_dir * sigma_t / distance_squared
    } else {
        0.0
    }
}
