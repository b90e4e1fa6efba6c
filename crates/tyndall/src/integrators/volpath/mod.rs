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
//! scattering event. After five events Russian roulette ends paths with
//! probability 1 − √max(throughput), unbiasedly ([`survives_roulette`]).
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
//! vertex (after the camera's), a light subpath started on a quad light
//! is picked from the pass's pool ([`LightSubpaths`]) and its first fog
//! event, and its second, joined to the vertex
//! (`connect_light_vertex`). This reaches the glow of fog right around
//! an area light, which camera paths find only by rare random walks; the
//! two join the balance heuristic as a fourth and fifth strategy. In a
//! scene whose media are uniform volumes instead of fog (chromatic fog,
//! say) the camera's collisions connect to the subpaths' first
//! collisions the same way (`volume_connections`); where fog and volumes
//! meet, or a volume is not uniform, there are no connections (a light
//! subpath's flight density would need tracking).
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
//! ratio-tracked shadow rays and MIS against phase sampling. Flights
//! through uniform volumes aim at area lights (their collisions crowd
//! where those are bright, [`crate::media::tracking::FlightOptions::aim`]);
//! towards point and spot lights they take equiangular samples that feed
//! NEE only, weighed in t against NEE at the collision, as the fog's do
//! (`volume_equiangular`): the path must continue from a distance-sampled
//! collision, or deep paths' throughputs wander. Every
//! transmittance the fog estimators use is multiplied by the volumes'
//! (ratio tracking), which keeps their MIS weights valid: the weights
//! still sum to one, and each strategy stays unbiased. Segments inside a
//! solid dielectric carry no medium. Emissive volumes add their emission
//! at every tentative collision of that walk (`β·j/μ̄`, as pbrt-v4's
//! `VolPathIntegrator`; docs/physics.md §2.5), on every segment of the
//! path, whatever its depth, like an emitting surface reached by BSDF
//! sampling. Emitting media are also lights: at volume events and
//! Lambertian surface vertices NEE draws a point of an emitting volume by
//! its power ([`crate::media::emitters`], `nee::media_emission_nee`), and
//! the emission tracking finds along the direction sampled there is
//! weighted against it by the balance heuristic (`HitWeighting`); from
//! fog events, the camera and specular bounces it counts in full.
//!
//! Light focused by dielectrics from point and spot lights cannot be
//! reached from here; [`super::light_tracer`] adds it.

mod connections;
mod light_subpaths;
mod mis;
mod nee;
mod path;
mod segment;
mod segment_weights;
mod volume_connections;
mod volume_equiangular;

pub use crate::settings::Strategies;
pub use light_subpaths::LightSubpaths;
pub(crate) use path::radiance;

use crate::color::Rgb;
use crate::sampler::PixelSampler;
use crate::visibility::Visibility;
use glam::Vec3;
use mis::EquiangularCounts;
use segment::FogSegment;

/// Scattering events before Russian roulette may end a path. Five, not
/// three: 3–14 % more efficient on the multiple-scattering references,
/// but for fog-room-chromatic (−1 %) (docs/benchmarks.md, "Russian
/// roulette on the square root").
const ROULETTE_DEPTH: u32 = 5;

/// Hard limit on scattering events when `max_depth` is unlimited. Russian
/// roulette never ends a path whose throughput stays 1 (albedo-1 fog with
/// nothing to absorb it, e.g. unbounded white fog), so without a limit such
/// a path would never end. Paths this long carry nothing measurable in any
/// scene that absorbs at all; in one that absorbs nothing the cut is a bias
/// and the only one in `volpath`.
pub(crate) const MAX_PATH_EVENTS: u32 = 65_536;

/// The volumetric path tracer's parameters.
#[derive(Clone, Copy)]
pub struct Volpath<'a> {
    /// Most scattering events of a path (pbrt-v4's depth: 1 is single
    /// scattering).
    pub max_depth: u32,
    /// The estimators combined by MIS.
    pub strategies: Strategies,
    /// Equiangular samples per point or spot light on a camera segment.
    pub volume_samples: u32,
    pub(crate) visibility: &'a Visibility,
    /// The pass's light subpaths, for light-vertex connections.
    pub(crate) light_subpaths: &'a LightSubpaths<'a>,
}

/// How the current path segment was sampled, for the MIS weight of the
/// emitter it may hit.
#[derive(Clone, Copy)]
enum Arrival<'a> {
    /// From the camera or a specular/glossy reflection: NEE cannot produce
    /// this direction, so emission counts in full.
    Unweighted,
    /// BSDF-sampled at surface point `from` (or phase-sampled at a volume
    /// event there, if `in_volume`) with solid-angle density `pdf`; a
    /// volume event the camera path reached from a vertex that connected
    /// to light vertices keeps that reach's volume density
    /// (`volume_connections::reached_density`).
    Sampled {
        from: Vec3,
        pdf: f32,
        in_volume: bool,
        reached: Option<f32>,
    },
    /// Phase-sampled (density `pdf`) at the free-flight event at `t` on
    /// `segment`, whose equiangular estimator took `samples` per light:
    /// three strategies can produce the light it hits.
    Medium {
        pdf: f32,
        segment: FogSegment<'a>,
        t: f32,
        samples: EquiangularCounts,
    },
}

/// Russian roulette after [`ROULETTE_DEPTH`] events: continue with
/// probability `q = min(1, √max(throughput))`, dividing by `q` (unbiased
/// for any q > 0). The square root, as Cycles' path termination has it,
/// ends paths later than `q = max(throughput)`: a path whose throughput
/// fell to 0.1 survives a third of the time with weight 3, not a tenth
/// with weight 10. In smoke of albedo 0.95 and rooms lit by bounced
/// light, where deep paths carry much of the image, that cost 1–9 % more
/// time per sample for 9–20 % less error (docs/benchmarks.md, "Russian
/// roulette on the square root").
pub(crate) fn survives_roulette(
    throughput: &mut Rgb,
    depth: u32,
    sampler: &mut PixelSampler,
) -> bool {
    if depth < ROULETTE_DEPTH {
        return true;
    }
    let q = throughput.max_element().sqrt().min(1.0);
    if q <= 0.0 || sampler.next_1d() >= q {
        return false;
    }
    *throughput /= q;
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Roulette never ends a path before [`ROULETTE_DEPTH`] events, and
    /// after that keeps the throughput in expectation: a survivor carries
    /// β/q with probability q, so over n trials the mean of what survives
    /// is β within the standard error `β·√((1/q − 1)/n)`.
    #[test]
    fn roulette_keeps_the_throughput_in_expectation() {
        let n = 20_000;
        for beta in [Rgb::new(0.9, 0.5, 0.1), Rgb::splat(0.01), Rgb::splat(2.0)] {
            let mut early = beta;
            let mut sampler = PixelSampler::new(3, 4, 0);
            assert!(survives_roulette(
                &mut early,
                ROULETTE_DEPTH - 1,
                &mut sampler
            ));
            assert_eq!(early, beta);

            let mut sum = Rgb::ZERO;
            let mut survivors = 0;
            for i in 0..n {
                let mut b = beta;
                let mut sampler = PixelSampler::new(3, 4, i);
                if survives_roulette(&mut b, ROULETTE_DEPTH, &mut sampler) {
                    sum += b;
                    survivors += 1;
                }
            }
            let q = beta.max_element().sqrt().min(1.0);
            let mean = sum / n as f32;
            for c in 0..3 {
                let error = beta[c] * ((1.0 / q - 1.0) / n as f32).sqrt();
                assert!(
                    (mean[c] - beta[c]).abs() <= 5.0 * error + 1e-6 * beta[c],
                    "β {beta:?}: mean {mean:?}"
                );
            }
            // The survival probability is q: binomial, 5σ.
            let sigma = (n as f32 * q * (1.0 - q)).sqrt();
            assert!((survivors as f32 - n as f32 * q).abs() <= 5.0 * sigma + 1.0);
        }
    }
}
