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
    fn new(density: &Density) -> Self {
        let cells = density.majorant_cells();
        let max = majorant_cell_boxes(cells)
            .map(|(lo, hi)| density.max_in(lo, hi))
            .collect();
        Self {
            cells,
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

    /// Appends the segments of `[t0, t1]` along `ray` (inside `bounds`,
    /// which the grid covers) with each cell's maximum times `scale`,
    /// walking the cells in order (Amanatides & Woo 1987).
    #[allow(clippy::too_many_arguments)]
    fn segments(
        &self,
        bounds: &Bounds,
        ray: &Ray,
        t0: f32,
        t1: f32,
        scale: f32,
        mask: u32,
        out: &mut Vec<MajorantSegment>,
    ) {
        let n = self.cells.as_ivec3();
        let per_unit = self.cells.as_vec3() / bounds.extent();
        let g0 = (ray.at(t0) - bounds.min) * per_unit;
        let mut cell = g0.floor().as_ivec3().clamp(IVec3::ZERO, n - 1);
        let d = ray.direction * per_unit;
        let (mut t_next, mut t_delta, mut step) = ([f32::INFINITY; 3], [f32::INFINITY; 3], [0; 3]);
        for a in 0..3 {
            if d[a] > 0.0 {
                t_next[a] = t0 + ((cell[a] + 1) as f32 - g0[a]) / d[a];
                t_delta[a] = 1.0 / d[a];
                step[a] = 1;
            } else if d[a] < 0.0 {
                t_next[a] = t0 + (cell[a] as f32 - g0[a]) / d[a];
                t_delta[a] = -1.0 / d[a];
                step[a] = -1;
            }
        }
        let mut t = t0;
        loop {
            let axis = if t_next[0] <= t_next[1] && t_next[0] <= t_next[2] {
                0
            } else if t_next[1] <= t_next[2] {
                1
            } else {
                2
            };
            let t_exit = t_next[axis].min(t1);
            if t_exit > t {
                let index = (cell.x + n.x * (cell.y + n.y * cell.z)) as usize;
                out.push(MajorantSegment {
                    t0: t,
                    t1: t_exit,
                    majorant: match self.floor.get(index) {
                        Some(&floor) => (self.max[index] * scale).max(floor),
                        None => self.max[index] * scale,
                    },
                    mask,
                });
            }
            if t_next[axis] >= t1 {
                return;
            }
            t = t_exit;
            cell[axis] += step[axis];
            if cell[axis] < 0 || cell[axis] >= n[axis] {
                return;
            }
            t_next[axis] += t_delta[axis];
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
        let majorants = MajorantGrid::new(&density);
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
        let cell = self.field_box.extent() / self.majorants.cells.as_vec3();
        let rate = 1.0 / cell.min_element();
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

    /// Appends the majorant segments of `[t0, t1]` along `ray` in this
    /// volume, tagged with `mask`; `intervals` and `hits` are scratch.
    pub(crate) fn majorant_segments(
        &self,
        ray: &Ray,
        t0: f32,
        t1: f32,
        mask: u32,
        scratch: &mut RegionScratch,
        out: &mut Vec<MajorantSegment>,
    ) {
        let scale = self.sigma_t.max_element();
        if scale <= 0.0 && self.majorants.floor.is_empty() {
            return;
        }
        scratch.intervals.clear();
        match &self.region {
            VolumeRegion::Everywhere => {
                if t0 < t1 {
                    out.push(MajorantSegment {
                        t0,
                        t1,
                        majorant: scale,
                        mask,
                    });
                }
                return;
            }
            VolumeRegion::Box(b) => {
                if let Some((a, b)) = b.clip_ray(ray, t0, t1) {
                    push_clipped(&mut scratch.intervals, a, b, t0, t1);
                }
            }
            VolumeRegion::Mesh(m) => {
                m.intervals(ray, t0, t1, &mut scratch.hits, &mut scratch.intervals);
            }
        }
        for &(a, b) in &scratch.intervals {
            // A mesh's intervals may reach past its box by rounding.
            if let Some((a, b)) = self.field_box.clip_ray(ray, a, b).filter(|(a, b)| a < b) {
                self.majorants
                    .segments(&self.field_box, ray, a, b, scale, mask, out);
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
