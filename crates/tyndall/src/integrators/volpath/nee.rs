//! Next event estimation at `volpath`'s scattering events: light
//! sampled towards every light from a free-flight event in the fog
//! ([`medium_nee`]) or a real collision in a volume ([`PathVertex::nee`]),
//! MIS-weighted against the other strategies that reach the same light.

use super::mis::{FogEventDensities, balance_of_two, segment_term};
use super::segment::{EquiangularNee, FogSegment};
use crate::color::Rgb;
use crate::integrators::{light_arriving, sample_light, scattered_light};
use crate::media::tracking::VolumeTracker;
use crate::phase::PhaseFunction;
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::settings::Strategies;
use crate::visibility::{RayCounts, Visibility};
use glam::Vec3;

/// NEE at the free-flight event at `t` on `segment`: the in-scattered
/// radiance of eq. 1 without σs (the path's throughput already holds the
/// albedo), MIS-weighted for area lights (against phase sampling and the
/// segment's equiangular samples) and for point and spot lights (against
/// the equiangular samples).
#[allow(clippy::too_many_arguments)]
pub(super) fn medium_nee(
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
                let y = incident.light_point(x);
                let q = if equiangular.covers(index) {
                    segment_term(segment, t, equiangular.counts, light, y)
                } else {
                    0.0
                };
                let p_connect = segment.light_vertex_terms(t, light, y.position);
                let p_phase = medium.phase(&incident);
                p_light / FogEventDensities::new(strategies, p_light, p_phase, q, p_connect).total()
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
pub(super) struct PathVertex<'a> {
    pub scene: &'a Scene,
    pub visibility: &'a Visibility,
    pub x: Vec3,
    pub direction: Vec3,
    pub phase: &'a PhaseFunction,
}

impl PathVertex<'_> {
    /// NEE to every light: `Σ p(θ)·E·V·Tr·w`, where `w` is the balance
    /// heuristic against phase sampling for area lights (delta lights
    /// have only this strategy). The path's throughput holds σs.
    pub(super) fn nee(
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
                balance_of_two(p_light, strategies.medium_hits, phase)
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
