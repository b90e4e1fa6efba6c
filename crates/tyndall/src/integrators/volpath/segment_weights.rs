//! The MIS densities and weights that read a path's fog segment: the
//! equiangular estimator's density for an event on it ([`segment_term`]),
//! the light-vertex connections' ([`FogSegment::light_vertex_terms`]), in
//! the solid-angle terms of the balance heuristic at a fog event (mis.rs),
//! and the weight of emission a sampled direction finds
//! ([`emission_weight`]). They live apart from mis.rs, which the segment
//! itself reads, so that no two modules import each other.

use super::Arrival;
use super::mis::{
    EquiangularCounts, FogEventDensities, LightVertexDensity, balance_of_two, finite_density, on,
};
use super::segment::FogSegment;
use super::volume_connections::connection_term;
use crate::lights::{Light, LightPoint};
use crate::media::tracking::VolumeTracker;
use crate::sampling::EquiangularSampler;
use crate::scene::Scene;
use crate::settings::Strategies;
use glam::Vec3;

/// For a quad light, the segment estimator's density for (t, y) relative
/// to the free-flight event's, in solid-angle terms:
/// `q = (n·p_e(t | y)/A) / (p_flight(t)·G)`. Added to `p_Ω + p_phase` it
/// completes the three-way balance heuristic at a fog event.
pub(super) fn segment_term(
    segment: &FogSegment,
    t: f32,
    counts: EquiangularCounts,
    light: &Light,
    y: LightPoint,
) -> f32 {
    let samples = counts.of(light);
    let Some(normal) = y.normal else {
        return 0.0;
    };
    let y = y.position;
    if samples == 0 {
        return 0.0;
    }
    let ray = &segment.medium.ray;
    let Some(eq) = EquiangularSampler::new(ray, y, segment.a, segment.b) else {
        return 0.0;
    };
    let d = y - ray.at(t);
    let d2 = d.length_squared();
    let g = normal.dot(d).abs() / (d2 * d2.sqrt());
    let p_flight = segment.flight_pdf(t);
    if !(g > 0.0 && p_flight > 0.0) {
        return 0.0;
    }
    samples as f32 * eq.pdf(t) / light.area() / (p_flight * g)
}

/// MIS weight of emission found by a sampled direction: the balance
/// heuristic against NEE's density for the same point, if the emitter is
/// a sampled area light, and against the light-vertex connection where
/// the direction left a volume collision that one could have made
/// (`volume_connections`, whose flight densities `tracker` computes).
pub(super) fn emission_weight(
    scene: &Scene,
    strategies: Strategies,
    arrival: Arrival,
    primitive: u32,
    p: Vec3,
    direction: Vec3,
    tracker: &mut VolumeTracker,
) -> f32 {
    match (arrival, scene.area_light_at(primitive)) {
        (
            Arrival::Sampled {
                from,
                pdf,
                in_volume,
                reached,
            },
            Some(index),
        ) => {
            let (nee, hits) = strategies.at_vertex(in_volume);
            if !hits {
                return 0.0;
            }
            let light = &scene.lights[index];
            let y = LightPoint::on_surface(p, scene.geometry.normal(primitive, p));
            let p_light = on(nee, light.pdf_li(from, y, direction));
            let p_connect = connection_term(scene, tracker, light, p, from, reached);
            pdf / (pdf + p_light + p_connect)
        }
        (
            Arrival::Medium {
                pdf,
                segment,
                t,
                samples,
            },
            Some(index),
        ) => {
            if !strategies.medium_hits {
                return 0.0;
            }
            let light = &scene.lights[index];
            let y = LightPoint::on_surface(p, scene.geometry.normal(primitive, p));
            let p_light = light.pdf_li(segment.medium.ray.at(t), y, direction);
            let q = segment_term(&segment, t, samples, light, y);
            let p_connect = segment.light_vertex_terms(t, light, p);
            pdf / FogEventDensities::new(strategies, p_light, pdf, q, p_connect).total()
        }
        _ => 1.0,
    }
}

/// MIS weight of the environment's radiance found by a sampled direction
/// that leaves the scene: the balance heuristic against NEE's density
/// for the same direction (every estimate visits the environment, so it
/// is chosen with probability 1). At a fog event NEE and phase sampling
/// are the only strategies that reach it (no equiangular samples or
/// light-vertex connections start from it). Without an environment, the
/// background is seen only along the camera's and specular paths: it
/// lights nothing (docs/scene-format.md), as in the single-scattering
/// integrators.
pub(super) fn escape_weight(
    scene: &Scene,
    strategies: Strategies,
    arrival: Arrival,
    direction: Vec3,
) -> f32 {
    let Some((_, environment)) = scene.environment() else {
        return if matches!(arrival, Arrival::Unweighted) {
            1.0
        } else {
            0.0
        };
    };
    match arrival {
        Arrival::Unweighted => 1.0,
        Arrival::Sampled { pdf, in_volume, .. } => {
            let (nee, hits) = strategies.at_vertex(in_volume);
            if !hits {
                return 0.0;
            }
            balance_of_two(pdf, nee, environment.pdf(direction))
        }
        Arrival::Medium { pdf, .. } => {
            if !strategies.medium_hits {
                return 0.0;
            }
            let p_light = environment.pdf(direction);
            pdf / FogEventDensities::new(strategies, p_light, pdf, 0.0, 0.0).total()
        }
    }
}

impl FogSegment<'_> {
    /// The densities of both light-vertex strategies for the event at `t`
    /// lit from `y0`, in the solid-angle terms of the balance heuristic
    /// at a fog event.
    pub(super) fn light_vertex_terms(&self, t: f32, light: &Light, y0: Vec3) -> f32 {
        // Light subpaths start only on flat emitters (quads): no other
        // light (a sphere, a mesh, the environment, whose `y0` is at
        // infinity) has a light vertex.
        if !light.is_flat_emitter()
            || self.connected_from.first.is_none() && self.connected_from.reached.is_none()
        {
            return 0.0;
        }
        let medium = &self.medium;
        let y = LightVertexDensity::new(medium.scene, medium.fog, light, y0, medium.ray.at(t));
        self.connection_term(t, y) + self.second_vertex_term(y)
    }

    /// The light-vertex connection's density for the event at `t`, the
    /// light subpath vertex `y` (see
    /// [`connect_light_vertex`](super::connections::connect_light_vertex)),
    /// relative to the free-flight event's, in the solid-angle terms of
    /// the balance heuristic at a fog event:
    /// `p₄ / (p_dir·p_flight(t)/t² · G)`, where
    /// `p₄ = σt·T(y0, y)·p_le·cos θ₀ / (n_q·|y − y0|²)` is the volume
    /// density of the light vertex y, `p_dir` the density of the ray's
    /// direction at its origin and `G = cos θ₀/|y − y0|²`. Zero unless
    /// the ray starts at a vertex that connected, and where no subpath
    /// reaches y.
    pub(super) fn connection_term(&self, t: f32, y: Option<LightVertexDensity>) -> f32 {
        let (Some(p_dir), Some(y)) = (self.connected_from.first, y) else {
            return 0.0;
        };
        let p_flight = self.flight_pdf(t);
        if !(p_dir > 0.0 && p_flight > 0.0) {
            return 0.0;
        }
        finite_density(y.density * t * t / (p_dir * p_flight))
    }

    /// The second-light-vertex strategy's density for the path
    /// (x, y₂, y₁, y0), y₁ the light subpath vertex `y1` on this ray,
    /// relative to the camera path's common factor at y₁, where y₂ is the
    /// ray's origin and x the vertex before it:
    /// `σt·T(y0, y₁)·p(y₁)·p_le / (n_q·P_x(y₂)·p_dir(y₂))` (the light
    /// subpath's densities of y₁ and y₂ over the camera's of y₂ and of the
    /// event at y₁; see
    /// [`connect_light_vertex`](super::connections::connect_light_vertex)).
    /// Zero unless the origin was reached from a vertex that connected to
    /// second light vertices, and where no subpath reaches y₁.
    pub(super) fn second_vertex_term(&self, y1: Option<LightVertexDensity>) -> f32 {
        let (Some(reached), Some(y1)) = (self.connected_from.reached, y1) else {
            return 0.0;
        };
        if reached <= 0.0 {
            return 0.0;
        }
        // Light arrives along y0 → y₁ and turns back along −ray.direction.
        let phase = self
            .medium
            .fog
            .phase
            .eval(-y1.direction.dot(self.medium.ray.direction));
        finite_density(y1.density * phase / reached)
    }
}
