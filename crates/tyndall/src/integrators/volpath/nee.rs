//! Next event estimation at `volpath`'s scattering events: light
//! sampled towards every light from a free-flight event in the fog
//! ([`medium_nee`]) or a real collision in a volume ([`PathVertex::nee`]),
//! MIS-weighted against the other strategies that reach the same light.

use super::mis::FogEventDensities;
use super::segment::{EquiangularNee, FogSegment};
use super::segment_weights::segment_term;
use super::volume_connections::connection_term;
use crate::color::Rgb;
use crate::integrators::media_transmittance;
use crate::integrators::path_radiance::{Gathered, Keep};
use crate::integrators::{light_arriving, lights_at, sample_light, scattered_light};
use crate::lights::Light;
use crate::media::emitters::hit_density;
use crate::media::tracking::VolumeTracker;
use crate::phase::PhaseFunction;
use crate::ray::offset_origin;
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::settings::Strategies;
use crate::visibility::segment_transmittance;
use crate::visibility::{RayCounts, Visibility};
use glam::Vec3;

/// NEE at the free-flight event at `t` on `segment`, towards the lights
/// chosen at the event's point ([`lights_at`], weight `c` each): the
/// in-scattered radiance of eq. 1 without σs (the path's throughput
/// already holds the albedo), MIS-weighted for area lights (against phase
/// sampling and the segment's equiangular samples) and for point and spot
/// lights (against the equiangular samples, see [`EquiangularNee`]).
// Inlined into each of `radiance`'s two instantiations (with and
// without the components), as it was into its one before: measured,
// the call instead cost 2 % of a volpath sample.
#[inline(always)]
pub(super) fn medium_nee<K: Keep>(
    segment: &FogSegment,
    t: f32,
    equiangular: &EquiangularNee,
    strategies: Strategies,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
) -> Gathered<K> {
    let mut sum = Gathered::new();
    if !strategies.medium_nee {
        return sum;
    }
    let medium = &segment.medium;
    let x = medium.ray.at(t);
    for (index, chosen) in lights_at(medium.scene, x, sampler) {
        let light = &medium.scene.lights[index];
        let Some((incident, p_light)) = sample_light(light, x, sampler) else {
            continue;
        };
        let weight = match p_light {
            // Area lights are visited by every estimate: the segment's
            // samples of them, if any, are its own.
            Some(p_light) => {
                let y = incident.light_point(x);
                let q = if equiangular.chosen(index).is_some_and(|c| c.sampled()) {
                    segment_term(segment, t, equiangular.counts, light, y)
                } else {
                    0.0
                };
                let p_connect = segment.light_vertex_terms(t, light, y.position);
                let p_phase = medium.phase(&incident);
                p_light / FogEventDensities::new(strategies, p_light, p_phase, q, p_connect).total()
            }
            None => {
                let p_equiangular = equiangular.delta_pdf(segment, index, light, t);
                if p_equiangular > 0.0 {
                    let p_flight = segment.flight_pdf(t);
                    p_flight / (p_flight + p_equiangular)
                } else {
                    1.0
                }
            }
        };
        sum.add(
            medium.scene.light_group(index),
            scattered_light(medium, index, x, &incident, counts, tracker) * (weight * chosen),
        );
    }
    sum
}

/// Next event estimation towards emitting media from `x` (a volume
/// event, `normal = None`, or a surface point with geometric normal
/// `normal` facing the side the path is on): a point `y` of an emitting
/// volume drawn by its power ([`crate::media::emitters`]), its emission
/// `j(y)` seen through glass, fog and the volumes (ratio tracking),
/// `f(ω)·T·j/(p_nee·|y − x|²)`, balance-heuristic weighted against the
/// emission that tracking along a direction sampled here with density
/// `pdf_dir(ω)` finds. `eval(ω)` gives `(f, pdf_dir)` — the phase
/// function or BSDF times cosine — or `None` where the vertex cannot
/// scatter towards ω. The throughput is the caller's.
#[allow(clippy::too_many_arguments)]
pub(super) fn media_emission_nee(
    scene: &Scene,
    x: Vec3,
    normal: Option<Vec3>,
    strategies: Strategies,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
    eval: impl Fn(Vec3) -> Option<(Rgb, f32)>,
) -> Rgb {
    let emitters = &scene.media_emitters;
    if !strategies.emission_nee || emitters.is_empty() {
        return Rgb::ZERO;
    }
    let (u_volume, u_cell) = (sampler.next_1d(), sampler.next_1d());
    let w = sampler.next_2d().extend(sampler.next_1d());
    let Some((volume, y, p_nee)) = emitters.sample(u_volume, u_cell, w) else {
        return Rgb::ZERO;
    };
    let d = y - x;
    let distance_squared = d.length_squared();
    let distance = distance_squared.sqrt();
    if distance.is_nan() || distance <= 0.0 {
        return Rgb::ZERO;
    }
    let direction = d / distance;
    let Some((f, pdf_dir)) = eval(direction) else {
        return Rgb::ZERO;
    };
    let emitter = &scene.volumes[volume];
    let j = emitter.emission_at(y);
    if f == Rgb::ZERO || j == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let origin = normal.map_or(x, |n| offset_origin(x, n, direction));
    let from_origin = distance - (origin - x).dot(direction);
    let glass = segment_transmittance(scene, origin, direction, from_origin, counts);
    if glass == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let media = media_transmittance(scene, tracker, x, origin, direction, distance);
    let p_hit = if strategies.emission_hits {
        hit_density(
            pdf_dir,
            emitter.extinction_at(y).max_element(),
            distance_squared,
        )
    } else {
        0.0
    };
    let weight = p_nee / (p_nee + p_hit);
    f * glass * media * j * (weight / (p_nee * distance_squared))
}

/// A real scattering event in a volume: where, the direction the path
/// arrived along, and the volume's phase function.
pub(super) struct PathVertex<'a> {
    pub scene: &'a Scene,
    pub visibility: &'a Visibility,
    pub x: Vec3,
    pub direction: Vec3,
    pub phase: &'a PhaseFunction,
    /// The camera path's volume density of reaching x, if the vertex
    /// before connected to light vertices
    /// ([`super::volume_connections::reached_density`]).
    pub reached: Option<f32>,
}

impl PathVertex<'_> {
    /// NEE to the chosen lights ([`lights_at`], weight `c`):
    /// `Σ c·p(θ)·E·V·Tr·w`, where `w` is the balance heuristic against
    /// phase sampling for area lights and `delta_weight(index, light)`
    /// for point, spot and directional lights (against the segment's
    /// equiangular samples, [`super::volume_equiangular`]). The path's
    /// throughput holds σs.
    pub(super) fn nee<K: Keep>(
        &self,
        strategies: Strategies,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        tracker: &mut VolumeTracker,
        delta_weight: impl Fn(usize, &Light) -> f32,
    ) -> Gathered<K> {
        let mut sum = Gathered::new();
        if !strategies.medium_nee {
            return sum;
        }
        for (index, chosen) in lights_at(self.scene, self.x, sampler) {
            let light = &self.scene.lights[index];
            let Some((incident, p_light)) = sample_light(light, self.x, sampler) else {
                continue;
            };
            let phase = self.phase.eval(incident.direction.dot(self.direction));
            let weight = match p_light {
                Some(p_light) => {
                    let y0 = incident.light_point(self.x).position;
                    let connection =
                        connection_term(self.scene, tracker, light, y0, self.x, self.reached);
                    p_light
                        / FogEventDensities::new(strategies, p_light, phase, 0.0, connection)
                            .total()
                }
                None => delta_weight(index, light),
            };
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
            sum.add(
                self.scene.light_group(index),
                arriving * (chosen * phase * weight),
            );
        }
        sum
    }
}
