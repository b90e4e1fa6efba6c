//! Light-vertex connections: the first (and second) fog events of light
//! subpaths started on quad lights
//! ([`LightSubpaths`](super::LightSubpaths)) joined to a camera-path
//! vertex ([`connect_light_vertex`]).

use super::Volpath;
use super::light_subpaths::LightSubpath;
use super::mis::FogEventDensities;
use super::segment::{Connections, FogSegment};
use super::segment_weights::segment_term;
use crate::color::Rgb;
use crate::integrators::Scatterer;
use crate::light_groups::LightGroup;
use crate::media::Fog;
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::visibility::RayCounts;
use glam::Vec3;

/// Light-vertex connections at the camera-path vertex `at.x` (a fog event
/// or a Lambertian surface point): a light subpath is chosen uniformly
/// from the pass's pool ([`LightSubpaths`](super::LightSubpaths)), its
/// first fog event y1 is connected to x, and, if `at.twice`, its second
/// y2 as well.
/// Returns the subpath's light group and the MIS-weighted radiance both
/// bring to the path (to be multiplied by the path's throughput at x,
/// which holds a fog event's albedo but not a surface's BRDF).
///
/// Why: fog right next to an area light is lit by a large solid angle of
/// it and glows brightly. Camera paths reach that glow only when a random
/// walk happens to pass close to the lamp — rare, and then worth a lot:
/// the fireflies of multiply scattered light. Light subpaths start there,
/// so their first events sample the glow where it is brightest. The
/// first connection competes, by the balance heuristic, with NEE at y1,
/// the equiangular sample on x's continuation segment, and the
/// phase-sampled hit from y1; each of those adds its density
/// ([`FogSegment::connection_term`]) when the segment starts at a vertex
/// that connected. The second does the same one vertex further: the
/// camera path reaching y2 from x and then generating (y1, y0) by any of
/// those strategies ([`FogSegment::second_vertex_term`]); it catches
/// paths that wander into the glow twice. The connections' own
/// 1/|x − y|² is tamed the same way: near x, sampling the continuation
/// from x dominates the weights.
pub(super) fn connect_light_vertex<'a>(
    integrator: &Volpath<'a>,
    scene: &'a Scene,
    fog: &'a Fog,
    at: &LightVertexOrigin,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
) -> (LightGroup, Rgb) {
    let Some(subpath) = integrator.light_subpaths.choose(sampler.next_1d()) else {
        return (LightGroup::OTHER, Rgb::ZERO);
    };
    (
        subpath.group,
        subpath_light(integrator, scene, fog, at, subpath, counts),
    )
}

/// [`connect_light_vertex`]'s light from the chosen `subpath`.
fn subpath_light(
    integrator: &Volpath,
    scene: &Scene,
    fog: &Fog,
    at: &LightVertexOrigin,
    subpath: &LightSubpath,
    counts: &mut RayCounts,
) -> Rgb {
    let strategies = integrator.strategies;
    let (light, y0, y1) = (subpath.light, subpath.y0, subpath.y1);
    let to_light = -subpath.direction;
    let samples = strategies.later_equiangular();
    // The balance heuristic at y1 reached along `segment` at `t` (phase
    // density `phase_y1` there): the first and second light-vertex
    // strategies' densities, and the sum of every strategy's.
    let densities = |segment: &FogSegment, t: f32, phase_y1: f32| {
        let first = segment.connection_term(t, subpath.at_y1);
        let second = segment.second_vertex_term(subpath.at_y1);
        let equiangular = segment_term(segment, t, samples, light, y0);
        let total = FogEventDensities::new(
            strategies,
            subpath.p_omega,
            phase_y1,
            equiangular,
            first + second,
        )
        .total();
        (first, second, total)
    };
    let mut sum = Rgb::ZERO;
    if let Some(first) = at.join(integrator, scene, fog, y1, counts) {
        // f/p of x → y1 → y0: f(x)·T(x, y1)/t² · σs/σt · p(y1) · β·n_q.
        let phase_y1 = fog.phase.eval(to_light.dot(first.omega));
        let (connection, _, total) = densities(&first.segment, first.distance, phase_y1);
        sum += subpath.emitted * fog.albedo * first.value * (phase_y1 * (connection / total));
    }
    if !at.twice {
        return sum;
    }
    let Some((y2, turn)) = subpath.second else {
        return sum;
    };
    let Some(second) = at.join(integrator, scene, fog, y2, counts) else {
        return sum;
    };
    // The camera path's view of y2 → y1: its direction density at y2 and
    // the segment it would fly along.
    let back = -turn;
    let p_dir_y2 = fog.phase.eval(back.dot(second.omega));
    let t12 = (y1 - y2).length();
    let reach_y2 = second.segment.flight_pdf(second.distance) / (second.distance * second.distance);
    let p_reach = second.p_dir * reach_y2;
    let segment_ray = Ray {
        origin: y2,
        direction: back,
    };
    // The segment's end beyond y₁ matters only to the equiangular term.
    let t_hit = if samples.area > 0 {
        counts.shadow += 1;
        scene
            .intersect(&segment_ray, f32::INFINITY)
            .map_or(f32::INFINITY, |h| h.t)
    } else {
        f32::INFINITY
    };
    let connections = Connections {
        first: Some(p_dir_y2),
        second: false,
        reached: Some(p_reach * p_dir_y2),
    };
    let Some(segment) = FogSegment::new(integrator, scene, fog, segment_ray, t_hit, connections)
    else {
        return sum;
    };
    let phase_y1 = fog.phase.eval(to_light.dot(back));
    let (_, second_vertex, total) = densities(&segment, t12, phase_y1);
    let weight = second_vertex / total;
    // f/p of x → y2 → y1 → y0: f(x)·T(x, y2)/t² · (σs/σt)² · p(y2) ·
    // β·n_q (the second flight's density cancels p(y1), T(y1, y2)
    // and 1/|y2 − y1|²).
    sum + subpath.emitted * fog.albedo * fog.albedo * second.value * (p_dir_y2 * weight)
}

/// A camera-path vertex that connects to light vertices: where it is,
/// how it scatters, and what the camera path's densities need.
pub(super) struct LightVertexOrigin<'a> {
    pub x: Vec3,
    pub vertex: &'a Scatterer<'a>,
    /// If x is a fog event reached from a vertex that connected to second
    /// light vertices, the volume density of that reach.
    pub reached: Option<f32>,
    /// Whether x also connects to second light vertices.
    pub twice: bool,
}

/// The camera vertex joined to a light vertex y: the direction towards
/// y, the distance, the camera-side segment x would fly along towards y,
/// x's direction density, and `f(x)·T(x, y)/t²`.
struct Join<'a> {
    omega: Vec3,
    distance: f32,
    segment: FogSegment<'a>,
    p_dir: f32,
    value: Rgb,
}

impl LightVertexOrigin<'_> {
    /// Joins x to the fog point `y`; `None` if a surface is between them
    /// or x does not scatter that way.
    fn join<'s>(
        &self,
        integrator: &Volpath<'s>,
        scene: &'s Scene,
        fog: &'s Fog,
        y: Vec3,
        counts: &mut RayCounts,
    ) -> Option<Join<'s>> {
        let to_y = y - self.x;
        let t = to_y.length();
        if t.is_nan() || t <= 0.0 {
            return None;
        }
        let omega = to_y / t;
        let (f_x, p_dir) = self.vertex.scatter(omega)?;
        let segment_ray = Ray {
            origin: self.vertex.origin(self.x, omega),
            direction: omega,
        };
        counts.shadow += 1;
        let t_hit = if integrator.strategies.later_equiangular().area > 0 {
            // The equiangular term needs the whole segment: to the next
            // surface beyond y.
            let t_hit = scene
                .intersect(&segment_ray, f32::INFINITY)
                .map_or(f32::INFINITY, |h| h.t);
            if t_hit <= t {
                return None;
            }
            t_hit
        } else {
            // The other densities need only where the segment enters the
            // fog: a visibility test up to y does.
            if scene.occluded(&segment_ray, t) {
                return None;
            }
            f32::INFINITY
        };
        let connections = Connections {
            first: Some(p_dir),
            second: self.twice,
            reached: self.reached.map(|r| r * p_dir),
        };
        let segment = FogSegment::new(integrator, scene, fog, segment_ray, t_hit, connections)?;
        let value = f_x * (fog.transmittance(&segment_ray, 0.0, t) / (t * t));
        Some(Join {
            omega,
            distance: t,
            segment,
            p_dir,
            value,
        })
    }
}
