//! Sampling along one path segment in the fog: the segment itself
//! ([`FogSegment`]: its free-flight distance and density) and
//! equiangular sampling towards each light on it ([`EquiangularNee`],
//! Kulla & Fajardo 2012).

use super::Volpath;
use super::mis::{EquiangularCounts, FogEventDensities, on};
use crate::color::Rgb;
use crate::integrators::path_radiance::{Gathered, Keep};
use crate::integrators::{MediumQuery, lights_along, media_transmittance, scattered_light};
use crate::lights::{Light, LightPoint};
use crate::media::tracking::VolumeTracker;
use crate::media::{Fog, free_flight, transmittance};
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::sampling::EquiangularSampler;
use crate::scene::Scene;
use crate::settings::Strategies;
use crate::visibility::RayCounts;

/// The part `[a, b]` of a path segment inside the fog.
#[derive(Clone, Copy)]
pub(super) struct FogSegment<'a> {
    pub(super) medium: MediumQuery<'a>,
    pub(super) a: f32,
    pub(super) b: f32,
    /// What the ray's origin vertex connected to.
    pub(super) connected_from: Connections,
}

impl<'a> FogSegment<'a> {
    /// The part of `ray`'s segment `(0, t_hit)` inside `fog`, if any
    /// (and if the fog can scatter at all).
    pub(super) fn new(
        integrator: &Volpath<'a>,
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
    pub(super) fn free_flight(&self, u: f32) -> Option<f32> {
        free_flight(self.medium.fog.sigma_t, self.a, self.b, u)
    }

    /// Density σt·e^{−σt(t−a)} of a free-flight event at `t`.
    pub(super) fn flight_pdf(&self, t: f32) -> f32 {
        let sigma_t = self.medium.fog.sigma_t;
        sigma_t * transmittance(sigma_t, t - self.a)
    }

    /// The volume density with which the camera path reaches the event at
    /// `t` from the ray's origin, `p_dir·p_flight(t)/t²`, if the origin
    /// connected to second light vertices (which can produce this event
    /// as one).
    pub(super) fn reached_density(&self, t: f32) -> Option<f32> {
        let p_dir = self.connected_from.first?;
        (self.connected_from.second && t > 0.0).then(|| p_dir * self.flight_pdf(t) / (t * t))
    }
}

/// What a camera-path vertex connected to, as seen from the segment that
/// leaves it.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Connections {
    /// The solid-angle density of the segment's direction, if the vertex
    /// connected to first light vertices.
    pub(super) first: Option<f32>,
    /// Whether it also connected to second light vertices.
    pub(super) second: bool,
    /// If the vertex is a fog event reached from one that connected to
    /// second light vertices: that reach's volume density times this
    /// segment's direction density, `P_x(y₂)·p_dir(y₂)`.
    pub(super) reached: Option<f32>,
}

/// Equiangular NEE along one fog segment (Kulla & Fajardo 2012): `n`
/// stratified samples per chosen light towards its position (point and
/// spot lights) or towards a point chosen uniformly on it (quad lights),
/// combined by the balance heuristic with NEE at the free-flight event
/// and, for quad lights, with phase-sampled hits of the light.
///
/// The lights are chosen for the segment ([`lights_along`]: all of them,
/// or the visited ones and those the light tree chooses by their
/// importance to the segment), each estimate weighted by `1/P`. NEE at
/// the segment's free-flight event chooses its own lights, by their
/// importance at the event's point; the balance heuristic between the two
/// estimators of a light reads only their densities in `t`
/// ([`EquiangularNee::delta_pdf`]), which do not depend on the choices,
/// so the weights still sum to one and each estimator, divided by its own
/// choice's probability, stays unbiased.
///
/// For quad lights the strategies are compared in the measure of (t, y),
/// the scattering distance and the light point: the segment estimator has
/// density `n·p_e(t | y)/A`; NEE at a free-flight event `p_flight(t)·p_Ω·G`
/// and a phase-sampled hit `p_flight(t)·p_phase·G`, with `G = cos θ_y/d²`
/// turning solid angle into area.
///
/// One value serves a whole path: [`EquiangularNee::prepare`] refills it
/// for each segment without allocating.
pub(super) struct EquiangularNee {
    chosen: Vec<ChosenLight>,
    pub(super) counts: EquiangularCounts,
}

/// A light chosen for the segment: its index, its weight `1/P`, and its
/// equiangular samples on the segment if it takes any.
#[derive(Clone, Copy)]
pub(super) struct ChosenLight {
    index: usize,
    weight: f32,
    samples: Option<SegmentLight>,
}

/// One light's equiangular sampler on the segment, its stratification
/// offset, and the point it aims at.
#[derive(Clone, Copy)]
struct SegmentLight {
    sampler: EquiangularSampler,
    u: f32,
    point: LightPoint,
    /// Samples taken towards the light.
    n: u32,
}

impl ChosenLight {
    /// Density with which a point or spot light's samples land at `t`,
    /// all `n` counted (0 if the light is not sampled here).
    pub(super) fn delta_pdf(&self, t: f32) -> f32 {
        self.samples.map_or(0.0, |l| l.n as f32 * l.sampler.pdf(t))
    }

    /// Whether the light is estimated by the segment's samples (and must
    /// be MIS-weighted at the free-flight event).
    pub(super) fn sampled(&self) -> bool {
        self.samples.is_some()
    }
}

impl EquiangularNee {
    pub(super) fn with_capacity(lights: usize) -> Self {
        Self {
            chosen: Vec::with_capacity(lights),
            counts: EquiangularCounts::default(),
        }
    }

    /// Chooses the segment's lights and sets up `counts` samples per
    /// chosen light on `segment`; a light with no samples is not
    /// estimated here.
    // Inlined into each of `radiance`'s two instantiations (with and
    // without the components), as it was into its one before: measured,
    // the call instead cost 2 % of a volpath sample.
    #[inline(always)]
    pub(super) fn prepare(
        &mut self,
        segment: &FogSegment,
        counts: EquiangularCounts,
        sampler: &mut PixelSampler,
    ) {
        let medium = &segment.medium;
        let ray = &medium.ray;
        self.counts = counts;
        self.chosen.clear();
        let lights = lights_along(medium.scene, ray, segment.a, segment.b, sampler);
        self.chosen.extend(lights.map(|(index, weight)| {
            let light = &medium.scene.lights[index];
            let samples = (|| {
                let n = counts.of(light);
                if n == 0 {
                    return None;
                }
                let u = sampler.next_1d();
                let point = if light.is_delta() {
                    LightPoint::delta(light.position()?)
                } else {
                    light.sample_point(sampler.next_2d())?
                };
                let (ea, eb) = light.reach(ray, segment.a, segment.b)?;
                let sampler = EquiangularSampler::new(ray, point.position, ea, eb)?;
                Some(SegmentLight {
                    sampler,
                    u,
                    point,
                    n,
                })
            })();
            ChosenLight {
                index,
                weight,
                samples,
            }
        }));
    }

    /// Light `index` if it was chosen for the segment.
    pub(super) fn chosen(&self, index: usize) -> Option<&ChosenLight> {
        self.chosen.iter().find(|c| c.index == index)
    }

    /// Density with which the samples towards point or spot light
    /// `light` (number `index`) land at `t`, all `n` counted, whether or
    /// not it was chosen for the segment: a function of the segment and
    /// the light alone, so that NEE at a free-flight event, which chooses
    /// its lights anew, weighs against the same density the segment's
    /// estimator has where it does choose the light.
    pub(super) fn delta_pdf(
        &self,
        segment: &FogSegment,
        index: usize,
        light: &Light,
        t: f32,
    ) -> f32 {
        if let Some(chosen) = self.chosen(index) {
            return chosen.delta_pdf(t);
        }
        let n = self.counts.of(light);
        let ray = &segment.medium.ray;
        let sampler = (|| {
            let (ea, eb) = light.reach(ray, segment.a, segment.b)?;
            EquiangularSampler::new(ray, light.position()?, ea, eb)
        })();
        match sampler {
            Some(sampler) if n > 0 => n as f32 * sampler.pdf(t),
            _ => 0.0,
        }
    }

    /// In-scattered radiance from lights whose last scattering lies on the
    /// segment, relative to the segment's start.
    // Inlined into each of `radiance`'s two instantiations (with and
    // without the components), as it was into its one before: measured,
    // the call instead cost 2 % of a volpath sample.
    #[inline(always)]
    pub(super) fn estimate<K: Keep>(
        &self,
        segment: &FogSegment,
        strategies: Strategies,
        counts: &mut RayCounts,
        tracker: &mut VolumeTracker,
    ) -> Gathered<K> {
        let medium = &segment.medium;
        let fog = medium.fog;
        let mut sum = Gathered::new();
        for chosen in &self.chosen {
            let Some(entry) = &chosen.samples else {
                continue;
            };
            let index = chosen.index;
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
                let denominator = match entry.point.normal {
                    // An area light.
                    Some(normal) => {
                        // E = L·A·G (area sampling), so the (t, y)
                        // densities appear here multiplied by A.
                        let g = normal.dot(incident.direction).abs()
                            / (incident.distance * incident.distance);
                        let p_omega = light.pdf_li(x, entry.point, incident.direction);
                        let p_connect = segment.light_vertex_terms(t, light, entry.point.position);
                        // This estimator's own density is n·p_e, above.
                        let others = FogEventDensities::new(
                            strategies,
                            p_omega,
                            medium.phase(&incident),
                            0.0,
                            p_connect,
                        );
                        n * p_e + light.area() * p_flight * g * others.total()
                    }
                    None => n * p_e + on(strategies.medium_nee, p_flight),
                };
                let ray = &medium.ray;
                let camera_t = media_transmittance(
                    medium.scene,
                    tracker,
                    ray.origin,
                    ray.origin,
                    ray.direction,
                    t,
                );
                sum.add(
                    medium.scene.light_group(index),
                    fog.sigma_s() * light_in * camera_t / denominator * chosen.weight,
                );
            }
        }
        sum
    }
}
