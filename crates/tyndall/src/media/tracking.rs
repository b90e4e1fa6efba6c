//! Delta and ratio tracking through [`Volume`]s with per-cell majorants,
//! for RGB extinction.
//!
//! Both walk a ray's majorant segments, drawing tentative collisions at
//! the majorant rate μ̄ (a Poisson process; μ̄ bounds σt in every channel).
//!
//! * Ratio tracking (Novák et al. 2014) estimates transmittance: each
//!   tentative collision multiplies the estimate by the null fraction
//!   `1 − σt(x)/μ̄`, per channel. Unbiased; Russian roulette ends walks
//!   whose estimate has fallen below 0.1.
//! * Free flights use spectral tracking (Kutz et al. 2017, "history-aware"
//!   probabilities), the unbiased generalisation of delta tracking
//!   (Woodcock 1965) to RGB: a tentative collision is a real scattering in
//!   volume i, an absorption (the path ends) or a null collision with
//!   probabilities `P_e ∝ ⟨β·σ_e⟩`, the channel sum of the coefficient
//!   weighted by the path's throughput β, and the throughput is multiplied
//!   by `σ_e/(μ̄·P_e)`. With a grey medium this is exactly delta tracking
//!   (the weights are 1); with RGB extinction the weights keep every
//!   channel unbiased while the probabilities follow the channels that
//!   still carry light. This is our answer to per-channel extinction in
//!   place of hero-wavelength MIS: one walk serves all three channels, so
//!   no channel's pdf ever has to be evaluated.
//! * Emission (docs/physics.md §2.5) is estimated on the same walk, as
//!   pbrt-v4's `VolPathIntegrator` does (§14.2.2, "Add emission from
//!   medium scattering event"): at every tentative collision, before its
//!   outcome is drawn, the estimate gains `β·j(x)/μ̄` — β the throughput
//!   the walk carries to x, whose expectation is the transmittance T(x)
//!   (the ratio-tracking identity), and 1/μ̄ the inverse density of
//!   tentative collisions; so its expectation is `∫ T(t)·j(t) dt`, the
//!   emission term of the radiative transfer equation, without bias.
//! * Homogeneous pieces need neither walk. Where every volume on a
//!   majorant segment is uniform and does not emit
//!   ([`Volume::uniform_extinction`]), σt is one constant per channel
//!   there: transmittance is Beer–Lambert's `exp(−σt·ℓ)` exactly, and a
//!   free flight is drawn in closed form by one-sample spectral MIS
//!   (Miller, Georgiev and Jarosz 2019, "A null-scattering path integral
//!   formulation of light transport", §6; Veach 1997, §9.2.4, the
//!   one-sample balance heuristic): a channel c is chosen with
//!   probability `w_c = β_c/Σβ`, a distance from its exponential
//!   `σt_c·e^{−σt_c s}`, and the throughput is weighted by the whole
//!   mixture's density `p(s) = Σ_k w_k·σt_k·T_k(s)`: past the segment by
//!   `T(ℓ) / Σ_k w_k·T_k(ℓ)`; at a collision, volume i scatters with
//!   probability `⟨β·σs_i·T(s)⟩ / ⟨β·σt·T(s)⟩` (⟨·⟩ the channel sum) and
//!   the flight is otherwise absorbed, as in spectral tracking, so that
//!   the scattering weight `σs_i·T(s) / (p(s)·P_i)` makes the throughput
//!   `β·σs_i·T(s)·Σβ / ⟨β·σs_i·T(s)⟩`, with the same channel sum Σβ as
//!   before. Every channel stays unbiased and no channel's weight exceeds
//!   Σβ, where tracking at the largest channel's rate would give the
//!   other channels binary ratio estimates on shadow rays and draw null
//!   collisions on flights. (Carrying absorption in the weight instead,
//!   σs for σt, with Russian roulette on the largest channel, kept paths
//!   going as long as the least absorbed channel: on fog-room-chromatic
//!   1.5× the time per sample for 0.75× the error, less efficient than
//!   sampling it.) A flight may also aim at a point on a light
//!   ([`FlightOptions::aim`]): a share of its collisions then move to
//!   equiangular samples towards it (distance and equiangular sampling,
//!   one-sample MIS). [`UniformFlight`] describes an unaimed flight in
//!   closed form, for estimators weighed against its collisions.

use super::emitters::HitWeighting;
use super::volume::{MajorantSegment, MajorantWalk, RegionScratch, Volume};
use super::{chromatic_transmittance, free_flight};
use crate::color::Rgb;
use crate::ray::Ray;
use crate::sampler::RandomStream;
use crate::sampling::EquiangularSampler;
use glam::Vec3;

/// Most volumes a scene may hold: segments record which overlap in a
/// 32-bit mask.
pub const MAX_VOLUMES: usize = 32;

/// Ratio tracking plays Russian roulette once its estimate is below this.
const RATIO_ROULETTE: f32 = 0.1;

/// The probability with which a collision on a uniform piece is moved to
/// an equiangular sample towards the flight's aim, when it has one
/// ([`FlightOptions::aim`]). A moved collision multiplies the path's
/// throughput by the ratio of the distance density to the mixture's,
/// up to `1/(1 − share)` far from the light; over a deep path those
/// factors compound, and at ½ (Cycles' share) fog-room-chromatic's deep
/// paths reached throughputs of 10⁴: one pixel held half a 320×240
/// image's error. At 0.35 (at most 1.54 per event) the worst 0.1 % of
/// pixels carry 5–6 % of it, for about 6 % less efficiency at 160×120
/// (docs/benchmarks.md); 0.25 lost 10 %.
const EQUIANGULAR_SHARE: f32 = 0.35;

/// What a free flight does besides finding its first collision.
#[derive(Default)]
pub struct FlightOptions<'a> {
    /// Gather the volumes' emission that reaches the ray's origin into
    /// this sum, weighted against next event estimation towards the
    /// media by the [`HitWeighting`] if the origin did that.
    pub emitted: Option<(&'a mut Rgb, Option<HitWeighting<'a>>)>,
    /// A point on a light: on a uniform piece, a flight that collides
    /// there moves its collision with probability [`EQUIANGULAR_SHARE`]
    /// to an equiangular sample towards the point (Kulla and Fajardo
    /// 2012) and is weighted by the two strategies' mixture density
    /// (one-sample MIS, Veach 1997 §9.2.4), so collisions crowd where that
    /// light is bright. Escapes keep their probability: a surface seen
    /// through thin fog is not reweighted. A path that continues from the
    /// moved collision carries the ratio of the densities in its
    /// throughput, event after event; next to a point light, where that
    /// ratio swings widest, `volpath` does not aim but samples NEE
    /// equiangularly instead.
    pub aim: Option<Vec3>,
}

/// Where a free flight through the volumes ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Collision {
    /// A real scattering event at `t` in volume `volume`; the throughput
    /// has been weighted.
    Scatter { t: f32, volume: usize },
    /// Absorbed: the path carries nothing further.
    Absorbed,
    /// Reached the end of the interval.
    Escaped,
}

/// Random numbers and scratch buffers for tracking along one path.
pub struct VolumeTracker {
    rng: RandomStream,
    segments: Vec<MajorantSegment>,
    merged: Vec<MajorantSegment>,
    breaks: Vec<f32>,
    scratch: RegionScratch,
    /// The flight [`VolumeTracker::even_flight_density`] describes.
    even_flight: UniformFlight,
}

impl VolumeTracker {
    pub fn new(rng: RandomStream) -> Self {
        Self {
            rng,
            segments: Vec::new(),
            merged: Vec::new(),
            breaks: Vec::new(),
            scratch: RegionScratch::default(),
            even_flight: UniformFlight::default(),
        }
    }

    /// Transmittance of `volumes` over `[t0, t1]` along `ray`, per
    /// channel, by ratio tracking (exactly 1 with no volume in the way;
    /// 0 over an infinite length with extinction).
    pub fn transmittance(&mut self, volumes: &[Volume], ray: &Ray, t0: f32, t1: f32) -> Rgb {
        if volumes.is_empty() {
            return Rgb::ONE;
        }
        let mut segments = self.segments(volumes, ray, t0, t1);
        let mut estimate = Rgb::ONE;
        while let Some(segment) = segments.next(&self.segments) {
            if let Some(sigma_t) = uniform_extinction(volumes, segment.mask) {
                estimate *= chromatic_transmittance(sigma_t, segment.t1 - segment.t0);
                continue;
            }
            if !segment.t1.is_finite() {
                return Rgb::ZERO;
            }
            let mut t = segment.t0;
            loop {
                t -= (1.0 - self.rng.next_f32()).ln() / segment.majorant;
                if t >= segment.t1 {
                    break;
                }
                let sigma_t = extinction(volumes, segment.mask, ray, t);
                estimate *= (Rgb::ONE - sigma_t / segment.majorant).max(Rgb::ZERO);
                let q = estimate.max_element();
                if q < RATIO_ROULETTE {
                    // Continue with probability 0.5, doubling: unbiased.
                    if q <= 0.0 || self.rng.next_f32() >= 0.5 {
                        return Rgb::ZERO;
                    }
                    estimate *= 2.0;
                }
            }
        }
        estimate
    }

    /// Samples the first real collision in `volumes` on `[t0, t1]` along
    /// `ray` by spectral tracking (uniform pieces in closed form), weighting
    /// `throughput` so that its expectation over the outcomes is the exact
    /// transmittance-weighted path contribution. With `options.emitted`,
    /// adds to that sum the volumes' emission that reaches the ray's
    /// origin from the walk, times the incoming throughput: an unbiased
    /// estimate of `β·∫ T(t)·j(t) dt` up to the collision (module doc),
    /// each volume's emission weighted against next event estimation
    /// towards it by the [`HitWeighting`] if the ray's origin did that.
    pub fn sample_collision(
        &mut self,
        volumes: &[Volume],
        ray: &Ray,
        t0: f32,
        t1: f32,
        throughput: &mut Rgb,
        options: FlightOptions,
    ) -> Collision {
        if volumes.is_empty() {
            return Collision::Escaped;
        }
        let FlightOptions { mut emitted, aim } = options;
        let mut segments = self.segments(volumes, ray, t0, t1);
        while let Some(segment) = segments.next(&self.segments) {
            if let Some(sigma_t) = uniform_extinction(volumes, segment.mask) {
                let piece = UniformPiece {
                    ray,
                    segment: &segment,
                    sigma_t,
                    aim,
                };
                match self.uniform_flight(volumes, &piece, throughput) {
                    Collision::Escaped => continue,
                    collision => return collision,
                }
            }
            let majorant = segment.majorant;
            let mut t = segment.t0;
            loop {
                t -= (1.0 - self.rng.next_f32()).ln() / majorant;
                if t >= segment.t1 {
                    break;
                }
                let beta = *throughput;
                let norm = majorant * beta.element_sum();
                if norm.is_nan() || norm <= 0.0 {
                    return Collision::Absorbed;
                }
                let mut sigma_t = Rgb::ZERO;
                let mut sigma_s = Rgb::ZERO;
                let mut j = Rgb::ZERO;
                let x = ray.at(t);
                let weighting = emitted.as_ref().map(|(_, w)| *w);
                for_each_volume(volumes, segment.mask, |i, v| {
                    let e = v.extinction_at(x);
                    sigma_t += e;
                    sigma_s += e * v.albedo;
                    if let Some(weighting) = weighting {
                        let jv = v.emission_at(x);
                        if jv != Rgb::ZERO {
                            let w = weighting.map_or(1.0, |h| h.weight(i, x, e.max_element()));
                            j += jv * w;
                        }
                    }
                });
                if let Some((sum, _)) = emitted.as_mut() {
                    // At every tentative collision, before its outcome.
                    **sum += beta * j / majorant;
                }
                let sigma_n = (Rgb::splat(majorant) - sigma_t).max(Rgb::ZERO);
                let p_scatter = (beta * sigma_s).element_sum() / norm;
                let p_null = (beta * sigma_n).element_sum() / norm;
                let u = self.rng.next_f32();
                if u < p_scatter {
                    // Which volume scatters: the same weighted shares. If
                    // rounding leaves `pick` past the last share, the last
                    // volume that scatters takes it.
                    let (chosen, last) = scatterer(volumes, segment.mask, beta, u * norm, |v| {
                        v.extinction_at(x) * v.albedo
                    });
                    // u < p_scatter, so some volume scatters here.
                    let Some(chosen) = chosen.or(last) else {
                        return Collision::Absorbed;
                    };
                    *throughput *= chosen.sigma_s * (norm / (majorant * chosen.share));
                    return Collision::Scatter {
                        t,
                        volume: chosen.index,
                    };
                } else if u < p_scatter + p_null {
                    *throughput *= sigma_n / (majorant * p_null);
                } else {
                    return Collision::Absorbed;
                }
            }
        }
        Collision::Escaped
    }

    /// A free flight across a uniform piece, drawn in closed form by
    /// one-sample spectral MIS (module doc), its collisions mixed with
    /// equiangular samples towards the piece's aim if it has one: a real
    /// scattering in volume i at s, with `throughput` weighted to
    /// `β·σs_i·T(s)·⟨β·σt·T(s)⟩ / (⟨β·σs_i·T(s)⟩·p(s))`, p the collisions'
    /// density `(1 − q)·p_d(s) + q·(1 − P_escape)·p_e(s)` (q the
    /// equiangular share; without an aim `p_d(s) = ⟨β·σt·T(s)⟩/Σβ`, which
    /// leaves the throughput's channel sum unchanged); an absorption; or
    /// an escape past the piece, weighted by `T(ℓ)` over the probability of
    /// escaping, `P_escape = Σ_c w_c·T_c(ℓ)`.
    fn uniform_flight(
        &mut self,
        volumes: &[Volume],
        piece: &UniformPiece,
        throughput: &mut Rgb,
    ) -> Collision {
        let UniformPiece {
            ray,
            segment,
            sigma_t,
            aim,
        } = *piece;
        let beta = *throughput;
        let total = beta.element_sum();
        if total.is_nan() || total <= 0.0 {
            return Collision::Absorbed;
        }
        let length = segment.t1 - segment.t0;
        let equiangular = aim.and_then(|y| EquiangularSampler::new(ray, y, segment.t0, segment.t1));
        let p_aim = if equiangular.is_some() {
            EQUIANGULAR_SHARE
        } else {
            0.0
        };
        // The channel whose exponential draws the distance is chosen with
        // probability w_c = β_c/Σβ.
        let w = beta / total;
        let rate = sigma_t[pick_channel(w, self.rng.next_f32())];
        let u = self.rng.next_f32();
        let flight = (rate > 0.0)
            .then(|| free_flight(rate, 0.0, length, u))
            .flatten();
        let escape = || {
            let t = chromatic_transmittance(sigma_t, length);
            (t, (w * t).element_sum())
        };
        let Some(s) = flight else {
            let (t, p_escape) = escape();
            *throughput *= t / p_escape;
            return Collision::Escaped;
        };
        // A collision: with probability p_aim it moves to an equiangular
        // sample of the piece, so collisions have the density
        // (1 − p_aim)·p_d(s) + p_aim·(1 − P_escape)·p_e(s), and escapes
        // keep theirs.
        let s = match equiangular {
            Some(e) if self.rng.next_f32() < p_aim => {
                (e.sample(self.rng.next_f32()).0 - segment.t0).min(length)
            }
            _ => s,
        };
        // A real collision at s: volume i scatters with probability
        // ⟨β·σs_i·T(s)⟩/⟨β·σt·T(s)⟩, else the flight is absorbed.
        let bt = beta * chromatic_transmittance(sigma_t, s);
        let collide = (bt * sigma_t).element_sum();
        // Where the transmittance has fallen below f32's normal range (an
        // equiangular sample far out on an endless ray) the flight carries
        // nothing that f32 can hold: absorbed.
        if collide.is_nan() || collide < f32::MIN_POSITIVE {
            return Collision::Absorbed;
        }
        let pdf = (1.0 - p_aim) * collide / total
            + equiangular.map_or(0.0, |e| p_aim * (1.0 - escape().1) * e.pdf(segment.t0 + s));
        // Past the last share, `pick` falls in the absorption's.
        let pick = self.rng.next_f32() * collide;
        let (chosen, _) = scatterer(volumes, segment.mask, bt, pick, |v| v.sigma_t * v.albedo);
        let Some(ScatteringVolume {
            index: volume,
            sigma_s,
            share,
        }) = chosen
        else {
            return Collision::Absorbed;
        };
        *throughput = bt * sigma_s * (collide / share / pdf);
        Collision::Scatter {
            t: segment.t0 + s,
            volume,
        }
    }

    /// The closed-form description of a free flight along `ray` over
    /// `[t0, t1]` that starts with throughput `beta`, written to `flight`:
    /// its pieces, each with the channel weights and the probability of
    /// reaching it that [`VolumeTracker::sample_collision`] gives a flight
    /// there, so that [`UniformFlight::density`] is the density of its
    /// distance-sampled collisions. False where a volume on the way is not
    /// uniform and quiet (the density has no closed form there).
    pub fn describe_uniform_flight(
        &mut self,
        volumes: &[Volume],
        ray: &Ray,
        t0: f32,
        t1: f32,
        beta: Rgb,
        flight: &mut UniformFlight,
    ) -> bool {
        flight.pieces.clear();
        if volumes.is_empty() {
            return true;
        }
        self.collect(volumes, ray, t0, t1);
        let (mut beta, mut reach) = (beta, 1.0);
        for segment in &self.segments {
            let Some(sigma_t) = uniform_extinction(volumes, segment.mask) else {
                return false;
            };
            let total = beta.element_sum();
            if !(total > 0.0 && reach > 0.0) {
                break;
            }
            let w = beta / total;
            flight.pieces.push(FlightPiece {
                t0: segment.t0,
                t1: segment.t1,
                sigma_t,
                w,
                reach,
                mask: segment.mask,
            });
            // An escape is weighted by T(ℓ)/P_escape (uniform_flight).
            let t = chromatic_transmittance(sigma_t, segment.t1 - segment.t0);
            let p_escape = (w * t).element_sum();
            beta = beta * t / p_escape;
            reach *= p_escape;
        }
        true
    }

    /// The density at `t` of the collision of a flight from `ray`'s
    /// origin whose channels weigh evenly (β = 1 at the origin):
    /// [`UniformFlight::density`] of that flight, without describing it
    /// past `t`; 0 where a volume before `t` is not uniform and quiet, or
    /// none is at `t`. A density the light-vertex connections and the
    /// strategies they compete with all weigh by alike.
    pub fn even_flight_density(&mut self, volumes: &[Volume], ray: &Ray, t: f32) -> f32 {
        if t.is_nan() || t <= 0.0 {
            return 0.0;
        }
        let mut flight = std::mem::take(&mut self.even_flight);
        let density = if self.describe_uniform_flight(volumes, ray, 0.0, t, Rgb::ONE, &mut flight) {
            flight.density(t)
        } else {
            0.0
        };
        self.even_flight = flight;
        density
    }

    /// The ordered majorant segments of all volumes on `[t0, t1]` with a
    /// positive majorant, for [`Segments::next`]. One volume without a
    /// mesh region (the common case) is walked lazily, so a flight that
    /// collides early, or a shadow ray that roulette ends, never walks
    /// the rest of the ray (as pbrt-v4's `DDAMajorantIterator`); otherwise
    /// they are collected into `self.segments` first.
    fn segments<'a>(&mut self, volumes: &'a [Volume], ray: &Ray, t0: f32, t1: f32) -> Segments<'a> {
        if let [volume] = volumes
            && let Some(walk) = volume.majorant_walk(ray, t0, t1, 1)
        {
            return Segments::Walk(walk);
        }
        self.collect(volumes, ray, t0, t1);
        Segments::Collected(0)
    }

    /// Fills `segments` with the ordered majorant segments of all volumes
    /// on `[t0, t1]`, summing majorants where volumes overlap.
    fn collect(&mut self, volumes: &[Volume], ray: &Ray, t0: f32, t1: f32) {
        self.segments.clear();
        for (i, volume) in volumes.iter().enumerate() {
            volume.majorant_segments(ray, t0, t1, 1 << i, &mut self.scratch, &mut self.segments);
        }
        if volumes.len() > 1 {
            self.merge();
        }
        self.segments.retain(|s| s.majorant > 0.0);
    }

    /// Replaces overlapping segments by their sums over every elementary
    /// interval between breakpoints.
    fn merge(&mut self) {
        self.breaks.clear();
        self.breaks
            .extend(self.segments.iter().flat_map(|s| [s.t0, s.t1]));
        self.breaks.sort_by(f32::total_cmp);
        self.breaks.dedup();
        self.merged.clear();
        for pair in self.breaks.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let mid = if b.is_finite() { 0.5 * (a + b) } else { a };
            let (mut majorant, mut mask) = (0.0, 0);
            for s in &self.segments {
                if s.t0 <= mid && mid < s.t1 {
                    majorant += s.majorant;
                    mask |= s.mask;
                }
            }
            if mask != 0 {
                self.merged.push(MajorantSegment {
                    t0: a,
                    t1: b,
                    majorant,
                    mask,
                });
            }
        }
        std::mem::swap(&mut self.segments, &mut self.merged);
    }
}

/// Majorant segments in order along a ray ([`VolumeTracker::segments`]).
enum Segments<'a> {
    /// Walked as they are needed.
    Walk(MajorantWalk<'a>),
    /// The tracker's collected segments, from this index on.
    Collected(usize),
}

impl Segments<'_> {
    /// The next segment with a positive majorant; `collected` is the
    /// tracker's list.
    #[inline]
    fn next(&mut self, collected: &[MajorantSegment]) -> Option<MajorantSegment> {
        match self {
            Self::Walk(walk) => walk.find(|s| s.majorant > 0.0),
            Self::Collected(index) => {
                let segment = collected.get(*index).copied();
                *index += 1;
                segment
            }
        }
    }
}

/// A free flight through uniform volumes in closed form
/// ([`VolumeTracker::describe_uniform_flight`]): where its collisions fall, and the
/// transmittance and in-scattering along it. One value serves a whole
/// path: refilled for each segment without allocating.
#[derive(Clone, Debug, Default)]
pub struct UniformFlight {
    pieces: Vec<FlightPiece>,
}

/// A uniform piece `[t0, t1]` of a flight: the summed extinction of the
/// volumes in `mask` there, the channel weights `w = β/Σβ` of the flight
/// entering it, and the probability `reach` that it gets there.
#[derive(Clone, Copy, Debug)]
struct FlightPiece {
    t0: f32,
    t1: f32,
    sigma_t: Rgb,
    w: Rgb,
    reach: f32,
    mask: u32,
}

impl UniformFlight {
    /// Whether the flight crosses no volume.
    pub fn is_empty(&self) -> bool {
        self.pieces.is_empty()
    }

    /// The piece holding `t` (the earlier one where two meet: a flight
    /// described up to `t` ends its last piece there).
    fn piece_at(&self, t: f32) -> Option<&FlightPiece> {
        self.pieces.iter().find(|p| p.t0 <= t && t <= p.t1)
    }

    /// The density of the flight's distance-sampled collision at `t`
    /// (one-sample spectral MIS, module doc):
    /// `reach·Σ_c w_c·σt_c·T_c(t − t0)` in the piece holding `t`, 0 where
    /// no volume is. Flights aimed at a light move some collisions
    /// ([`FlightOptions::aim`]); this is their density without the move.
    pub fn density(&self, t: f32) -> f32 {
        self.piece_at(t).map_or(0.0, |p| {
            let t = chromatic_transmittance(p.sigma_t, t - p.t0);
            p.reach * (p.w * p.sigma_t * t).element_sum()
        })
    }

    /// The volumes' transmittance from the flight's start to `t`, per
    /// channel (Beer–Lambert over each piece crossed).
    pub fn transmittance(&self, t: f32) -> Rgb {
        let mut transmittance = Rgb::ONE;
        for p in self.pieces.iter().take_while(|p| p.t0 < t) {
            transmittance *= chromatic_transmittance(p.sigma_t, t.min(p.t1) - p.t0);
        }
        transmittance
    }

    /// In-scattering at `t` per unit length and solid angle, for light
    /// turned through `cos_theta`: `Σ_i σs_i·p_i(cos θ)` over the volumes
    /// there (each with its own phase function); 0 where none is.
    pub fn in_scattering(&self, volumes: &[Volume], t: f32, cos_theta: f32) -> Rgb {
        let mut sum = Rgb::ZERO;
        if let Some(p) = self.piece_at(t) {
            for_each_volume(volumes, p.mask, |_, v| {
                sum += v.sigma_t * v.albedo * v.phase.eval(cos_theta);
            });
        }
        sum
    }
}

/// A piece of a ray on which the volumes are uniform and quiet, and what
/// its flight aims at.
#[derive(Clone, Copy)]
struct UniformPiece<'a> {
    ray: &'a Ray,
    segment: &'a MajorantSegment,
    /// The volumes' summed extinction there.
    sigma_t: Rgb,
    aim: Option<Vec3>,
}

/// The channel c with `u` in its share of the cumulative probabilities
/// `w`; rounding past the last share falls to the last channel with a
/// positive one.
#[inline]
fn pick_channel(w: Rgb, u: f32) -> usize {
    let (mut channel, mut cumulative) = (0, 0.0);
    for c in 0..3 {
        if w[c] > 0.0 {
            channel = c;
            cumulative += w[c];
            if u < cumulative {
                break;
            }
        }
    }
    channel
}

/// The summed constant extinction of the volumes in `mask`, if every one
/// of them is uniform and quiet ([`Volume::uniform_extinction`]).
#[inline]
fn uniform_extinction(volumes: &[Volume], mask: u32) -> Option<Rgb> {
    let mut sigma_t = Some(Rgb::ZERO);
    for_each_volume(volumes, mask, |_, v| {
        sigma_t = sigma_t.zip(v.uniform_extinction()).map(|(a, b)| a + b);
    });
    sigma_t
}

/// A volume that may scatter at a collision: its index, its σs there and
/// its share `⟨β·σs⟩` of the collision.
#[derive(Clone, Copy)]
struct ScatteringVolume {
    index: usize,
    sigma_s: Rgb,
    share: f32,
}

/// A volume in `mask` chosen to scatter with probability proportional to
/// its share `⟨β·σs_i⟩` (`sigma_s` gives its σs_i there): the first whose
/// share holds `pick` once the shares before it are taken off, if `pick`
/// is below their sum; and the last volume with a share at all, which
/// takes what rounding leaves past the final share where the caller knows
/// some volume scatters.
#[inline]
fn scatterer(
    volumes: &[Volume],
    mask: u32,
    beta: Rgb,
    mut pick: f32,
    sigma_s: impl Fn(&Volume) -> Rgb,
) -> (Option<ScatteringVolume>, Option<ScatteringVolume>) {
    let (mut chosen, mut last) = (None, None);
    for_each_volume(volumes, mask, |index, v| {
        let sigma_s = sigma_s(v);
        let share = (beta * sigma_s).element_sum();
        if share > 0.0 {
            last = Some(ScatteringVolume {
                index,
                sigma_s,
                share,
            });
            if chosen.is_none() && pick < share {
                chosen = last;
            }
            pick -= share;
        }
    });
    (chosen, last)
}

/// Summed extinction of the volumes in `mask` at `ray.at(t)`.
#[inline]
fn extinction(volumes: &[Volume], mask: u32, ray: &Ray, t: f32) -> Rgb {
    let mut sigma_t = Rgb::ZERO;
    for_each_volume(volumes, mask, |_, v| sigma_t += v.extinction_at(ray.at(t)));
    sigma_t
}

#[inline]
fn for_each_volume(volumes: &[Volume], mut mask: u32, mut visit: impl FnMut(usize, &Volume)) {
    while mask != 0 {
        let i = mask.trailing_zeros() as usize;
        visit(i, &volumes[i]);
        mask &= mask - 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::media::density::Density;
    use crate::media::sparse::{BRICK_VOXELS, Precision, SparseDensity, SparseGrid};
    use crate::media::volume::VolumeRegion;
    use crate::phase::PhaseFunction;
    use crate::shapes::Bounds;
    use glam::{IVec3, Mat4, Vec3};

    /// Sparse traversal: tentative collisions are drawn only on segments
    /// of positive majorant, and a majorant cell is positive only where
    /// trilinear interpolation reads a stored brick. Two half-float
    /// bricks 72 voxels apart along x, with seven empty bricks between
    /// them: of the eleven majorant cells (one brick wide, centred on
    /// the voxel centres' half-voxel offset) the ray crosses, exactly the
    /// two at each occupied brick (its own, and its neighbour that
    /// interpolates towards it) carry samples.
    #[test]
    fn empty_bricks_cost_no_samples() {
        let mut grid = SparseGrid::with_precision(Mat4::IDENTITY, Precision::Half);
        let full = [u64::MAX; BRICK_VOXELS / 64];
        for x in [0, 80] {
            grid.insert_leaf(IVec3::new(x, 0, 0), &full, &[0.5; BRICK_VOXELS])
                .unwrap();
        }
        assert_eq!(grid.brick_counts(), (2, 0));
        // World x ∈ [0, 88] is index x − 0.5: voxel centres at half-integers.
        let unit_to_index =
            Mat4::from_translation(Vec3::splat(-0.5)) * Mat4::from_scale(Vec3::new(88.0, 8.0, 8.0));
        let density = Density::Sparse(Box::new(SparseDensity {
            grid,
            unit_to_index,
        }));
        let region = VolumeRegion::Box(Bounds::new(Vec3::ZERO, Vec3::new(88.0, 8.0, 8.0)));
        let volume = Volume::new(
            Rgb::splat(2.0),
            Rgb::splat(0.5),
            PhaseFunction::Isotropic,
            density,
            region,
        )
        .unwrap();
        let ray = Ray {
            origin: Vec3::new(-5.0, 4.0, 4.0),
            direction: Vec3::X,
        };
        let mut tracker = VolumeTracker::new(RandomStream::new(1));
        let volumes = [volume];
        tracker.collect(&volumes, &ray, 0.0, 200.0);
        // World x = t − 5; cells 0–1 are x ∈ [0, 16], cells 9–10 x ∈ [72, 88].
        let sampled: Vec<(f32, f32)> = tracker.segments.iter().map(|s| (s.t0, s.t1)).collect();
        let covered: f32 = sampled.iter().map(|(a, b)| b - a).sum();
        assert!((covered - 32.0).abs() < 1e-3, "segments {sampled:?}");
        for &(a, b) in &sampled {
            let inside = |lo: f32, hi: f32| a >= lo - 1e-3 && b <= hi + 1e-3;
            assert!(
                inside(5.0, 21.0) || inside(77.0, 93.0),
                "a segment [{a}, {b}] samples the empty bricks"
            );
        }
        assert!(tracker.segments.iter().all(|s| s.majorant > 0.0));
    }
}
