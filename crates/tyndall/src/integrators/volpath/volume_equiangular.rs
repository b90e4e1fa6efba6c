//! Equiangular NEE towards point and spot lights along a path segment's
//! flight through uniform volumes ([`VolumeEquiangular`]), the volumes'
//! counterpart of the fog's [`EquiangularNee`](super::segment::EquiangularNee).
//!
//! Next to a point light, NEE from distance-sampled collisions alone has
//! unbounded variance (the light's 1/d² against a density that does not
//! grow there). Moving the collisions themselves towards the light, as
//! flights aimed at area lights do ([`FlightOptions::aim`]), is no cure:
//! the path continues from the moved collision, so every event multiplies
//! the throughput by the ratio of the distance density to the mixture's,
//! and over a deep path that ratio's product is a random walk that
//! roulette does not stop (docs/benchmarks.md). So, as in the fog and as
//! Cycles does for its homogeneous volumes, the path continues from its
//! distance-sampled collision, and the equiangular samples feed NEE only:
//! along the segment's flight `[0, end]`, `n` stratified samples per
//! chosen point or spot light (Kulla & Fajardo 2012), weighed by the
//! balance heuristic in t against NEE at the collision
//! ([`VolumeEquiangular::collision_weight`]), whose density is the
//! flight's ([`UniformFlight::density`]).
//!
//! The flight ends at the fog's free-flight event if one comes first; the
//! samples cover the same interval as the collision they compete with, so
//! the fog's transmittance is in the probability that the interval
//! reaches t, not in the estimate. Only segments whose volumes are all
//! uniform and quiet take samples: elsewhere the collision density has no
//! closed form, and NEE at collisions keeps its full weight.
//!
//! [`FlightOptions::aim`]: crate::media::tracking::FlightOptions::aim

use super::mis::on;
use crate::color::Rgb;
use crate::integrators::light_arriving;
use crate::integrators::lights_along;
use crate::integrators::path_radiance::{Gathered, Keep};
use crate::lights::Light;
use crate::media::tracking::{UniformFlight, VolumeTracker};
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::sampling::EquiangularSampler;
use crate::scene::Scene;
use crate::settings::Strategies;
use crate::visibility::{RayCounts, Visibility};
use glam::Vec3;

/// The equiangular samples of one segment's flight through uniform
/// volumes. One value serves a whole path: [`VolumeEquiangular::prepare`]
/// refills it for each segment without allocating.
pub(super) struct VolumeEquiangular {
    flight: UniformFlight,
    ray: Ray,
    /// The flight's interval is `[0, end]`.
    end: f32,
    /// Samples per point or spot light; 0 where the segment takes none.
    samples: u32,
    chosen: Vec<ChosenDelta>,
}

/// A point or spot light chosen for the segment: its index, its weight
/// `1/P`, its equiangular sampler and its stratification offset.
#[derive(Clone, Copy)]
struct ChosenDelta {
    index: usize,
    weight: f32,
    sampler: EquiangularSampler,
    u: f32,
}

impl VolumeEquiangular {
    pub(super) fn with_capacity(lights: usize) -> Self {
        Self {
            flight: UniformFlight::default(),
            ray: Ray {
                origin: Vec3::ZERO,
                direction: Vec3::Z,
            },
            end: 0.0,
            samples: 0,
            chosen: Vec::with_capacity(lights),
        }
    }

    /// Takes no samples on the current segment.
    pub(super) fn clear(&mut self) {
        self.samples = 0;
        self.chosen.clear();
    }

    /// Sets up `samples` samples per chosen point or spot light on the
    /// flight along `ray` over `[0, end]` that starts with throughput
    /// `beta`; none unless every volume on the way is uniform and quiet.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn prepare(
        &mut self,
        scene: &Scene,
        tracker: &mut VolumeTracker,
        ray: Ray,
        end: f32,
        beta: Rgb,
        samples: u32,
        sampler: &mut PixelSampler,
    ) {
        self.clear();
        if samples == 0
            || !tracker.describe_uniform_flight(
                &scene.volumes,
                &ray,
                0.0,
                end,
                beta,
                &mut self.flight,
            )
            || self.flight.is_empty()
        {
            return;
        }
        self.samples = samples;
        self.ray = ray;
        self.end = end;
        for (index, weight) in lights_along(scene, &ray, 0.0, end, sampler) {
            let light = &scene.lights[index];
            if !light.is_delta() {
                continue;
            }
            let u = sampler.next_1d();
            if let Some(sampler) = self.sampler_towards(light) {
                self.chosen.push(ChosenDelta {
                    index,
                    weight,
                    sampler,
                    u,
                });
            }
        }
    }

    /// The equiangular sampler towards a point or spot light's position
    /// over the part of the flight it reaches; `None` for a sun.
    fn sampler_towards(&self, light: &Light) -> Option<EquiangularSampler> {
        let (a, b) = light.reach(&self.ray, 0.0, self.end)?;
        EquiangularSampler::new(&self.ray, light.position()?, a, b)
    }

    /// Density with which the samples towards point or spot light
    /// `light` (number `index`) land at `t`, all `n` counted, whether or
    /// not it was chosen for the segment: a function of the segment and
    /// the light alone, so that NEE at the collision, which chooses its
    /// lights anew, weighs against the density the segment's estimator
    /// has where it does choose the light.
    fn delta_pdf(&self, index: usize, light: &Light, t: f32) -> f32 {
        if self.samples == 0 {
            return 0.0;
        }
        let n = self.samples as f32;
        if let Some(chosen) = self.chosen.iter().find(|c| c.index == index) {
            return n * chosen.sampler.pdf(t);
        }
        self.sampler_towards(light).map_or(0.0, |s| n * s.pdf(t))
    }

    /// The balance-heuristic weight of NEE towards point or spot light
    /// `light` (number `index`) at the flight's collision at `t`:
    /// `p_d(t)/(p_d(t) + n·p_e(t))`, 1 where the segment takes no samples
    /// towards it.
    pub(super) fn collision_weight(&self, index: usize, light: &Light, t: f32) -> f32 {
        let p_equiangular = self.delta_pdf(index, light, t);
        if p_equiangular > 0.0 {
            let p_flight = self.flight.density(t);
            p_flight / (p_flight + p_equiangular)
        } else {
            1.0
        }
    }

    /// In-scattered radiance from point and spot lights whose last
    /// scattering lies on the flight, relative to the throughput at its
    /// start: per sample `T(0, t)·Σ_i σs_i·p_i(θ)·E·V·Tr / (n·p_e(t) +
    /// p_d(t))` times the light's `1/P`.
    pub(super) fn estimate<K: Keep>(
        &self,
        scene: &Scene,
        visibility: &Visibility,
        strategies: Strategies,
        counts: &mut RayCounts,
        tracker: &mut VolumeTracker,
    ) -> Gathered<K> {
        let mut sum = Gathered::new();
        let n = self.samples as f32;
        for chosen in &self.chosen {
            let light = &scene.lights[chosen.index];
            for k in 0..self.samples {
                let (t, p_e) = chosen.sampler.sample((k as f32 + chosen.u) / n);
                let x = self.ray.at(t);
                let Some(incident) = light.incident(x, None) else {
                    continue;
                };
                let cos_theta = incident.direction.dot(self.ray.direction);
                let scattering = self.flight.in_scattering(&scene.volumes, t, cos_theta);
                if scattering == Rgb::ZERO {
                    continue;
                }
                let arriving = light_arriving(
                    scene,
                    visibility,
                    chosen.index,
                    x,
                    None,
                    &incident,
                    counts,
                    tracker,
                );
                if arriving == Rgb::ZERO {
                    continue;
                }
                let denominator = n * p_e + on(strategies.medium_nee, self.flight.density(t));
                sum.add(
                    scene.light_group(chosen.index),
                    self.flight.transmittance(t)
                        * scattering
                        * arriving
                        * (chosen.weight / denominator),
                );
            }
        }
        sum
    }
}
