//! Light tracing: paths from point and spot lights, each scattering event
//! connected to the camera — how `volpath` gets caustics.
//!
//! A camera path cannot reach a point or spot light through a refractive
//! surface: NEE's shadow ray is blocked by it, and a sampled direction
//! never hits a point. So every path whose light end starts `light →
//! dielectric …` (the beam a glass sphere focuses into the fog) is missing
//! from `volpath`'s camera paths. Traced from the light, those paths are
//! easy: emit, refract through the glass (Fresnel-chosen reflection or
//! refraction), and at every later scattering event in a medium or on a
//! diffuse surface connect to the camera through its importance
//! ([`crate::camera::Projection`]).
//!
//! [`LightPaths::Caustic`] keeps exactly those paths — at least one
//! specular event before the first scattering — so it complements the
//! camera paths without overlap. [`LightPaths::All`] keeps every path; it
//! is a complete, independent estimator of everything lit by point and
//! spot lights, used to validate the measurement against `volpath`.
//!
//! Not covered by either side: light seen through a dielectric after a
//! specular chain (light → glass → fog → glass → camera), and point
//! lights seen in mirrors — connections through specular surfaces.

use super::lighting::{TRACKING_STREAM, media_transmittance};
use super::scatterer::Scatterer;
use super::surfaces::{MAX_GLASS_CROSSINGS, SolidDepth, SurfaceNormals, refract_or_reflect};
use super::volpath::{MAX_PATH_EVENTS, survives_roulette};
use crate::camera::Camera;
use crate::color::Rgb;
use crate::exact_sum::ExactRgb;
use crate::footprint::Footprint;
use crate::materials::{Material, SurfaceEvent};
use crate::media::free_flight;
use crate::media::tracking::{Collision, FlightOptions, VolumeTracker};
use crate::phase::PhaseFunction;
use crate::ray::{Ray, offset_origin};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::visibility::RayCounts;
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use std::ops::{ControlFlow, Range};

/// Which light paths to trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightPaths {
    /// Only paths that meet a dielectric before they first scatter.
    Caustic,
    /// Every path.
    All,
}

/// Paths are traced in blocks of this many, in parallel; each block
/// returns its splats, added to the film in exact fixed point
/// ([`ExactRgb`]), so the film depends on nothing but the set of paths
/// traced: not on the thread count, the scheduling, or how the paths were
/// divided among tiles, passes and machines.
const BLOCK: u64 = 1024;

/// Blocks traced in parallel before their splats are added to the film
/// (bounds the splats held in memory).
const BLOCKS_PER_BATCH: u64 = 64;

/// Seed offset of the light paths' Sobol sequence (distinct from the
/// camera samples' pixel sequences).
const LIGHT_SEED: u64 = 0x5eed_1197;

/// Whether the scene has light that only light tracing delivers: a point
/// or spot light and a dielectric.
pub fn has_caustics(scene: &Scene) -> bool {
    scene.lights.iter().any(|l| l.position().is_some())
        && scene.materials.iter().any(Material::refracts)
}

/// Traces `paths` light paths (split over the lights uniformly) and
/// returns the image of their camera connections, in radiance: each pixel
/// is the sum of its connections divided by `paths`.
pub fn trace(
    scene: &Scene,
    camera: &Camera,
    (width, height): (u32, u32),
    paths: u64,
    seed: u64,
    max_depth: u32,
    which: LightPaths,
) -> (Vec<Rgb>, RayCounts) {
    let mut sums = vec![ExactRgb::ZERO; (width * height) as usize];
    let (counts, _) = trace_paths(
        scene,
        camera,
        width,
        0..paths,
        seed,
        max_depth,
        which,
        &mut sums,
    );
    let scale = 1.0 / paths.max(1) as f64;
    (
        sums.iter()
            .map(|s| (s.to_dvec3() * scale).as_vec3())
            .collect(),
        counts,
    )
}

/// Traces the light paths with global indices `paths` and adds their
/// camera connections to `sums` (the full image's pixels, row-major,
/// `width` wide; unnormalised: divide by the number of paths). Path `i`
/// is the `i`-th point of one Sobol sequence over all paths, so disjoint
/// index ranges are disjoint parts of one stratified set, and the sums of
/// any division of a range into sub-ranges add up exactly to the range's.
/// Returns the rays traced and how many connections were dropped as
/// non-finite.
#[allow(clippy::too_many_arguments)]
pub fn trace_paths(
    scene: &Scene,
    camera: &Camera,
    width: u32,
    paths: Range<u64>,
    seed: u64,
    max_depth: u32,
    which: LightPaths,
    sums: &mut [ExactRgb],
) -> (RayCounts, u64) {
    let emitters: Vec<usize> = (0..scene.lights.len())
        .filter(|&i| scene.lights[i].position().is_some())
        .collect();
    let mut counts = RayCounts::default();
    let mut dropped = 0u64;
    if emitters.is_empty() || paths.is_empty() {
        return (counts, dropped);
    }
    let tracer = Tracer {
        scene,
        camera,
        width,
        emitters: &emitters,
        // The same guard as `volpath`'s against endless albedo-1 walks.
        max_depth: max_depth.min(MAX_PATH_EVENTS),
        which,
    };
    let batch = BLOCK * BLOCKS_PER_BATCH;
    let mut batch_start = paths.start;
    while batch_start < paths.end {
        let batch_end = paths.end.min(batch_start.saturating_add(batch));
        let blocks: Vec<(Vec<Splat>, RayCounts)> = (batch_start..batch_end)
            .step_by(BLOCK as usize)
            .collect::<Vec<u64>>()
            .into_par_iter()
            .map(|first| {
                let mut splats = Vec::new();
                let mut counts = RayCounts::default();
                for index in first..batch_end.min(first + BLOCK) {
                    // One Sobol sequence over all paths: stratified
                    // emission. Indices past 2³² continue in further
                    // scrambled sequences.
                    let mut sampler =
                        PixelSampler::new(seed ^ LIGHT_SEED, index >> 32, index as u32);
                    tracer.trace_path(&mut sampler, &mut splats, &mut counts);
                }
                (splats, counts)
            })
            .collect();
        for (splats, c) in blocks {
            for (pixel, value) in splats {
                if value.is_finite() {
                    sums[pixel as usize].add(value);
                } else {
                    dropped += 1;
                }
            }
            counts.camera += c.camera;
            counts.shadow += c.shadow;
        }
        batch_start = batch_end;
    }
    (counts, dropped)
}

/// A camera connection: the index of its pixel and its contribution.
type Splat = (u32, Rgb);

struct Tracer<'a> {
    scene: &'a Scene,
    camera: &'a Camera,
    width: u32,
    emitters: &'a [usize],
    max_depth: u32,
    which: LightPaths,
}

impl Tracer<'_> {
    fn trace_path(
        &self,
        sampler: &mut PixelSampler,
        splats: &mut Vec<Splat>,
        counts: &mut RayCounts,
    ) {
        let scene = self.scene;
        let n = self.emitters.len();
        let pick = ((sampler.next_1d() * n as f32) as usize).min(n - 1);
        let u = sampler.next_2d();
        // Point and spot lights take only the direction's dimensions.
        let Some(emitted) = scene.lights[self.emitters[pick]].sample_le(Vec2::ZERO, u, 0.0) else {
            return;
        };
        let (mut ray, mut beta) = (emitted.ray, emitted.beta);
        beta *= n as f32;
        let mut tracker = VolumeTracker::new(sampler.stream(TRACKING_STREAM));
        let mut solids = SolidDepth::default();
        let (mut depth, mut crossings) = (0u32, 0u32);
        // Whether a specular event came before any scattering.
        let mut caustic = false;
        loop {
            counts.camera += 1;
            let hit = scene.intersect(&ray, f32::INFINITY);
            let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
            let event = if solids.inside() {
                // Inside a solid the path crosses its absorbing inside.
                beta *= solids.transmittance(t_hit);
                MediumEvent::None
            } else {
                medium_event(scene, &ray, t_hit, sampler, &mut tracker, &mut beta)
            };
            if let MediumEvent::Absorbed = event {
                return;
            }
            if let MediumEvent::Scatter(t, phase) = event {
                if !self.scattering_allowed(caustic) || depth >= self.max_depth {
                    return;
                }
                depth += 1;
                let x = ray.at(t);
                let scatterer = Scatterer::Medium {
                    phase,
                    arriving: ray.direction,
                };
                let lens = self.camera.lens_sample(sampler);
                self.connect(x, lens, &scatterer, beta, &mut tracker, splats, counts);
                let (direction, _) = phase.sample(ray.direction, sampler.next_2d());
                ray = Ray {
                    origin: x,
                    direction,
                };
                if !survives_roulette(&mut beta, depth, sampler) {
                    return;
                }
                continue;
            }
            let Some(hit) = hit else { return };
            let p = ray.at(hit.t);
            let geometric_normal = scene.geometry.normal(hit.primitive, p);
            // Light paths cross glass even where camera rays draw it opaque,
            // and end on any emitter, whichever side they meet, unless it
            // also reflects.
            match scene
                .material(hit.primitive)
                .event(true, false)
                .without_emission()
            {
                SurfaceEvent::Emitter { .. } => return,
                SurfaceEvent::Pane { transmittance } => {
                    crossings += 1;
                    if crossings > MAX_GLASS_CROSSINGS {
                        return;
                    }
                    beta *= transmittance;
                    ray.origin = offset_origin(p, geometric_normal, ray.direction);
                }
                SurfaceEvent::Interface(interface) => {
                    if depth >= self.max_depth {
                        return;
                    }
                    depth += 1;
                    caustic = true;
                    ray = refract_or_reflect(
                        &ray,
                        p,
                        geometric_normal,
                        interface,
                        sampler,
                        &mut solids,
                    );
                }
                SurfaceEvent::Reflector(surface) => {
                    if !self.scattering_allowed(caustic) || depth >= self.max_depth {
                        return;
                    }
                    let surface = scene.surface_at(surface, hit.primitive, p, Footprint::POINT);
                    depth += 1;
                    let normal = if geometric_normal.dot(ray.direction) < 0.0 {
                        geometric_normal
                    } else {
                        -geometric_normal
                    };
                    // Light paths shade with the geometric normal: the
                    // adjoint of interpolated normals (Veach 1997 §5.3)
                    // is not applied.
                    if surface.diffuse != Rgb::ZERO {
                        let normals = SurfaceNormals::flat(normal);
                        let diffuse = Scatterer::Surface { surface, normals };
                        let lens = self.camera.lens_sample(sampler);
                        self.connect(p, lens, &diffuse, beta, &mut tracker, splats, counts);
                    }
                    // Continue by the lobes, as `volpath` does.
                    if surface.diffuse_probability().is_none() {
                        return;
                    }
                    let choice = sampler.next_1d();
                    let u = sampler.next_2d();
                    let Some(sample) = surface.sample(ray.direction, normal, choice, u) else {
                        return;
                    };
                    beta *= sample.weight;
                    let direction = sample.direction;
                    ray = Ray {
                        origin: offset_origin(p, geometric_normal, direction),
                        direction,
                    };
                    if !survives_roulette(&mut beta, depth, sampler) {
                        return;
                    }
                }
            }
        }
    }

    /// Whether a scattering event may be connected (and the path go on):
    /// caustic tracing stops at a first scattering with no specular event
    /// before it, which the camera paths estimate.
    fn scattering_allowed(&self, caustic: bool) -> bool {
        caustic || self.which == LightPaths::All
    }

    /// Splats the light scattered at `x` towards the camera through the
    /// lens point `lens` picks: `β·f·T·W/d²`, f the phase function or
    /// `ρ/π·cos` towards the camera, T everything between (thin glass,
    /// and the media by [`media_transmittance`]; zero if blocked), W and d
    /// from [`Camera::project`].
    #[allow(clippy::too_many_arguments)]
    fn connect(
        &self,
        x: Vec3,
        lens: Vec2,
        scatterer: &Scatterer,
        beta: Rgb,
        tracker: &mut VolumeTracker,
        splats: &mut Vec<Splat>,
        counts: &mut RayCounts,
    ) {
        let Some(projection) = self.camera.project(x, lens) else {
            return;
        };
        let to_camera = projection.to_camera;
        let Some((f, _)) = scatterer.scatter(to_camera) else {
            return;
        };
        let origin = scatterer.origin(x, to_camera);
        counts.shadow += 1;
        let distance = projection.distance;
        let glass = self.glass_towards_camera(origin, to_camera, distance);
        if glass == Rgb::ZERO {
            return;
        }
        let media = media_transmittance(self.scene, tracker, x, origin, to_camera, distance);
        let value = beta * f * glass * media * (projection.importance / (distance * distance));
        let pixel = projection.film.floor().as_uvec2();
        splats.push((pixel.y * self.width + pixel.x, value));
    }

    /// Transmittance of thin glass between `origin` and the camera; zero
    /// if anything else is in the way (a dielectric included: light is
    /// not connected through refraction).
    fn glass_towards_camera(&self, origin: Vec3, direction: Vec3, distance: f32) -> Rgb {
        let scene = self.scene;
        let ray = Ray { origin, direction };
        let mut tint = Rgb::ONE;
        let opaque_glass = scene.glass.opaque_to_camera;
        scene
            .geometry
            .for_each_hit(&ray, distance * (1.0 - 1e-4), |t, primitive| {
                if scene.has_coverage() && scene.passes(primitive, &ray, t) {
                    return ControlFlow::Continue(());
                }
                match scene.material(primitive).event(true, opaque_glass) {
                    SurfaceEvent::Pane { transmittance } => {
                        tint *= transmittance;
                        ControlFlow::Continue(())
                    }
                    _ => {
                        tint = Rgb::ZERO;
                        ControlFlow::Break(())
                    }
                }
            });
        tint
    }
}

/// What a light path meets in the media before its next surface.
enum MediumEvent<'s> {
    None,
    /// A real scattering event at `t` in a medium with this phase function.
    Scatter(f32, &'s PhaseFunction),
    Absorbed,
}

/// The first real event in the fog or the volumes before `t_hit`; `beta`
/// is weighted (albedo for the fog, spectral tracking for volumes).
fn medium_event<'s>(
    scene: &'s Scene,
    ray: &Ray,
    t_hit: f32,
    sampler: &mut PixelSampler,
    tracker: &mut VolumeTracker,
    beta: &mut Rgb,
) -> MediumEvent<'s> {
    let u = sampler.next_1d();
    let fog_event = scene.fog.as_ref().and_then(|fog| {
        let (a, b) = fog.interval(ray, 0.0, t_hit)?;
        if fog.sigma_t <= 0.0 {
            return None;
        }
        free_flight(fog.sigma_t, a, b, u).map(|t| (t, fog))
    });
    let t_end = fog_event.map_or(t_hit, |(t, _)| t);
    match tracker.sample_collision(
        &scene.volumes,
        ray,
        0.0,
        t_end,
        beta,
        FlightOptions::default(),
    ) {
        Collision::Scatter { t, volume } => MediumEvent::Scatter(t, &scene.volumes[volume].phase),
        Collision::Absorbed => MediumEvent::Absorbed,
        Collision::Escaped => match fog_event {
            Some((t, fog)) => {
                *beta *= fog.albedo;
                MediumEvent::Scatter(t, &fog.phase)
            }
            None => MediumEvent::None,
        },
    }
}
