//! Volumes: media with RGB extinction, any density field, and a region
//! bounded by a box, a closed mesh, or nothing.
//!
//! A volume's extinction at a point is `σt(x) = sigma_t·density(x)` per
//! channel and its scattering `σs(x) = albedo·σt(x)`. Where volumes
//! overlap their coefficients add (a mixture of particle populations —
//! smoke in fog); a region's boundary is not a surface (it neither
//! reflects nor refracts: give it a material separately for that).
//!
//! Density fields live in the region's bounding box mapped to the unit
//! cube. Each volume carries a [`MajorantGrid`]: the largest density in
//! each cell of a coarse grid over that box, so that delta and ratio
//! tracking ([`super::tracking`]) take steps sized to the local density
//! instead of the global maximum.

pub use super::density::Density;
use super::emission::{Emission, EmissionEval, EmitsUnabsorbed};
use crate::accel::{Geometry, Primitive};
use crate::color::Rgb;
use crate::phase::PhaseFunction;
use crate::ray::Ray;
use crate::shapes::{Bounds, Shape, Triangle};
use glam::{IVec3, UVec3, Vec3};
use std::ops::ControlFlow;

/// Extra width, in cells, added around each majorant cell when bounding
/// it, so that a sample rounded across a cell face is still bounded.
const MAJORANT_MARGIN: f32 = 1e-3;

/// Where a volume is.
#[derive(Debug)]
pub enum VolumeRegion {
    /// All of space (only for a uniform density).
    Everywhere,
    Box(Bounds),
    /// The inside of a closed triangle mesh, found by counting crossings.
    Mesh(MeshRegion),
}

/// The interior of a closed (watertight) triangle mesh.
pub struct MeshRegion {
    geometry: Geometry,
}

impl std::fmt::Debug for MeshRegion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshRegion")
            .field("triangles", &self.geometry.primitives())
            .finish()
    }
}

impl MeshRegion {
    pub fn new(triangles: Vec<Triangle>) -> Self {
        let primitives = triangles
            .into_iter()
            .map(|t| Primitive {
                shape: Shape::Triangle(t),
                material: 0,
            })
            .collect();
        Self {
            geometry: Geometry::new(primitives),
        }
    }

    pub fn bounds(&self) -> Bounds {
        self.geometry.bounds()
    }

    /// Appends to `out` the parts of `[t0, t1]` along `ray` inside the
    /// mesh. A point is inside when a ray from it crosses the surface an
    /// odd number of times; crossings closer than a relative 1e-5 are one
    /// (a ray through a shared edge hits both triangles).
    fn intervals(
        &self,
        ray: &Ray,
        t0: f32,
        t1: f32,
        hits: &mut Vec<f32>,
        out: &mut Vec<(f32, f32)>,
    ) {
        hits.clear();
        self.geometry.for_each_hit(ray, f32::INFINITY, |t, _| {
            hits.push(t);
            ControlFlow::Continue(())
        });
        hits.sort_by(f32::total_cmp);
        hits.dedup_by(|b, a| *b - *a <= 1e-5 * a.abs().max(1e-3));
        let mut inside = hits.len() % 2 == 1;
        let mut start = 0.0f32;
        for &t in hits.iter() {
            if inside {
                push_clipped(out, start, t, t0, t1);
            }
            inside = !inside;
            start = t;
        }
        if inside {
            push_clipped(out, start, f32::INFINITY, t0, t1);
        }
    }
}

fn push_clipped(out: &mut Vec<(f32, f32)>, a: f32, b: f32, t0: f32, t1: f32) {
    let (a, b) = (a.max(t0), b.min(t1));
    if a < b {
        out.push((a, b));
    }
}

/// A piece `[t0, t1)` of a ray on which the summed extinction of the
/// volumes in `mask` (bit i: volume i) is at most `majorant` in every
/// channel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MajorantSegment {
    pub t0: f32,
    pub t1: f32,
    pub majorant: f32,
    pub mask: u32,
}

/// The largest density in each cell of a grid over the unit cube.
#[derive(Clone, Debug)]
pub struct MajorantGrid {
    cells: UVec3,
    /// Where the field box starts, and the size of a cell along each axis
    /// (scene units; infinite for a volume filling all space, whose one
    /// cell is never walked).
    origin: Vec3,
    cell_size: Vec3,
    max: Vec<f32>,
    /// Per cell, an absolute lower bound of the majorant (1/scene unit)
    /// where an emission field is positive (empty: none): tracking must
    /// take tentative collisions wherever the medium emits.
    floor: Vec<f32>,
}

/// The box in the unit cube of each cell of a `cells` majorant grid, x
/// fastest, widened by [`MAJORANT_MARGIN`] of a cell on every side (and
/// clamped to the cube), so that a bound over it holds for points rounded
/// across a cell face.
fn majorant_cell_boxes(cells: UVec3) -> impl Iterator<Item = (Vec3, Vec3)> {
    let n = cells.as_vec3();
    (0..cells.z).flat_map(move |z| {
        (0..cells.y).flat_map(move |y| {
            (0..cells.x).map(move |x| {
                let c = UVec3::new(x, y, z).as_vec3();
                let lo = ((c - MAJORANT_MARGIN) / n).max(Vec3::ZERO);
                let hi = ((c + 1.0 + MAJORANT_MARGIN) / n).min(Vec3::ONE);
                (lo, hi)
            })
        })
    })
}

impl MajorantGrid {
    /// The grid of `density` over `field_box`.
    fn new(density: &Density, field_box: &Bounds) -> Self {
        let cells = density.majorant_cells();
        let max = majorant_cell_boxes(cells)
            .map(|(lo, hi)| density.max_in(lo, hi))
            .collect();
        Self {
            cells,
            origin: field_box.min,
            cell_size: field_box.extent() / cells.as_vec3(),
            max,
            floor: Vec::new(),
        }
    }

    /// Raises the majorant floor to `rate` (1/scene unit) in every cell
    /// where `field` may be positive.
    fn add_floor(&mut self, field: &Density, rate: f32) {
        if self.floor.is_empty() {
            self.floor = vec![0.0; self.max.len()];
        }
        for ((lo, hi), floor) in majorant_cell_boxes(self.cells).zip(&mut self.floor) {
            if field.max_in(lo, hi) > 0.0 {
                *floor = floor.max(rate);
            }
        }
    }

    /// The cells of `[t0, t1]` along `ray` (inside the field box), one at
    /// a time.
    fn walk(&self, ray: &Ray, t0: f32, t1: f32) -> CellWalk {
        CellWalk::new(self, ray, t0, t1)
    }

    /// The majorant of cell `index` for extinction `scale` per unit density.
    #[inline]
    fn majorant(&self, index: usize, scale: f32) -> f32 {
        match self.floor.get(index) {
            Some(&floor) => (self.max[index] * scale).max(floor),
            None => self.max[index] * scale,
        }
    }
}

/// The cells of a grid that a piece of a ray crosses, in order (Amanatides
/// & Woo 1987), produced one at a time: tracking that stops at an early
/// collision never walks the rest of the ray.
#[derive(Clone, Debug)]
pub(crate) struct CellWalk {
    cells: IVec3,
    cell: IVec3,
    t_next: [f32; 3],
    t_delta: [f32; 3],
    step: [i32; 3],
    /// Where the next cell's piece starts; past `t1` when the walk is over.
    t: f32,
    t1: f32,
}

impl CellWalk {
    /// The walk over `[t0, t1]` along `ray`, inside `grid`'s field box.
    fn new(grid: &MajorantGrid, ray: &Ray, t0: f32, t1: f32) -> Self {
        let n = grid.cells.as_ivec3();
        let p0 = ray.at(t0) - grid.origin;
        let cell = (p0 / grid.cell_size)
            .floor()
            .as_ivec3()
            .clamp(IVec3::ZERO, n - 1);
        let inverse = ray.direction.recip();
        // Ray length per cell crossed along each axis, signed.
        let per_cell = grid.cell_size * inverse;
        let (mut t_next, mut t_delta, mut step) = ([f32::INFINITY; 3], [f32::INFINITY; 3], [0; 3]);
        for a in 0..3 {
            let face = |c: i32| t0 + (c as f32 * grid.cell_size[a] - p0[a]) * inverse[a];
            if ray.direction[a] > 0.0 {
                t_next[a] = face(cell[a] + 1);
                t_delta[a] = per_cell[a];
                step[a] = 1;
            } else if ray.direction[a] < 0.0 {
                t_next[a] = face(cell[a]);
                t_delta[a] = -per_cell[a];
                step[a] = -1;
            }
        }
        Self {
            cells: n,
            cell,
            t_next,
            t_delta,
            step,
            t: t0,
            t1,
        }
    }

    /// The next cell's index (x fastest) and the piece `[t0, t1)` of the
    /// ray in it; empty pieces (a ray through a cell's edge) are skipped.
    #[inline]
    fn next_cell(&mut self) -> Option<(usize, f32, f32)> {
        while self.t < self.t1 {
            let (t_next, cell) = (self.t_next, self.cell);
            let axis = if t_next[0] <= t_next[1] && t_next[0] <= t_next[2] {
                0
            } else if t_next[1] <= t_next[2] {
                1
            } else {
                2
            };
            let t0 = self.t;
            let t_exit = t_next[axis].min(self.t1);
            // Leaving the grid (or reaching t1) ends the walk.
            self.cell[axis] += self.step[axis];
            self.t_next[axis] += self.t_delta[axis];
            self.t = if t_next[axis] >= self.t1
                || self.cell[axis] < 0
                || self.cell[axis] >= self.cells[axis]
            {
                f32::INFINITY
            } else {
                t_exit
            };
            if t_exit > t0 {
                let n = self.cells;
                let index = (cell.x + n.x * (cell.y + n.y * cell.z)) as usize;
                return Some((index, t0, t_exit));
            }
        }
        None
    }
}

/// A volume's majorant segments along one piece of a ray, produced one at
/// a time ([`Volume::majorant_walk`]).
pub(crate) enum MajorantWalk<'a> {
    /// No segment is left.
    Done,
    /// One segment (a volume filling all space), then none.
    Whole(MajorantSegment),
    /// The majorant grid's cells the piece crosses.
    Cells {
        grid: &'a MajorantGrid,
        walk: CellWalk,
        scale: f32,
        mask: u32,
    },
}

impl Iterator for MajorantWalk<'_> {
    type Item = MajorantSegment;

    #[inline]
    fn next(&mut self) -> Option<MajorantSegment> {
        match self {
            Self::Done => None,
            Self::Whole(segment) => {
                let segment = *segment;
                *self = Self::Done;
                Some(segment)
            }
            Self::Cells {
                grid,
                walk,
                scale,
                mask,
            } => {
                let (index, t0, t1) = walk.next_cell()?;
                Some(MajorantSegment {
                    t0,
                    t1,
                    majorant: grid.majorant(index, *scale),
                    mask: *mask,
                })
            }
        }
    }
}

/// A medium: RGB extinction scale, albedo, phase function, density field
/// and region.
#[derive(Debug)]
pub struct Volume {
    /// Extinction per channel (1/scene unit) where the density is 1.
    pub sigma_t: Rgb,
    /// Single-scattering albedo per channel, ≤ 1.
    pub albedo: Rgb,
    pub phase: PhaseFunction,
    density: Density,
    region: VolumeRegion,
    /// The box the density field is mapped to (the region's bounds).
    field_box: Bounds,
    majorants: MajorantGrid,
    emission: Option<EmissionEval>,
}

impl Volume {
    /// A volume; the error says why it cannot be built (a non-uniform
    /// density needs a bounded region).
    pub fn new(
        sigma_t: Rgb,
        albedo: Rgb,
        phase: PhaseFunction,
        density: Density,
        region: VolumeRegion,
    ) -> Result<Self, String> {
        let field_box = match &region {
            VolumeRegion::Everywhere => {
                if density != Density::Uniform {
                    return Err(
                        "a volume with a non-uniform density needs a `box` or a `mesh`".into(),
                    );
                }
                Bounds {
                    min: Vec3::splat(f32::NEG_INFINITY),
                    max: Vec3::splat(f32::INFINITY),
                }
            }
            VolumeRegion::Box(b) => *b,
            VolumeRegion::Mesh(m) => m.bounds(),
        };
        if matches!(region, VolumeRegion::Mesh(_)) && field_box.extent().min_element() <= 0.0 {
            return Err("the mesh is flat: it encloses no volume".into());
        }
        let majorants = MajorantGrid::new(&density, &field_box);
        Ok(Self {
            sigma_t,
            albedo,
            phase,
            density,
            region,
            field_box,
            majorants,
            emission: None,
        })
    }

    /// The volume emitting `emission` (docs/physics.md §2.5). Where its
    /// emission can be positive but the extinction majorant is 0 (an
    /// emission grid outside the density, or no extinction at all), the
    /// majorant is raised to one tentative collision per majorant cell,
    /// so that tracking finds the emission there (null collisions:
    /// unbiased). Refused for a volume filling all space.
    pub fn with_emission(mut self, emission: Emission) -> Result<Self, String> {
        if matches!(self.region, VolumeRegion::Everywhere) {
            return Err(
                "an emitting medium needs a `box` or a `mesh` (one filling all space would emit without bound)"
                    .into(),
            );
        }
        let colour_field = if emission.color == Rgb::ZERO {
            None
        } else if let Some(field) = &emission.field {
            Some(field.clone())
        } else if self.sigma_t.max_element() <= 0.0 {
            Some(self.density.clone())
        } else {
            None
        };
        // Cycles' blackbody law emits wherever the temperature is
        // positive, and everywhere below intensity 1.
        let hot_field = emission
            .blackbody
            .as_ref()
            .and_then(|b| match b.emits_unabsorbed() {
                EmitsUnabsorbed::Nowhere => None,
                EmitsUnabsorbed::WhereHot => Some(b.temperature.clone()),
                EmitsUnabsorbed::Everywhere => Some(Density::Uniform),
            });
        let rate = 1.0 / self.majorants.cell_size.min_element();
        for field in [colour_field, hot_field].into_iter().flatten() {
            self.majorants.add_floor(&field, rate);
        }
        self.emission = Some(EmissionEval::new(emission));
        Ok(self)
    }

    /// For next event estimation towards the volume's emission
    /// ([`super::emitters`]): its box, its majorant cells and a bound of
    /// the emission in each (x fastest); `None` unless it emits and is
    /// bounded by a box (a mesh region's cells reach outside it).
    pub(crate) fn emission_cells(&self) -> Option<(Bounds, UVec3, Vec<f32>)> {
        let emission = self.emission.as_ref()?;
        let VolumeRegion::Box(bounds) = self.region else {
            return None;
        };
        let cells = self.majorants.cells;
        let sigma_a_max = (self.sigma_t * (Rgb::ONE - self.albedo)).max_element();
        let weights = majorant_cell_boxes(cells)
            .map(|(lo, hi)| {
                let w = emission.bound(lo, hi, &self.density, sigma_a_max);
                if w.is_finite() { w.max(0.0) } else { 0.0 }
            })
            .collect();
        Some((bounds, cells, weights))
    }

    /// The box that bounds the medium (all of space for a uniform
    /// medium everywhere).
    pub fn bounds(&self) -> Bounds {
        self.field_box
    }

    /// Whether the volume emits light.
    pub fn is_emissive(&self) -> bool {
        self.emission.is_some()
    }

    /// The emission coefficient j(x) per channel at a point of the
    /// region, W·sr⁻¹·m⁻² per scene unit (docs/physics.md §2.5); 0 for a
    /// volume that does not emit.
    #[inline]
    pub fn emission_at(&self, x: Vec3) -> Rgb {
        let Some(emission) = &self.emission else {
            return Rgb::ZERO;
        };
        // An emitting volume has a bounded field box.
        let u = (x - self.field_box.min) / self.field_box.extent();
        let density = self.density.eval(u);
        let sigma_a = self.sigma_t * density * (Rgb::ONE - self.albedo);
        emission.eval(u, density, sigma_a)
    }

    /// Extinction σt(x) per channel at a point of the region.
    #[inline]
    pub fn extinction_at(&self, x: Vec3) -> Rgb {
        let density = match self.density {
            // No field coordinates: a volume everywhere has an infinite
            // box, which would map x to NaN.
            Density::Uniform => 1.0,
            _ => self
                .density
                .eval((x - self.field_box.min) / self.field_box.extent()),
        };
        self.sigma_t * density
    }

    /// σt per channel where the volume is homogeneous and does not emit:
    /// its extinction is that constant throughout its region, so its
    /// transmittance over a chord of length ℓ is `exp(−σt·ℓ)` in closed
    /// form and its free flights can be drawn without tracking
    /// ([`super::tracking`]). `None` for a density field or an emitting
    /// volume (whose emission tracking must find at its tentative
    /// collisions).
    #[inline]
    pub fn uniform_extinction(&self) -> Option<Rgb> {
        (matches!(self.density, Density::Uniform) && self.emission.is_none())
            .then_some(self.sigma_t)
    }

    /// The largest extinction in any channel anywhere in the volume.
    pub fn max_extinction(&self) -> f32 {
        let peak = self.majorants.max.iter().copied().fold(0.0, f32::max);
        peak * self.sigma_t.max_element()
    }

    /// The box the density field is mapped to: the region's bounds
    /// (infinite for a volume everywhere).
    pub fn field_box(&self) -> Bounds {
        self.field_box
    }

    /// Whether the volume fills all of space.
    pub fn is_unbounded(&self) -> bool {
        matches!(self.region, VolumeRegion::Everywhere)
    }

    /// The majorant segments of `[t0, t1]` along `ray` in this volume,
    /// tagged with `mask`, produced one at a time; `None` for a mesh
    /// region, whose inside may be several pieces of the ray
    /// ([`Volume::majorant_segments`] collects those).
    pub(crate) fn majorant_walk(
        &self,
        ray: &Ray,
        t0: f32,
        t1: f32,
        mask: u32,
    ) -> Option<MajorantWalk<'_>> {
        let scale = self.sigma_t.max_element();
        if scale <= 0.0 && self.majorants.floor.is_empty() {
            return Some(MajorantWalk::Done);
        }
        match &self.region {
            VolumeRegion::Everywhere => Some(if t0 < t1 {
                MajorantWalk::Whole(MajorantSegment {
                    t0,
                    t1,
                    majorant: scale,
                    mask,
                })
            } else {
                MajorantWalk::Done
            }),
            // The field box is the box.
            VolumeRegion::Box(_) => Some(match self.field_box.clip_ray(ray, t0, t1) {
                Some((a, b)) if a < b => self.cells_walk(ray, a, b, scale, mask),
                _ => MajorantWalk::Done,
            }),
            VolumeRegion::Mesh(_) => None,
        }
    }

    /// The walk over the majorant cells of `[a, b]`, inside the field box.
    fn cells_walk(&self, ray: &Ray, a: f32, b: f32, scale: f32, mask: u32) -> MajorantWalk<'_> {
        MajorantWalk::Cells {
            grid: &self.majorants,
            walk: self.majorants.walk(ray, a, b),
            scale,
            mask,
        }
    }

    /// Appends the majorant segments of `[t0, t1]` along `ray` in this
    /// volume, tagged with `mask`; `scratch` holds a mesh region's pieces.
    pub(crate) fn majorant_segments(
        &self,
        ray: &Ray,
        t0: f32,
        t1: f32,
        mask: u32,
        scratch: &mut RegionScratch,
        out: &mut Vec<MajorantSegment>,
    ) {
        if let Some(walk) = self.majorant_walk(ray, t0, t1, mask) {
            out.extend(walk);
            return;
        }
        // Only a mesh region has no single walk.
        let VolumeRegion::Mesh(m) = &self.region else {
            return;
        };
        scratch.intervals.clear();
        m.intervals(ray, t0, t1, &mut scratch.hits, &mut scratch.intervals);
        let scale = self.sigma_t.max_element();
        for &(a, b) in &scratch.intervals {
            // A mesh's intervals may reach past its box by rounding.
            if let Some((a, b)) = self.field_box.clip_ray(ray, a, b).filter(|(a, b)| a < b) {
                out.extend(self.cells_walk(ray, a, b, scale, mask));
            }
        }
    }
}

/// Reusable buffers for region queries.
#[derive(Default)]
pub(crate) struct RegionScratch {
    intervals: Vec<(f32, f32)>,
    hits: Vec<f32>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::media::noise::SmokeNoise;

    fn ray(origin: Vec3, direction: Vec3) -> Ray {
        Ray {
            origin,
            direction: direction.normalize(),
        }
    }

    #[test]
    fn majorant_segments_tile_the_clipped_ray_and_bound_the_density() {
        let noise = SmokeNoise {
            frequency: 2.0,
            octaves: 3,
            bias: 0.3,
            seed: 4,
        };
        let region = VolumeRegion::Box(Bounds::new(Vec3::splat(-1.0), Vec3::splat(1.0)));
        let volume = Volume::new(
            Rgb::new(2.0, 3.0, 1.0),
            Rgb::ONE,
            PhaseFunction::Isotropic,
            Density::Noise(noise),
            region,
        )
        .unwrap();
        let r = ray(Vec3::new(-3.0, -0.2, 0.1), Vec3::new(1.0, 0.3, 0.05));
        let mut out = Vec::new();
        volume.majorant_segments(&r, 0.0, 10.0, 1, &mut RegionScratch::default(), &mut out);
        assert!(out.len() > 4, "{} segments", out.len());
        for pair in out.windows(2) {
            assert!((pair[0].t1 - pair[1].t0).abs() < 1e-5);
        }
        for s in &out {
            for i in 0..=16 {
                let t = s.t0 + (s.t1 - s.t0) * i as f32 / 16.0;
                let sigma = volume.extinction_at(r.at(t)).max_element();
                assert!(
                    sigma <= s.majorant * (1.0 + 1e-5),
                    "{sigma} > {}",
                    s.majorant
                );
            }
        }
    }

    /// A box region is walked lazily and a mesh region collected piece by
    /// piece; over a cube both give the same segments.
    #[test]
    fn a_box_walked_lazily_and_a_cube_mesh_give_the_same_segments() {
        let noise = SmokeNoise {
            frequency: 3.0,
            octaves: 2,
            bias: 0.2,
            seed: 9,
        };
        let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let corner = |i: u32| {
            Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        };
        // Each face of the cube as two triangles.
        let faces = [
            [0, 1, 3, 2],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 3, 7, 5],
        ];
        let triangles = faces
            .iter()
            .flat_map(|&[a, b, c, d]| {
                [
                    Triangle::new(corner(a), corner(b), corner(c)).unwrap(),
                    Triangle::new(corner(a), corner(c), corner(d)).unwrap(),
                ]
            })
            .collect();
        let volume = |region| {
            let density = Density::Noise(noise);
            Volume::new(
                Rgb::ONE,
                Rgb::ONE,
                PhaseFunction::Isotropic,
                density,
                region,
            )
            .unwrap()
        };
        let boxed = volume(VolumeRegion::Box(Bounds::new(lo, hi)));
        let meshed = volume(VolumeRegion::Mesh(MeshRegion::new(triangles)));
        assert!(
            boxed
                .majorant_walk(&ray(Vec3::ZERO, Vec3::X), 0.0, 1.0, 1)
                .is_some()
        );
        assert!(
            meshed
                .majorant_walk(&ray(Vec3::ZERO, Vec3::X), 0.0, 1.0, 1)
                .is_none()
        );
        let rays = [
            (Vec3::new(-3.0, -0.2, 0.1), Vec3::new(1.0, 0.3, 0.05), 0.0),
            (Vec3::new(0.3, 0.2, -0.4), Vec3::new(-0.2, 1.0, 0.7), 0.0),
            (Vec3::new(2.5, 2.0, 1.5), Vec3::new(-1.0, -0.9, -0.6), 1.0),
        ];
        let mut scratch = RegionScratch::default();
        for (origin, direction, t0) in rays {
            let r = ray(origin, direction);
            let (mut a, mut b) = (Vec::new(), Vec::new());
            boxed.majorant_segments(&r, t0, 10.0, 1, &mut scratch, &mut a);
            meshed.majorant_segments(&r, t0, 10.0, 1, &mut scratch, &mut b);
            assert!(
                a.len() > 3 && a.len() == b.len(),
                "{} and {}",
                a.len(),
                b.len()
            );
            for (x, y) in a.iter().zip(&b) {
                assert!((x.t0 - y.t0).abs() < 1e-4 && (x.t1 - y.t1).abs() < 1e-4);
                assert_eq!(x.majorant, y.majorant);
            }
        }
    }

    #[test]
    fn mesh_region_is_the_inside_of_a_closed_mesh() {
        // A tetrahedron with its apex up.
        let (a, b, c, d) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 2.0),
            Vec3::new(0.0, 2.0, 0.0),
        );
        let faces = [(a, b, c), (a, b, d), (a, c, d), (b, c, d)];
        let mesh = MeshRegion::new(
            faces
                .iter()
                .map(|&(p, q, r)| Triangle::new(p, q, r).unwrap())
                .collect(),
        );
        // Along x at y = z = 0.25 the tetrahedron x + y + z ≤ 2 spans
        // x ∈ [0, 1.5].
        let r = ray(Vec3::new(-1.0, 0.25, 0.25), Vec3::X);
        let (mut hits, mut out) = (Vec::new(), Vec::new());
        mesh.intervals(&r, 0.0, f32::INFINITY, &mut hits, &mut out);
        assert_eq!(out.len(), 1);
        assert!((out[0].0 - 1.0).abs() < 1e-5 && (out[0].1 - 2.5).abs() < 1e-5);
        // From inside, the interval starts at the origin.
        let inside = ray(Vec3::new(0.5, 0.25, 0.25), Vec3::X);
        out.clear();
        mesh.intervals(&inside, 0.0, f32::INFINITY, &mut hits, &mut out);
        assert_eq!(out.len(), 1);
        assert!(out[0].0 == 0.0 && (out[0].1 - 1.0).abs() < 1e-5);
    }
}
