//! Light-vertex connections in uniform volumes: the fog's connections
//! ([`super::connections`]) where the medium is a set of uniform
//! `[[media]]` volumes instead, such as chromatic fog, whose extinction
//! differs by channel and so cannot be `[fog]`.
//!
//! A light subpath's first event y1 is a collision drawn by one-sample
//! spectral MIS ([`LightSubpath`]), and a camera-path collision x is
//! joined to it ([`connect_in_volumes`]). The connection competes by the
//! balance heuristic with the camera path reaching y1 from x and there
//! sampling the light by NEE or hitting it by phase sampling, exactly as
//! in the fog, in the same solid-angle terms (mis.rs). What differs is the
//! flights' densities: each path draws its flight by its own throughput's
//! channels, so the camera's density of reaching y1 and the subpath's of
//! starting it depend on paths the other strategies do not know. The
//! weights use instead the densities of flights whose channels weigh
//! evenly ([`VolumeTracker::even_flight_density`]), the same wherever a
//! strategy computes them: the balance heuristic needs weights that sum
//! to one over the strategies for every path, not the strategies' own
//! densities (Veach 1997 §9.2.2), while each estimate divides by the
//! density it was really drawn with (its throughput's weights). Only
//! first light vertices, and only from camera collisions (surfaces do not
//! connect to them).

use super::Volpath;
use super::light_subpaths::LightSubpath;
use super::mis::{FogEventDensities, LightVertexDensity, finite_density};
use crate::color::Rgb;
use crate::light_groups::LightGroup;
use crate::lights::Light;
use crate::media::tracking::VolumeTracker;
use crate::phase::PhaseFunction;
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::visibility::RayCounts;
use glam::Vec3;

/// The volume density with which a camera path reaches the collision at
/// `t` along `ray` from the ray's origin, a vertex that connected to
/// light vertices and sampled the ray's direction with density `p_dir`:
/// `p_dir·p_flight(t)/t²`, the flight's density with even channel
/// weights. `None` if the origin did not connect (`p_dir` is `None`).
pub(super) fn reached_density(
    scene: &Scene,
    tracker: &mut VolumeTracker,
    ray: &Ray,
    t: f32,
    p_dir: Option<f32>,
) -> Option<f32> {
    let p_dir = p_dir?;
    let p_flight = tracker.even_flight_density(&scene.volumes, ray, t);
    (t > 0.0).then(|| p_dir * p_flight / (t * t))
}

/// The light-vertex connection's density for the collision `y`, lit from
/// `y0` on `light`, relative to the camera path's `reached` (from
/// [`reached_density`]), in the solid-angle terms of the balance
/// heuristic at a collision: `p_y/reached`, `p_y` the light vertex's
/// [`LightVertexDensity::in_volumes`]. Zero if the camera path's vertex
/// before y did not connect, for lights that start no subpaths, and
/// where no subpath reaches y.
pub(super) fn connection_term(
    scene: &Scene,
    tracker: &mut VolumeTracker,
    light: &Light,
    y0: Vec3,
    y: Vec3,
    reached: Option<f32>,
) -> f32 {
    let Some(reached) = reached.filter(|r| *r > 0.0) else {
        return 0.0;
    };
    if !light.is_flat_emitter() {
        return 0.0;
    }
    LightVertexDensity::in_volumes(scene, tracker, light, y0, y)
        .map_or(0.0, |v| finite_density(v.density / reached))
}

/// A camera-path collision that connects: where it is, the direction the
/// path arrived along, and the phase function of the volume that
/// scattered there.
pub(super) struct CollisionVertex<'a> {
    pub x: Vec3,
    pub arriving: Vec3,
    pub phase: &'a PhaseFunction,
}

/// The connection at the camera collision `at`: a light subpath chosen
/// uniformly from the pass's pool, its first collision y1 joined to x.
/// Returns the subpath's light group and the MIS-weighted radiance it
/// brings (to be multiplied by the path's throughput at x, which holds
/// x's scattering coefficient):
/// `p(x)·T(x, y1)/|x − y1|² · p(y1) · β₁ · w`, β₁ the subpath's
/// throughput at y1 (`Le·cos θ₀·n_q/(p_pos·p_dir)` times its flight's
/// `σs·T/p`).
pub(super) fn connect_in_volumes(
    integrator: &Volpath,
    scene: &Scene,
    at: &CollisionVertex,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
) -> (LightGroup, Rgb) {
    let Some(subpath) = integrator.light_subpaths.choose(sampler.next_1d()) else {
        return (LightGroup::OTHER, Rgb::ZERO);
    };
    let light = subpath_light(integrator, scene, at, subpath, counts, tracker);
    (subpath.group, light)
}

/// [`connect_in_volumes`]'s light from the chosen `subpath`.
fn subpath_light(
    integrator: &Volpath,
    scene: &Scene,
    at: &CollisionVertex,
    subpath: &LightSubpath,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
) -> Rgb {
    let Some(volume) = subpath.volume else {
        return Rgb::ZERO;
    };
    let to_y = subpath.y1 - at.x;
    let distance = to_y.length();
    if distance.is_nan() || distance <= 0.0 {
        return Rgb::ZERO;
    }
    let omega = to_y / distance;
    let f_x = at.phase.eval(omega.dot(at.arriving));
    if f_x <= 0.0 {
        return Rgb::ZERO;
    }
    let ray = Ray {
        origin: at.x,
        direction: omega,
    };
    counts.shadow += 1;
    if scene.occluded(&ray, distance) {
        return Rgb::ZERO;
    }
    // Phase sampling at x draws ω with density p(x): the camera path's
    // volume density of y1, against which the connection is weighed.
    let reached = reached_density(scene, tracker, &ray, distance, Some(f_x));
    let Some(at_y1) = subpath.at_y1 else {
        return Rgb::ZERO;
    };
    let Some(reached) = reached.filter(|r| *r > 0.0) else {
        return Rgb::ZERO;
    };
    let connection = finite_density(at_y1.density / reached);
    // Light arrives at y1 along the subpath's direction and turns to x.
    let phase_y1 = scene.volumes[volume]
        .phase
        .eval(-subpath.direction.dot(omega));
    let total = FogEventDensities::new(
        integrator.strategies,
        subpath.p_omega,
        phase_y1,
        0.0,
        connection,
    )
    .total();
    if total.is_nan() || total <= 0.0 {
        return Rgb::ZERO;
    }
    let transmittance = tracker.transmittance(&scene.volumes, &ray, 0.0, distance);
    subpath.emitted * transmittance * (f_x * phase_y1 * (connection / total))
        / (distance * distance)
}
