//! `volpath`: a volumetric path tracer with multiple scattering — the
//! reference the fast single-scattering methods are judged against.
//!
//! From the camera, free-flight distances are sampled in the fog
//! proportionally to its transmittance (σt is grey, so one exponential
//! serves all channels and a real scattering event weighs the path by the
//! albedo σs/σt). At every scattering event in fog or on a surface, next
//! event estimation (NEE) connects to every light; the path then continues
//! by phase-function or BSDF sampling. Quad area lights are reachable both
//! ways, so the two estimates are combined by multiple importance sampling
//! with the balance heuristic (Veach 1997); point, spot and directional
//! lights only by NEE. Thin glass tints and passes the path; it is not a
//! scattering event. After three events Russian roulette ends paths with
//! probability 1 − max(throughput), unbiasedly.
//!
//! Every light but the sun is also estimated along fog segments by
//! equiangular sampling (Kulla & Fajardo 2012) towards the light's position
//! or an area-sampled point on it, combined by the balance heuristic with
//! NEE at the free-flight event (whose density is σt·e^{−σt(t−a)}) and,
//! for area lights, with phase-sampled hits: free flights alone put few
//! events near a light, whose 1/d² makes the rare ones fireflies. The
//! camera segment takes `volume_samples` stratified samples per point or
//! spot light and one per area light; later segments one per point or
//! spot light (NEE from a free-flight event has unbounded variance next
//! to a point light) and none per area light (solid-angle NEE is bounded
//! there, and the light-vertex connections cover the glow: more samples
//! cost more time than they saved error).
//! [`Strategies`] switches each estimator off for tests and measurements.
//!
//! Light-vertex connections: at every fog event and Lambertian surface
//! vertex (after the camera's), a light subpath is started on a quad
//! light and its first fog event, and its second, joined to the vertex
//! (`connect_light_vertex`). This reaches the glow of fog right around
//! an area light, which camera paths find only by rare random walks; the
//! two join the balance heuristic as a fourth and fifth strategy. With volumes in the
//! scene it is off (the light subpath's flight density would need
//! tracking).
//!
//! Depth counts scattering events, as in pbrt-v4: with `max_depth = 1` the
//! path stops at its second event, so it holds exactly light scattered once
//! (by fog or a surface) on its way to the camera — what `single` computes.
//!
//! Surfaces: the Lambertian lobe is sampled by cosine and also reached by
//! NEE (with MIS); the reflective layer is sampled only, its light found
//! when its reflected ray hits an emitter. The lobe is chosen with
//! probability proportional to its reflectance's luminance.
//!
//! Volumes (`[[media]]`): on each segment the fog's free flight is drawn
//! first, then the volumes' first collision before it by spectral
//! tracking ([`crate::media::tracking`]); the nearer real event wins (the
//! first of independent Poisson processes). At a volume event NEE uses
//! ratio-tracked shadow rays and MIS against phase sampling. Every
//! transmittance the fog estimators use is multiplied by the volumes'
//! (ratio tracking), which keeps their MIS weights valid: the weights
//! still sum to one, and each strategy stays unbiased. Segments inside a
//! solid dielectric carry no medium.
//!
//! Light focused by dielectrics from point and spot lights cannot be
//! reached from here; [`super::light_tracer`] adds it.

use super::{
    Integrator, MediumQuery, SolidDepth, SurfaceHit, TRACKING_STREAM, lambert_direct_lighting,
    light_arriving, refract_or_reflect, sample_light, scattered_light,
};
use crate::color::{Rgb, luminance};
use crate::lights::Light;
use crate::materials::{Material, Surface};
use crate::media::tracking::{Collision, VolumeTracker};
use crate::media::{Fog, free_flight, transmittance};
use crate::phase::PhaseFunction;
use crate::ray::{Ray, offset_origin};
use crate::sampler::PixelSampler;
use crate::sampling::{EquiangularSampler, cosine_hemisphere};
use crate::scene::Scene;
use crate::visibility::RayCounts;
use crate::visibility::Visibility;
use glam::Vec3;
use std::f32::consts::{FRAC_1_PI, PI};

/// Scattering events before Russian roulette may end a path.
const ROULETTE_DEPTH: u32 = 3;

/// Hard limit on scattering events when `max_depth` is unlimited. Russian
/// roulette never ends a path whose throughput stays 1 (albedo-1 fog with
/// nothing to absorb it, e.g. unbounded white fog), so without a limit such
/// a path would never end. Paths this long carry nothing measurable in any
/// scene that absorbs at all; in one that absorbs nothing the cut is a bias
/// and the only one in `volpath`.
pub(crate) const MAX_PATH_EVENTS: u32 = 65_536;

/// The estimators `volpath` combines by the balance heuristic, each of
/// which can produce the last connection of a path to a light on its own.
/// A strategy that is off contributes nothing and its density leaves every
/// other strategy's weight, so any subset that can still produce every
/// path renders the same image (the tests render each alone against the
/// others, which checks that the weights of every path sum to one):
///
/// - surfaces: `surface_nee` (light sampling) or `surface_hits` (BSDF
///   sampling that hits an area light);
/// - fog and volume events: `medium_nee` (light sampling at free-flight
///   events), `medium_hits` (phase sampling that hits an area light),
///   `equiangular` (samples along each fog segment towards each light)
///   and `connections` (light-vertex connections, fog scenes with area
///   lights only).
///
/// Point, spot and directional lights are reached only by light sampling
/// (`surface_nee`, `medium_nee`) and `equiangular`; single scattering from
/// an area light not by `connections` alone (the camera is no connecting
/// vertex).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Strategies {
    pub surface_nee: bool,
    pub surface_hits: bool,
    pub medium_nee: bool,
    pub medium_hits: bool,
    pub equiangular: bool,
    /// Equiangular sampling towards area lights also on segments after
    /// the first scattering event (with `equiangular`; towards point and
    /// spot lights it always runs there). Off by default: on those
    /// segments NEE, phase sampling and the light-vertex connections
    /// already cover area lights, and the extra samples cost more time
    /// than they save error (docs/benchmarks.md).
    pub later_area_equiangular: bool,
    pub connections: bool,
}

impl Strategies {
    /// Every strategy: the default.
    pub const ALL: Self = Self {
        surface_nee: true,
        surface_hits: true,
        medium_nee: true,
        medium_hits: true,
        equiangular: true,
        later_area_equiangular: false,
        connections: true,
    };

    /// No strategy; switch on the ones wanted.
    pub const NONE: Self = Self {
        surface_nee: false,
        surface_hits: false,
        medium_nee: false,
        medium_hits: false,
        equiangular: false,
        later_area_equiangular: false,
        connections: false,
    };

    /// Equiangular samples per light on a camera ray, if the strategy is
    /// on: `volume_samples` towards each point and spot light,
    /// [`CAMERA_AREA_EQUIANGULAR_SAMPLES`] towards each area light.
    fn camera_equiangular(self, volume_samples: u32) -> EquiangularCounts {
        if !self.equiangular {
            return EquiangularCounts::default();
        }
        EquiangularCounts {
            delta: volume_samples,
            area: CAMERA_AREA_EQUIANGULAR_SAMPLES.min(volume_samples),
        }
    }

    /// Equiangular samples per light on a segment after a scattering
    /// event: one.
    fn later_equiangular(self) -> EquiangularCounts {
        EquiangularCounts {
            delta: u32::from(self.equiangular),
            area: u32::from(self.equiangular && self.later_area_equiangular),
        }
    }
}

/// Equiangular samples per light on one fog segment: towards each point
/// or spot light, and towards each area light.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct EquiangularCounts {
    delta: u32,
    area: u32,
}

impl EquiangularCounts {
    /// Emissive spheres take none: their light is shared by NEE and
    /// phase or BSDF sampling alone.
    fn of(self, light: &Light) -> u32 {
        match light {
            Light::Quad(_) => self.area,
            Light::Sphere(_) => 0,
            Light::Point(_) | Light::Spot(_) | Light::Directional(_) => self.delta,
        }
    }
}

impl Default for Strategies {
    fn default() -> Self {
        Self::ALL
    }
}

/// `density` if its strategy is on, else 0: an MIS denominator counts
/// only the strategies that run.
#[inline]
fn on(enabled: bool, density: f32) -> f32 {
    if enabled { density } else { 0.0 }
}

/// Equiangular samples towards each area light on a camera ray. More
/// (`single` takes `volume_samples`, 8) cost time without lowering the
/// error here: fog-event NEE and the light-vertex connections already
/// cover area lights. Measured against 8: 22 % less CPU time at equal
/// error on the Cornell fog scene, 18 % more efficient (1/(relMSE·time))
/// on fog-room-multi; with none, fog-room-multi's error rises by a
/// quarter.
const CAMERA_AREA_EQUIANGULAR_SAMPLES: u32 = 1;

/// How the current path segment was sampled, for the MIS weight of the
/// emitter it may hit.
#[derive(Clone, Copy)]
enum Arrival<'a> {
    /// From the camera or a specular/glossy reflection: NEE cannot produce
    /// this direction, so emission counts in full.
    Unweighted,
    /// BSDF-sampled at surface point `from` (or phase-sampled at a volume
    /// event there, if `in_volume`) with solid-angle density `pdf`.
    Sampled {
        from: Vec3,
        pdf: f32,
        in_volume: bool,
    },
    /// Phase-sampled (density `pdf`) at the free-flight event at `t` on
    /// `segment`, whose equiangular estimator took `area_samples` per
    /// area light: three strategies can produce the light it hits.
    Medium {
        pdf: f32,
        segment: FogSegment<'a>,
        t: f32,
        area_samples: u32,
    },
}

/// Radiance along a camera ray: one path sample.
pub(crate) fn radiance(
    integrator: &Integrator,
    scene: &Scene,
    mut ray: Ray,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
) -> Rgb {
    let mut radiance = Rgb::ZERO;
    let mut throughput = Rgb::ONE;
    let mut depth = 0u32;
    let mut crossings = 0u32;
    let mut solids = SolidDepth::default();
    let mut arrival = Arrival::Unweighted;
    let mut equiangular = EquiangularNee::with_capacity(scene.lights.len());
    let mut tracker = VolumeTracker::new(sampler.stream(TRACKING_STREAM));
    let max_events = integrator.max_depth.min(MAX_PATH_EVENTS);
    let strategies = integrator.strategies;
    let connections =
        strategies.connections && scene.volumes.is_empty() && scene.quad_light_count() > 0;
    // What the vertex the ray leaves from connected to.
    let mut connected_from = Connections::default();
    loop {
        counts.camera += 1;
        let hit = scene.geometry.intersect(&ray, f32::INFINITY);
        let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
        // The fog's free-flight event, if one comes before the surface.
        let mut fog_event = None;
        if let Some(fog) = &scene.fog
            && !solids.inside()
            && let Some(segment) =
                FogSegment::new(integrator, scene, fog, ray, t_hit, connected_from)
        {
            let u_flight = sampler.next_1d();
            // Equiangular samples along the whole segment, for light
            // whose last scattering is on it.
            let samples = if depth == 0 {
                strategies.camera_equiangular(integrator.volume_samples)
            } else {
                strategies.later_equiangular()
            };
            equiangular.prepare(&segment, samples, sampler);
            if depth < max_events {
                radiance +=
                    throughput * equiangular.estimate(&segment, strategies, counts, &mut tracker);
            }
            fog_event = segment
                .free_flight(u_flight)
                .map(|t| (segment, t, samples.area));
        }
        // The volumes' first collision before the fog's event or the
        // surface: the first of independent events is the nearest.
        if !solids.inside() {
            let t_end = fog_event.map_or(t_hit, |(_, t, _)| t);
            match tracker.sample_collision(&scene.volumes, &ray, 0.0, t_end, &mut throughput) {
                Collision::Escaped => {}
                Collision::Absorbed => return radiance,
                Collision::Scatter { t, volume } => {
                    if depth >= max_events {
                        return radiance;
                    }
                    depth += 1;
                    let x = ray.at(t);
                    let phase = &scene.volumes[volume].phase;
                    let medium = PathVertex {
                        scene,
                        visibility: integrator.visibility,
                        x,
                        direction: ray.direction,
                        phase,
                    };
                    radiance += throughput * medium.nee(strategies, sampler, counts, &mut tracker);
                    let (direction, pdf) = phase.sample(ray.direction, sampler.next_2d());
                    arrival = Arrival::Sampled {
                        from: x,
                        pdf,
                        in_volume: true,
                    };
                    connected_from = Connections::default();
                    ray = Ray {
                        origin: x,
                        direction,
                    };
                    if !survives_roulette(&mut throughput, depth, sampler) {
                        return radiance;
                    }
                    continue;
                }
            }
        }
        if let Some((segment, t, area_samples)) = fog_event {
            // A real scattering event in the fog.
            if depth >= max_events {
                return radiance;
            }
            depth += 1;
            let fog = segment.medium.fog;
            throughput *= fog.albedo;
            let x = ray.at(t);
            let nee = medium_nee(
                &segment,
                t,
                &equiangular,
                strategies,
                sampler,
                counts,
                &mut tracker,
            );
            radiance += throughput * nee;
            let connects = connections && depth < max_events;
            let twice = connects && depth + 1 < max_events;
            // The density with which the camera path reached x from a
            // vertex that connected to second light vertices.
            let reached = segment.reached_density(t);
            if connects {
                let vertex = ConnectionVertex::Medium {
                    phase: &fog.phase,
                    view: ray.direction,
                };
                let at = LightVertexOrigin {
                    x,
                    vertex: &vertex,
                    reached,
                    twice,
                };
                radiance +=
                    throughput * connect_light_vertex(integrator, scene, fog, &at, sampler, counts);
            }
            let (direction, pdf) = fog.phase.sample(ray.direction, sampler.next_2d());
            // Phase sampling is exact: the weight p/pdf is 1.
            connected_from = Connections {
                first: connects.then_some(pdf),
                second: twice,
                reached: reached.map(|r| r * pdf),
            };
            arrival = Arrival::Medium {
                pdf,
                segment,
                t,
                area_samples,
            };
            ray = Ray {
                origin: x,
                direction,
            };
            if !survives_roulette(&mut throughput, depth, sampler) {
                return radiance;
            }
            continue;
        }
        // No event before the surface: transmittance over its probability is 1.
        let Some(hit) = hit else {
            return radiance + throughput * scene.background;
        };
        let SurfaceHit {
            p,
            geometric_normal,
            normal,
            front,
        } = SurfaceHit::new(scene, &ray, &hit);
        let surface = match *scene.material(hit.primitive) {
            Material::Emissive {
                radiance: le,
                two_sided,
            } => {
                if front || two_sided {
                    let weight = emission_weight(
                        scene,
                        strategies,
                        arrival,
                        hit.primitive,
                        p,
                        ray.direction,
                    );
                    radiance += throughput * le * weight;
                }
                return radiance;
            }
            // A spot's lamp is seen only by paths without a scattering
            // event (camera and specular): scattered light already has
            // the spot by NEE.
            Material::LampFace { radiance: le } => {
                if front && matches!(arrival, Arrival::Unweighted) {
                    radiance += throughput * le;
                }
                return radiance;
            }
            Material::Glass(glass) if !scene.glass.opaque_to_camera => {
                crossings += 1;
                if crossings > super::MAX_GLASS_CROSSINGS {
                    return radiance;
                }
                throughput *= glass.filter_transmittance();
                ray.origin = offset_origin(p, geometric_normal, ray.direction);
                // The segment after the pane no longer starts at the event.
                connected_from = Connections::default();
                continue;
            }
            Material::Dielectric { ior } => {
                // A specular event: NEE cannot reach through it.
                if depth >= max_events {
                    return radiance;
                }
                depth += 1;
                ray = refract_or_reflect(&ray, p, geometric_normal, ior, sampler, &mut solids);
                arrival = Arrival::Unweighted;
                connected_from = Connections::default();
                if !survives_roulette(&mut throughput, depth, sampler) {
                    return radiance;
                }
                continue;
            }
            Material::Glass(glass) => Surface::diffuse(glass.color),
            Material::Opaque(surface) => surface,
        };
        if depth >= max_events {
            return radiance;
        }
        depth += 1;
        let (diffuse_weight, specular_weight) =
            (luminance(surface.diffuse), luminance(surface.specular));
        if diffuse_weight + specular_weight <= 0.0 {
            return radiance;
        }
        let p_diffuse = diffuse_weight / (diffuse_weight + specular_weight);
        // NEE for the Lambertian lobe, MIS against its cosine sampling
        // (chosen with probability P_d).
        let mis = |p_light: Option<f32>, cos: f32| {
            p_light.map_or(1.0, |p_light| {
                p_light / (p_light + on(strategies.surface_hits, p_diffuse * cos * FRAC_1_PI))
            })
        };
        let visibility = integrator.visibility;
        if strategies.surface_nee {
            radiance += throughput
                * lambert_direct_lighting(
                    scene,
                    visibility,
                    &surface,
                    p,
                    normal,
                    sampler,
                    counts,
                    &mut tracker,
                    mis,
                );
        }
        // Light-vertex connections from Lambertian surfaces only: a
        // glossy lobe's density could not be weighed against them.
        let connects = connections && depth < max_events && !surface.has_specular();
        let twice = connects && depth + 1 < max_events;
        if connects && let Some(fog) = &scene.fog {
            let vertex = ConnectionVertex::Diffuse {
                rho: surface.diffuse,
                normal,
            };
            let at = LightVertexOrigin {
                x: p,
                vertex: &vertex,
                reached: None,
                twice,
            };
            radiance +=
                throughput * connect_light_vertex(integrator, scene, fog, &at, sampler, counts);
        }
        let choice = sampler.next_1d();
        let u = sampler.next_2d();
        let direction = if choice < p_diffuse {
            let direction = cosine_hemisphere(normal, u);
            // f·cos/pdf = (ρ/π)·cos / (P_d·cos/π) = ρ/P_d.
            throughput *= surface.diffuse / p_diffuse;
            let pdf = p_diffuse * normal.dot(direction).max(0.0) * FRAC_1_PI;
            arrival = Arrival::Sampled {
                from: p,
                pdf,
                in_volume: false,
            };
            let connects = connects && scene.fog.is_some();
            connected_from = Connections {
                first: connects.then_some(pdf),
                second: twice && connects,
                reached: None,
            };
            direction
        } else {
            let Some(direction) = surface.reflect(ray.direction, normal, u) else {
                return radiance;
            };
            throughput *= surface.specular / (1.0 - p_diffuse);
            arrival = Arrival::Unweighted;
            connected_from = Connections::default();
            direction
        };
        ray = Ray {
            origin: offset_origin(p, geometric_normal, direction),
            direction,
        };
        if !survives_roulette(&mut throughput, depth, sampler) {
            return radiance;
        }
    }
}

/// The part `[a, b]` of a path segment inside the fog.
#[derive(Clone, Copy)]
struct FogSegment<'a> {
    medium: MediumQuery<'a>,
    a: f32,
    b: f32,
    /// What the ray's origin vertex connected to.
    connected_from: Connections,
}

impl<'a> FogSegment<'a> {
    fn new(
        integrator: &Integrator<'a>,
        scene: &'a Scene,
        fog: &'a Fog,
        ray: Ray,
        t_hit: f32,
        connected_from: Connections,
    ) -> Option<Self> {
        let (a, b) = fog.interval(&ray, 0.0, t_hit)?;
        let medium = MediumQuery {
            scene,
            visibility: integrator.visibility,
            fog,
            ray,
            t_hit,
        };
        (fog.sigma_t > 0.0).then_some(Self {
            medium,
            a,
            b,
            connected_from,
        })
    }

    /// Distance to a real scattering event, sampled with density
    /// [`FogSegment::flight_pdf`]; `None` if the flight leaves the segment
    /// (probability e^{−σt(b−a)}).
    fn free_flight(&self, u: f32) -> Option<f32> {
        free_flight(self.medium.fog.sigma_t, self.a, self.b, u)
    }

    /// Density σt·e^{−σt(t−a)} of a free-flight event at `t`.
    fn flight_pdf(&self, t: f32) -> f32 {
        let sigma_t = self.medium.fog.sigma_t;
        sigma_t * transmittance(sigma_t, t - self.a)
    }

    /// For a quad light, the light-vertex connection's density for the
    /// event at `t` lit from the light point `y0`, relative to the
    /// free-flight event's (see [`connect_light_vertex`]), in the
    /// solid-angle terms of the balance heuristic at a fog event:
    /// `p₄ / (p_dir·p_flight(t)/t² · G)`, where
    /// `p₄ = σt·T(y0, y)·cos θ₀ / (n_q·A·π·s·|y − y0|²)` is the volume
    /// density of the light vertex y, `p_dir` the density of the ray's
    /// direction at its origin and `G = cos θ₀/|y − y0|²`. Zero unless the
    /// ray starts at a vertex that connected.
    fn connection_term(&self, t: f32, light: &Light, y0: Vec3) -> f32 {
        let (Some(p_dir), Light::Quad(q)) = (self.connected_from.first, light) else {
            return 0.0;
        };
        let medium = &self.medium;
        let y = medium.ray.at(t);
        let to_y = y - y0;
        let d = to_y.length();
        if d.is_nan() || d <= 0.0 || !(q.two_sided || to_y.dot(q.quad.normal) > 0.0) {
            return 0.0;
        }
        let p_flight = self.flight_pdf(t);
        if !(p_dir > 0.0 && p_flight > 0.0) {
            return 0.0;
        }
        let fog = medium.fog;
        let t_light = fog.transmittance_along(y0, to_y / d, d);
        let lights = medium.scene.quad_light_count() as f32;
        let sides = if q.two_sided { 2.0 } else { 1.0 };
        finite_density(
            fog.sigma_t * t_light * t * t
                / (lights * q.quad.area() * PI * sides * p_dir * p_flight),
        )
    }
}

impl FogSegment<'_> {
    /// The densities of both light-vertex strategies for the event at `t`
    /// lit from `y0`, in the solid-angle terms of the balance heuristic
    /// at a fog event.
    fn light_vertex_terms(&self, t: f32, light: &Light, y0: Vec3) -> f32 {
        self.connection_term(t, light, y0) + self.second_vertex_term(t, light, y0)
    }

    /// The volume density with which the camera path reaches the event at
    /// `t` from the ray's origin, `p_dir·p_flight(t)/t²`, if the origin
    /// connected to second light vertices (which can produce this event
    /// as one).
    fn reached_density(&self, t: f32) -> Option<f32> {
        let p_dir = self.connected_from.first?;
        (self.connected_from.second && t > 0.0).then(|| p_dir * self.flight_pdf(t) / (t * t))
    }

    /// For a quad light, the second-light-vertex strategy's density for
    /// the path (x, y₂, y₁ = ray.at(t), y0) relative to the camera path's
    /// common factor at y₁, where y₂ is the ray's origin and x the vertex
    /// before it: `σt·T(y0, y₁)·p(y₁) / (n_q·A·π·s·P_x(y₂)·p_dir(y₂))`
    /// (the light subpath's densities of y₁ and y₂ over the camera's of
    /// y₂ and of the event at y₁; see [`connect_light_vertex`]). Zero
    /// unless the origin was reached from a vertex that connected to
    /// second light vertices.
    fn second_vertex_term(&self, t: f32, light: &Light, y0: Vec3) -> f32 {
        let (Some(reached), Light::Quad(q)) = (self.connected_from.reached, light) else {
            return 0.0;
        };
        let medium = &self.medium;
        let y1 = medium.ray.at(t);
        let to_y1 = y1 - y0;
        let d = to_y1.length();
        if d.is_nan()
            || d <= 0.0
            || !(q.two_sided || to_y1.dot(q.quad.normal) > 0.0)
            || reached <= 0.0
        {
            return 0.0;
        }
        let fog = medium.fog;
        let t_light = fog.transmittance_along(y0, to_y1 / d, d);
        // Light arrives along to_y1 and turns back along −ray.direction.
        let phase = fog.phase.eval(-(to_y1 / d).dot(medium.ray.direction));
        let lights = medium.scene.quad_light_count() as f32;
        let sides = if q.two_sided { 2.0 } else { 1.0 };
        finite_density(
            fog.sigma_t * t_light * phase / (lights * q.quad.area() * PI * sides * reached),
        )
    }
}

/// A connection density relative to a camera-path density, kept finite.
/// Where the camera path's flight density underflows f32 (a free flight
/// through an optical depth above ~85, e.g. a camera deep in dense fog)
/// the ratio overflows, and ∞/∞ in the connection's own weight was NaN
/// (found by fuzzing). Capped at `f32::MAX` the connection takes the
/// whole weight, which is the limit of the balance heuristic; only
/// where both light-vertex terms overflow at once is the split between
/// them lost, on contributions below f32's resolution.
fn finite_density(ratio: f32) -> f32 {
    if ratio.is_nan() {
        0.0
    } else {
        ratio.min(f32::MAX)
    }
}

/// What a camera-path vertex connected to, as seen from the segment that
/// leaves it.
#[derive(Clone, Copy, Debug, Default)]
struct Connections {
    /// The solid-angle density of the segment's direction, if the vertex
    /// connected to first light vertices.
    first: Option<f32>,
    /// Whether it also connected to second light vertices.
    second: bool,
    /// If the vertex is a fog event reached from one that connected to
    /// second light vertices: that reach's volume density times this
    /// segment's direction density, `P_x(y₂)·p_dir(y₂)`.
    reached: Option<f32>,
}

/// Equiangular NEE along one fog segment (Kulla & Fajardo 2012): `n`
/// stratified samples per light towards its position (point and spot
/// lights) or towards a point chosen uniformly on it (quad lights),
/// combined by the balance heuristic with NEE at the free-flight event
/// and, for quad lights, with phase-sampled hits of the light.
///
/// For quad lights the strategies are compared in the measure of (t, y),
/// the scattering distance and the light point: the segment estimator has
/// density `n·p_e(t | y)/A`; NEE at a free-flight event `p_flight(t)·p_Ω·G`
/// and a phase-sampled hit `p_flight(t)·p_phase·G`, with `G = cos θ_y/d²`
/// turning solid angle into area.
///
/// One value serves a whole path: [`EquiangularNee::prepare`] refills it
/// for each segment without allocating.
struct EquiangularNee {
    lights: Vec<Option<SegmentLight>>,
    counts: EquiangularCounts,
}

/// One light's equiangular sampler on the segment, its stratification
/// offset, and the point it aims at.
#[derive(Clone, Copy)]
struct SegmentLight {
    sampler: EquiangularSampler,
    u: f32,
    point: Vec3,
    /// Samples taken towards the light.
    n: u32,
}

impl EquiangularNee {
    fn with_capacity(lights: usize) -> Self {
        Self {
            lights: Vec::with_capacity(lights),
            counts: EquiangularCounts::default(),
        }
    }

    /// Sets up `counts` samples per light on `segment`; a light with no
    /// samples is not estimated here.
    fn prepare(
        &mut self,
        segment: &FogSegment,
        counts: EquiangularCounts,
        sampler: &mut PixelSampler,
    ) {
        let ray = &segment.medium.ray;
        self.counts = counts;
        self.lights.clear();
        self.lights
            .extend(segment.medium.scene.lights.iter().map(|light| {
                let n = counts.of(light);
                if n == 0 {
                    return None;
                }
                let u = sampler.next_1d();
                let point = match light {
                    Light::Point(p) => p.position,
                    Light::Spot(s) => s.position,
                    Light::Quad(q) => {
                        let v = sampler.next_2d();
                        q.quad.point(v.x, v.y)
                    }
                    Light::Directional(_) | Light::Sphere(_) => return None,
                };
                let (ea, eb) = light.reach(ray, segment.a, segment.b)?;
                let sampler = EquiangularSampler::new(ray, point, ea, eb)?;
                Some(SegmentLight {
                    sampler,
                    u,
                    point,
                    n,
                })
            }));
    }

    /// Density with which a point or spot light's samples land at `t`, all
    /// `n` counted (0 if the light is not sampled here).
    fn delta_pdf(&self, index: usize, t: f32) -> f32 {
        self.lights[index].map_or(0.0, |l| l.n as f32 * l.sampler.pdf(t))
    }

    /// Whether light `index` is estimated here (and must be MIS-weighted
    /// at the free-flight event).
    fn covers(&self, index: usize) -> bool {
        self.lights[index].is_some()
    }

    /// In-scattered radiance from lights whose last scattering lies on the
    /// segment, relative to the segment's start.
    fn estimate(
        &self,
        segment: &FogSegment,
        strategies: Strategies,
        counts: &mut RayCounts,
        tracker: &mut VolumeTracker,
    ) -> Rgb {
        let medium = &segment.medium;
        let fog = medium.fog;
        let mut sum = Rgb::ZERO;
        for (index, entry) in self.lights.iter().enumerate() {
            let Some(entry) = entry else { continue };
            let light = &medium.scene.lights[index];
            let n = entry.n as f32;
            for k in 0..entry.n {
                let (t, p_e) = entry.sampler.sample((k as f32 + entry.u) / n);
                let x = medium.ray.at(t);
                let Some(incident) = light.incident(x, Some(entry.point)) else {
                    continue;
                };
                let light_in = scattered_light(medium, index, x, &incident, counts, tracker);
                if light_in == Rgb::ZERO {
                    continue;
                }
                let p_flight = segment.flight_pdf(t);
                // The integrand T(a, t)·σs·(eq. 1) over the summed densities.
                let denominator = match light {
                    Light::Quad(q) => {
                        // E = L·A·G (area sampling), so the (t, y)
                        // densities appear here multiplied by A.
                        let g = q.quad.normal.dot(incident.direction).abs()
                            / (incident.distance * incident.distance);
                        let p_omega = q.pdf(x, entry.point, incident.direction);
                        let p_connect = segment.light_vertex_terms(t, light, entry.point);
                        n * p_e
                            + q.quad.area()
                                * p_flight
                                * g
                                * (on(strategies.medium_nee, p_omega)
                                    + on(strategies.medium_hits, medium.phase(&incident))
                                    + p_connect)
                    }
                    _ => n * p_e + on(strategies.medium_nee, p_flight),
                };
                let camera_t = transmittance(fog.sigma_t, t - segment.a)
                    * tracker.transmittance(&medium.scene.volumes, &medium.ray, 0.0, t);
                sum += fog.sigma_s() * light_in * camera_t / denominator;
            }
        }
        sum
    }
}

/// For a quad light, the segment estimator's density for (t, y) relative
/// to the free-flight event's, in solid-angle terms:
/// `q = (n·p_e(t | y)/A) / (p_flight(t)·G)`. Added to `p_Ω + p_phase` it
/// completes the three-way balance heuristic at a fog event.
fn segment_term(segment: &FogSegment, t: f32, samples: u32, light: &Light, y: Vec3) -> f32 {
    let Light::Quad(q) = light else {
        return 0.0;
    };
    if samples == 0 {
        return 0.0;
    }
    let ray = &segment.medium.ray;
    let Some(eq) = EquiangularSampler::new(ray, y, segment.a, segment.b) else {
        return 0.0;
    };
    let d = y - ray.at(t);
    let d2 = d.length_squared();
    let g = q.quad.normal.dot(d).abs() / (d2 * d2.sqrt());
    let p_flight = segment.flight_pdf(t);
    if !(g > 0.0 && p_flight > 0.0) {
        return 0.0;
    }
    samples as f32 * eq.pdf(t) / q.quad.area() / (p_flight * g)
}

/// Russian roulette after [`ROULETTE_DEPTH`] events: continue with
/// probability `q = min(1, max(throughput))`, dividing by `q`.
pub(crate) fn survives_roulette(
    throughput: &mut Rgb,
    depth: u32,
    sampler: &mut PixelSampler,
) -> bool {
    if depth < ROULETTE_DEPTH {
        return true;
    }
    let q = throughput.max_element().min(1.0);
    if q <= 0.0 || sampler.next_1d() >= q {
        return false;
    }
    *throughput /= q;
    true
}

/// Solid-angle density with which NEE picks the point `p` of the area
/// light `light` from a point `from` (see [`sample_light`]).
fn light_pdf(light: &Light, from: Vec3, p: Vec3, direction: Vec3) -> f32 {
    match light {
        Light::Quad(q) => q.pdf(from, p, direction),
        Light::Sphere(s) => s.pdf(from, p, direction),
        _ => 0.0,
    }
}

/// MIS weight of emission found by a sampled direction: the balance
/// heuristic against NEE's density for the same point, if the emitter is
/// a sampled area light.
fn emission_weight(
    scene: &Scene,
    strategies: Strategies,
    arrival: Arrival,
    primitive: u32,
    p: Vec3,
    direction: Vec3,
) -> f32 {
    match (arrival, scene.area_light_at(primitive)) {
        (
            Arrival::Sampled {
                from,
                pdf,
                in_volume,
            },
            Some(index),
        ) => {
            let (nee, hits) = if in_volume {
                (strategies.medium_nee, strategies.medium_hits)
            } else {
                (strategies.surface_nee, strategies.surface_hits)
            };
            if !hits {
                return 0.0;
            }
            let p_light = light_pdf(&scene.lights[index], from, p, direction);
            pdf / (pdf + on(nee, p_light))
        }
        (
            Arrival::Medium {
                pdf,
                segment,
                t,
                area_samples,
            },
            Some(index),
        ) => {
            if !strategies.medium_hits {
                return 0.0;
            }
            let light = &scene.lights[index];
            let p_light = light_pdf(light, segment.medium.ray.at(t), p, direction);
            let q = segment_term(&segment, t, area_samples, light, p);
            let p_connect = segment.light_vertex_terms(t, light, p);
            pdf / (pdf + on(strategies.medium_nee, p_light) + q + p_connect)
        }
        _ => 1.0,
    }
}

/// NEE at the free-flight event at `t` on `segment`: the in-scattered
/// radiance of eq. 1 without σs (the path's throughput already holds the
/// albedo), MIS-weighted for area lights (against phase sampling and the
/// segment's equiangular samples) and for point and spot lights (against
/// the equiangular samples).
#[allow(clippy::too_many_arguments)]
fn medium_nee(
    segment: &FogSegment,
    t: f32,
    equiangular: &EquiangularNee,
    strategies: Strategies,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
) -> Rgb {
    if !strategies.medium_nee {
        return Rgb::ZERO;
    }
    let medium = &segment.medium;
    let x = medium.ray.at(t);
    let mut sum = Rgb::ZERO;
    for (index, light) in medium.scene.lights.iter().enumerate() {
        let Some((incident, p_light)) = sample_light(light, x, sampler) else {
            continue;
        };
        let weight = match p_light {
            Some(p_light) => {
                let y = x + incident.direction * incident.distance;
                let q = if equiangular.covers(index) {
                    segment_term(segment, t, equiangular.counts.area, light, y)
                } else {
                    0.0
                };
                let p_connect = segment.light_vertex_terms(t, light, y);
                let p_phase = on(strategies.medium_hits, medium.phase(&incident));
                p_light / (p_light + p_phase + q + p_connect)
            }
            None if equiangular.covers(index) => {
                let p_flight = segment.flight_pdf(t);
                p_flight / (p_flight + equiangular.delta_pdf(index, t))
            }
            None => 1.0,
        };
        sum += scattered_light(medium, index, x, &incident, counts, tracker) * weight;
    }
    sum
}

/// A real scattering event in a volume: where, the direction the path
/// arrived along, and the volume's phase function.
struct PathVertex<'a> {
    scene: &'a Scene,
    visibility: &'a Visibility,
    x: Vec3,
    direction: Vec3,
    phase: &'a PhaseFunction,
}

impl PathVertex<'_> {
    /// NEE to every light: `Σ p(θ)·E·V·Tr·w`, where `w` is the balance
    /// heuristic against phase sampling for area lights (delta lights
    /// have only this strategy). The path's throughput holds σs.
    fn nee(
        &self,
        strategies: Strategies,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        tracker: &mut VolumeTracker,
    ) -> Rgb {
        let mut sum = Rgb::ZERO;
        if !strategies.medium_nee {
            return sum;
        }
        for (index, light) in self.scene.lights.iter().enumerate() {
            let Some((incident, p_light)) = sample_light(light, self.x, sampler) else {
                continue;
            };
            let phase = self.phase.eval(incident.direction.dot(self.direction));
            let weight = p_light.map_or(1.0, |p_light| {
                p_light / (p_light + on(strategies.medium_hits, phase))
            });
            let arriving = light_arriving(
                self.scene,
                self.visibility,
                index,
                self.x,
                None,
                &incident,
                counts,
                tracker,
            );
            sum += arriving * (phase * weight);
        }
        sum
    }
}

/// Light-vertex connections at the camera-path vertex `at.x` (a fog event
/// or a Lambertian surface point): a light subpath is started on a quad
/// light (chosen uniformly, a point uniform on it, a cosine-distributed
/// direction, through thin glass); its first free-flight event y1 in the
/// fog is connected to x, and, if `at.twice`, the light turns at y1 by the
/// phase function, flies on to a second event y2, and y2 is connected to
/// x as well. Returns the MIS-weighted radiance both bring to the path
/// (to be multiplied by the path's throughput at x, which holds a fog
/// event's albedo but not a surface's BRDF).
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
fn connect_light_vertex(
    integrator: &Integrator,
    scene: &Scene,
    fog: &Fog,
    at: &LightVertexOrigin,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
) -> Rgb {
    let strategies = integrator.strategies;
    let lights = scene.quad_light_count();
    let choice = sampler.next_1d() * lights as f32;
    let (u_point, u_direction, u_flight) =
        (sampler.next_2d(), sampler.next_2d(), sampler.next_1d());
    let (u_turn, u_flight2) = (sampler.next_2d(), sampler.next_1d());
    let Some((index, q)) = scene
        .lights
        .iter()
        .enumerate()
        .filter_map(|(i, l)| match l {
            Light::Quad(q) => Some((i, q)),
            _ => None,
        })
        .nth((choice as usize).min(lights - 1))
    else {
        return Rgb::ZERO;
    };
    // A two-sided light picks its side with the choice's fraction.
    let (normal, sides) = if q.two_sided {
        let back = choice.fract() >= 0.5;
        (if back { -q.quad.normal } else { q.quad.normal }, 2.0)
    } else {
        (q.quad.normal, 1.0)
    };
    let y0 = q.quad.point(u_point.x, u_point.y);
    let direction = cosine_hemisphere(normal, u_direction);
    let first_flight = Ray {
        origin: offset_origin(y0, normal, direction),
        direction,
    };
    // The first flight may cross thin glass (it is not a camera segment).
    let Some((y1, tint)) = light_flight(scene, fog, first_flight, u_flight, true, counts) else {
        return Rgb::ZERO;
    };
    let light = &scene.lights[index];
    // Le·n_q·A·π·s: the light vertex's density cancels T(y0, y1), cos θ₀
    // and 1/|y1 − y0|² of the path's contribution.
    let emitted = q.radiance * tint * (lights as f32 * q.quad.area() * PI * sides);
    let mut sum = Rgb::ZERO;
    if let Some(first) = at.join(integrator, scene, fog, y1, counts) {
        // f/p of x → y1 → y0: f(x)·T(x, y1)/t² · σs/σt · p(y1) · Le·n_q·A·π·s.
        let to_light = -direction;
        let phase_y1 = fog.phase.eval(to_light.dot(first.omega));
        let t = first.distance;
        let p_connect = first.segment.light_vertex_terms(t, light, y0);
        let p_omega = q.pdf(y1, y0, to_light);
        let samples = strategies.later_equiangular().area;
        let equiangular = segment_term(&first.segment, t, samples, light, y0);
        let weight = first.segment.connection_term(t, light, y0)
            / others(strategies, p_connect, p_omega, phase_y1, equiangular);
        sum += emitted * fog.albedo * first.value * (phase_y1 * weight);
    }
    if !at.twice {
        return sum;
    }
    // The second light vertex: the light turns at y1 by the phase function
    // and flies to y2 (no surface between: y2 → y1 is a camera segment).
    let (turn, _) = fog.phase.sample(direction, u_turn);
    let Some((y2, _)) = light_flight(
        scene,
        fog,
        Ray {
            origin: y1,
            direction: turn,
        },
        u_flight2,
        false,
        counts,
    ) else {
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
    let t_hit = if strategies.later_equiangular().area > 0 {
        counts.shadow += 1;
        scene
            .geometry
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
    let to_light = -direction;
    let phase_y1 = fog.phase.eval(to_light.dot(back));
    let p_connect = segment.light_vertex_terms(t12, light, y0);
    let p_omega = q.pdf(y1, y0, to_light);
    let samples = strategies.later_equiangular().area;
    let equiangular = segment_term(&segment, t12, samples, light, y0);
    let weight = segment.second_vertex_term(t12, light, y0)
        / others(strategies, p_connect, p_omega, phase_y1, equiangular);
    // f/p of x → y2 → y1 → y0: f(x)·T(x, y2)/t² · (σs/σt)² · p(y2) ·
    // Le·n_q·A·π·s (the second flight's density cancels p(y1), T(y1, y2)
    // and 1/|y2 − y1|²).
    sum + emitted * fog.albedo * fog.albedo * second.value * (p_dir_y2 * weight)
}

/// The balance heuristic's denominator for a light-vertex connection to
/// the fog point y₁ lit from the light point y₀: the connections' own
/// densities plus those of the strategies that are on — NEE at y₁, the
/// phase-sampled hit from y₁, and the equiangular sample on the segment
/// (already zero when off); all relative to the same common factor.
fn others(
    strategies: Strategies,
    p_connect: f32,
    p_omega: f32,
    phase_y1: f32,
    equiangular: f32,
) -> f32 {
    p_connect
        + on(strategies.medium_nee, p_omega)
        + on(strategies.medium_hits, phase_y1)
        + equiangular
}

/// A camera-path vertex that connects to light vertices: where it is,
/// how it scatters, and what the camera path's densities need.
struct LightVertexOrigin<'a> {
    x: Vec3,
    vertex: &'a ConnectionVertex<'a>,
    /// If x is a fog event reached from a vertex that connected to second
    /// light vertices, the volume density of that reach.
    reached: Option<f32>,
    /// Whether x also connects to second light vertices.
    twice: bool,
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
        integrator: &Integrator<'s>,
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
                .geometry
                .intersect(&segment_ray, f32::INFINITY)
                .map_or(f32::INFINITY, |h| h.t);
            if t_hit <= t {
                return None;
            }
            t_hit
        } else {
            // The other densities need only where the segment enters the
            // fog: a visibility test up to y does.
            if scene.geometry.occluded(&segment_ray, t) {
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

/// A light subpath's free flight along `ray` to its first fog event, with
/// one optical depth `−ln(1 − u)` spent piece by piece; across thin glass
/// panes (multiplying the tint) if `through_glass`, else stopping at any
/// surface. The event and the tint, or `None` if the flight ends on a
/// surface or leaves the scene.
fn light_flight(
    scene: &Scene,
    fog: &Fog,
    mut ray: Ray,
    u: f32,
    through_glass: bool,
    counts: &mut RayCounts,
) -> Option<(Vec3, Rgb)> {
    let mut depth_left = -(1.0 - u).ln();
    let mut tint = Rgb::ONE;
    let mut crossings = 0u32;
    loop {
        counts.camera += 1;
        let hit = scene.geometry.intersect(&ray, f32::INFINITY);
        let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
        if let Some((a, b)) = fog.interval(&ray, 0.0, t_hit) {
            let depth = fog.sigma_t * (b - a);
            if depth_left < depth {
                return Some((ray.at(a + depth_left / fog.sigma_t), tint));
            }
            depth_left -= depth;
        }
        let hit = hit?;
        match scene.material(hit.primitive) {
            Material::Glass(glass) if through_glass => {
                tint *= glass.filter_transmittance();
                crossings += 1;
                if crossings > super::MAX_GLASS_CROSSINGS {
                    return None;
                }
                let p = ray.at(hit.t);
                let n = scene.geometry.normal(hit.primitive, p);
                ray.origin = offset_origin(p, n, ray.direction);
            }
            _ => return None,
        }
    }
}

/// A camera-path vertex that connects to light vertices, and how it
/// scatters light towards the path.
enum ConnectionVertex<'a> {
    /// A fog event reached along `view`.
    Medium {
        phase: &'a PhaseFunction,
        view: Vec3,
    },
    /// A Lambertian surface with the normal facing the path.
    Diffuse { rho: Rgb, normal: Vec3 },
}

impl ConnectionVertex<'_> {
    /// For light arriving from direction `omega`, the scattering towards
    /// the path (`p(θ)`, or `ρ/π·cos θ`) and the density with which the
    /// path's continuation picks `omega` (phase sampling, or cosine
    /// sampling of a surface with no reflective layer: P_d = 1).
    fn scatter(&self, omega: Vec3) -> Option<(Rgb, f32)> {
        match *self {
            ConnectionVertex::Medium { phase, view } => {
                let p = phase.eval(omega.dot(view));
                Some((Rgb::splat(p), p))
            }
            ConnectionVertex::Diffuse { rho, normal } => {
                let cos = normal.dot(omega);
                (cos > 0.0).then(|| (rho * (FRAC_1_PI * cos), cos * FRAC_1_PI))
            }
        }
    }

    /// Where a ray towards `omega` starts: just off a surface.
    fn origin(&self, x: Vec3, omega: Vec3) -> Vec3 {
        match *self {
            ConnectionVertex::Medium { .. } => x,
            ConnectionVertex::Diffuse { normal, .. } => offset_origin(x, normal, omega),
        }
    }
}
