//! Participating media.
//!
//! Two kinds, by what estimating them needs:
//!
//! * [`Fog`]: the paper's medium — homogeneous, everywhere or inside a
//!   box, with grey extinction `sigma_t` (the paper's density τ, per scene
//!   unit) and an RGB `albedo`, so `sigma_s = albedo·sigma_t`.
//!   Transmittance over a length `d` is `T = exp(−sigma_t·d)` in closed
//!   form, which the equiangular and distance sampling of every integrator
//!   relies on.
//! * [`volume::Volume`]: the general medium — RGB extinction, a density
//!   field (uniform, procedural [`noise`], a voxel [`grid`] or a
//!   [`sparse`] grid from OpenVDB) inside a
//!   box or a closed mesh; estimated by [`tracking`] (delta and ratio
//!   tracking against per-cell majorants), and may emit light
//!   ([`emission`]). `volpath` renders them.

pub mod density;
pub mod emission;
pub mod emitters;
pub mod grid;
pub mod noise;
pub mod sparse;
pub mod tracking;
pub mod volume;

use crate::color::Rgb;
use crate::phase::PhaseFunction;
use crate::ray::Ray;
use crate::shapes::Bounds;

/// Homogeneous fog filling all space (`bounds = None`) or an
/// axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fog {
    /// Extinction coefficient σt (1/scene unit), ≥ 0.
    pub sigma_t: f32,
    /// Single-scattering albedo per channel (σs/σt).
    pub albedo: Rgb,
    pub phase: PhaseFunction,
    pub bounds: Option<Bounds>,
}

impl Fog {
    /// Scattering coefficient σs = albedo·σt per channel.
    #[inline]
    pub fn sigma_s(&self) -> Rgb {
        self.albedo * self.sigma_t
    }

    /// Whether the fog fills all space and scatters some channel without
    /// absorbing it (albedo 1): a path's throughput in that channel never
    /// falls, so Russian roulette never ends the path, which wanders on
    /// through the endless fog.
    pub fn is_endless_and_lossless(&self) -> bool {
        self.bounds.is_none() && self.sigma_t > 0.0 && self.albedo.max_element() >= 1.0
    }

    /// The part of `[t0, t1]` along `ray` that lies in the fog (one
    /// interval: a box is convex).
    #[inline]
    pub fn interval(&self, ray: &Ray, t0: f32, t1: f32) -> Option<(f32, f32)> {
        match &self.bounds {
            None => (t0 < t1).then_some((t0, t1)),
            Some(b) => b.clip_ray(ray, t0, t1).filter(|(a, b)| a < b),
        }
    }

    /// Transmittance over `distance` from `origin` along the unit
    /// `direction` (towards a light, say; ∞ for a sun).
    #[inline]
    pub fn transmittance_along(
        &self,
        origin: glam::Vec3,
        direction: glam::Vec3,
        distance: f32,
    ) -> f32 {
        self.transmittance(&Ray { origin, direction }, 0.0, distance)
    }

    /// Transmittance `exp(−σt·ℓ)` where ℓ is the length of `[t0, t1]`
    /// inside the fog; 0 for an infinite length in fog.
    #[inline]
    pub fn transmittance(&self, ray: &Ray, t0: f32, t1: f32) -> f32 {
        match self.interval(ray, t0, t1) {
            Some((a, b)) => transmittance(self.sigma_t, b - a),
            None => 1.0,
        }
    }
}

/// A free-flight distance in homogeneous fog entered at `a`: `a − ln(1 −
/// u)/σt`, density `σt·e^{−σt(t−a)}`; `None` if it lies beyond `b` (the
/// flight leaves the fog, probability `e^{−σt(b−a)}`). σt must be > 0.
#[inline]
pub fn free_flight(sigma_t: f32, a: f32, b: f32, u: f32) -> Option<f32> {
    let t = a - (1.0 - u).ln() / sigma_t;
    (t < b).then_some(t)
}

/// Beer–Lambert transmittance per channel, [`transmittance`] of each of
/// `sigma_t`'s channels over `distance`.
#[inline]
pub fn chromatic_transmittance(sigma_t: Rgb, distance: f32) -> Rgb {
    Rgb::new(
        transmittance(sigma_t.x, distance),
        transmittance(sigma_t.y, distance),
        transmittance(sigma_t.z, distance),
    )
}

/// Beer–Lambert transmittance `exp(−σt·d)` of a homogeneous medium; exact
/// 1 for σt = 0 even over an infinite distance.
#[inline]
pub fn transmittance(sigma_t: f32, distance: f32) -> f32 {
    if sigma_t == 0.0 {
        1.0
    } else {
        (-sigma_t * distance).exp()
    }
}
