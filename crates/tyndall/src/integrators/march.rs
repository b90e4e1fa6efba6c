//! The paper's ray march (its §4.2): a Riemann sum of the in-scattering
//! integral with a fixed step `h`, per-step shadow rays to every light.
//!
//! Step points form the lattice `t_k = a + (ξ + k)·h` with one uniform
//! jitter ξ per sample. Every `t` in the fog segment is covered by exactly
//! one lattice point for each ξ, so the estimate is unbiased for any step
//! (docs/physics.md §5.2); a smaller step lowers the variance. Steps outside every
//! light's reach (a spotlight's cone) are skipped without a shadow ray.
//!
//! Interleaved sampling (Keller & Heidrich 2001), optional: the pixels of
//! an `n × n` tile take the `n²` strata of [0, 1) for their jitter, so
//! neighbouring pixels march from different offsets and a few steps give
//! fine-grained noise instead of banding. Each pixel alone is then
//! unbiased only up to its stratum; a tile's average is unbiased.

use super::PixelPosition;
use super::lighting::{MediumQuery, light_point, scattered_radiance};
use super::path_radiance::{Gathered, Keep};
use crate::color::Rgb;
use crate::media::tracking::VolumeTracker;
use crate::media::transmittance;
use crate::sampler::PixelSampler;
use crate::settings::MAX_MARCH_STEPS;
use crate::visibility::{RayCounts, Visibility};

/// The ray march's parameters.
#[derive(Clone, Copy)]
pub struct March<'a> {
    /// Step length `h` between lattice points (scene units).
    pub step: f32,
    /// Interleaving tile size `n` (1: no interleaving; see
    /// [`interleaved_stratum`]).
    pub interleave: u32,
    /// Most specular events (dielectrics, reflective layers) a camera
    /// path follows.
    pub max_bounces: u32,
    pub(crate) visibility: &'a Visibility,
}

/// Optical depth `σt·ℓ` after which a march stops: the camera-side
/// transmittance is then below `e^{−9.21} = 10⁻⁴`, so the in-scattering
/// left out is under 10⁻⁴ of the brightest in-scattered radiance
/// `albedo·L_in` beyond that point. This bounds the march on rays that
/// leave the scene in unbounded fog.
pub const MAX_OPTICAL_DEPTH: f32 = 9.21;

/// The jitter stratum `(k, n²)` of `pixel` in an `n × n` interleaving
/// tile (`n = 1`: no interleaving). For `n` a power of two the strata
/// follow the Bayer matrix, so neighbouring pixels get distant offsets;
/// otherwise they are in row order.
pub fn interleaved_stratum(pixel: PixelPosition, n: u32) -> (u32, u32) {
    let n = n.max(1);
    let (x, y) = (pixel.x % n, pixel.y % n);
    let k = if n.is_power_of_two() {
        // Bayer: M₂ = [[0, 2], [3, 1]], M₂ₙ = 4·Mₙ(low bits) + M₂(high
        // bit); each bit pair (x_b, y_b) contributes 2·(x_b ⊕ y_b) + y_b.
        let bits = n.trailing_zeros();
        (0..bits).fold(0, |k, b| {
            let (xb, yb) = ((x >> b) & 1, (y >> b) & 1);
            k * 4 + 2 * (xb ^ yb) + yb
        })
    } else {
        y * n + x
    };
    (k, n * n)
}

/// In-scattered radiance along the query's ray over `(0, t_hit)`,
/// relative to the radiance at the ray origin (one sample), with the
/// jitter drawn in stratum `k` of `count` (see [`interleaved_stratum`]).
// Inlined into both instantiations of the camera path (with and without
// the components; see `camera_path::InScattering::estimate`).
#[inline(always)]
pub(crate) fn in_scattered<K: Keep>(
    medium: &MediumQuery,
    step: f32,
    (k, count): (u32, u32),
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
) -> Gathered<K> {
    let jitter = (k as f32 + sampler.next_1d()) / count as f32;
    lattice_sum(medium, step, jitter, sampler, counts, tracker)
}

/// The march's Riemann sum `Σ_k T(a, t_k)·Σ_lights σs·p·E·V·h` over the
/// lattice `t_k = a + (jitter + k)·step` in the fog part `[a, b)` of the
/// query's ray (the paper's eq. 1 per step), `sampler` drawing only area
/// lights' points.
fn lattice_sum<K: Keep>(
    medium: &MediumQuery,
    step: f32,
    jitter: f32,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
) -> Gathered<K> {
    let (scene, fog, ray) = (medium.scene, medium.fog, &medium.ray);
    let mut sum = Gathered::new();
    let Some((a, b)) = fog.interval(ray, 0.0, medium.t_hit) else {
        return sum;
    };
    if fog.sigma_s() == Rgb::ZERO {
        return sum;
    }
    let b = b.min(a + MAX_OPTICAL_DEPTH / fog.sigma_t);
    // Only the lattice points inside some light's reach need visiting.
    let Some((lo, hi)) = scene
        .lights
        .iter()
        .filter_map(|l| l.reach(ray, a, b))
        .reduce(|(l0, h0), (l1, h1)| (l0.min(l1), h0.max(h1)))
    else {
        return sum;
    };
    // Lattice indices k with lo ≤ t_k < hi, counted in integers (an f32
    // counter stops at 2²⁴, issue 11) and in f64 so the division cannot
    // overflow; at most MAX_MARCH_STEPS over the lights, which the settings
    // were checked against (the cap only guards callers that skipped it).
    let (first, end) = lattice_range(a, lo, hi, step, jitter);
    let budget = MAX_MARCH_STEPS / scene.lights.len().max(1) as u64;
    let end = end.min(first.saturating_add(budget));
    for index in first..end {
        let t = a + (jitter + index as f32) * step;
        if t >= hi {
            break;
        }
        let x = ray.at(t);
        let camera_t = transmittance(fog.sigma_t, t - a);
        for (light_index, light) in scene.lights.iter().enumerate() {
            let y = light_point(light, sampler);
            sum.add(
                scene.light_group(light_index),
                camera_t * scattered_radiance(medium, light_index, y, x, sampler, counts, tracker),
            );
        }
    }
    sum.scaled(Rgb::splat(step))
}

/// The range `first..end` of lattice indices `k ≥ 0` whose points
/// `t_k = a + (jitter + k)·step` lie in `[lo, hi)`, computed in f64 and
/// saturated to u64 (an unbounded `hi` gives `u64::MAX`).
fn lattice_range(a: f32, lo: f32, hi: f32, step: f32, jitter: f32) -> (u64, u64) {
    let index = |t: f32| {
        let k = ((t as f64 - a as f64) / step as f64 - jitter as f64).ceil();
        // `as` saturates: negative to 0, +∞ to u64::MAX, NaN to 0.
        k.max(0.0) as u64
    };
    (index(lo), index(hi))
}

/// The march's functions as the GPU's twin of them is probed against
/// (crates/tyndall-gpu/tests/march_functions.rs).
pub mod twins {
    use super::super::lighting::twins::{fog_query, tracker};
    use super::*;
    use crate::Scene;
    use crate::integrators::path_radiance::Whole;
    use crate::ray::Ray;

    /// The march's in-scattered radiance along `ray` over `(0, t_hit)` in
    /// `scene`'s fog (none: 0), lattice step `step` and `jitter` ∈ [0, 1)
    /// (one stratum: no interleaving). Area lights' points are drawn from
    /// a fixed stream; the GPU's twin draws others, so compare on delta
    /// lights.
    pub fn in_scattered(
        scene: &Scene,
        visibility: &Visibility,
        ray: Ray,
        t_hit: f32,
        step: f32,
        jitter: f32,
    ) -> Rgb {
        let Some(medium) = fog_query(scene, visibility, ray, t_hit) else {
            return Rgb::ZERO;
        };
        let mut sampler = PixelSampler::new(0, 0, 0);
        let mut tracker = tracker();
        let mut counts = RayCounts::default();
        lattice_sum::<Whole>(
            &medium,
            step,
            jitter,
            &mut sampler,
            &mut counts,
            &mut tracker,
        )
        .total()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (issue 11): with an f32 counter, `index += 1.0` stopped
    /// at 2²⁴ and a step of 3e-7 looped forever; a step of 1e-45 made the
    /// first index infinite and skipped the fog.
    #[test]
    fn lattice_ranges_are_exact_integers() {
        assert_eq!(lattice_range(0.0, 0.0, 1.0, 0.25, 0.5), (0, 4));
        assert_eq!(lattice_range(0.0, 0.3, 1.0, 0.25, 0.0), (2, 4));
        let (first, end) = lattice_range(0.0, 0.0, 10.0, 3e-7, 0.5);
        assert_eq!(first, 0);
        assert!(end > 1 << 24, "{end}");
        let (first, end) = lattice_range(0.0, 0.0, 1.0, 1e-45, 0.5);
        assert_eq!(first, 0);
        assert!(end > 1 << 40, "{end}");
    }
}
