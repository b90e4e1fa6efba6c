//! How much of a surface is there: glTF's `alphaMode` (glTF 2.0 §3.9.4)
//! on a surface's coverage, its base colour's alpha (`baseColorFactor`
//! alpha times the base colour texture's, linear).
//!
//! - `MASK` cuts the surface out: below a cutoff it is a hole that every
//!   ray passes, elsewhere wholly there.
//! - `BLEND` covers a fraction of it: a ray meets it with probability the
//!   coverage and passes it otherwise, so that each ray, camera, shadow
//!   or light path, sees the surface's light weighed by its coverage and
//!   what lies behind by the rest — in expectation, as Cycles' Principled
//!   BSDF mixes its Transparent BSDF by alpha. The choice is made by a
//!   number hashed from the ray and the primitive (as pbrt-v4's
//!   `GeometricPrimitive` tests alpha, "stochastic alpha"): it needs no
//!   sampler dimension, every query of the same ray against the same
//!   primitive answers alike, and the primitives along a ray are chosen
//!   independently.

use crate::ray::Ray;

/// A surface's coverage rule, on its coverage `factor · α(p)` (α the base
/// colour texture's alpha at the point, 1 without one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Coverage {
    /// glTF `MASK`: a hole where the coverage is below `cutoff`
    /// (glTF's `alphaCutoff`, 0.5 by default), in `[0, 1]`.
    Cutout { cutoff: f32, factor: f32 },
    /// glTF `BLEND`: the surface is met with probability the coverage.
    Partial { factor: f32 },
}

impl Coverage {
    /// The factor on the texture's alpha (glTF's `baseColorFactor`
    /// alpha), in `[0, 1]`.
    pub fn factor(&self) -> f32 {
        match *self {
            Coverage::Cutout { factor, .. } | Coverage::Partial { factor } => factor,
        }
    }

    /// Whether the surface is a hole everywhere, whatever its texture's
    /// alpha (≤ 1) is.
    pub fn is_empty(&self) -> bool {
        match *self {
            Coverage::Cutout { cutoff, factor } => factor < cutoff,
            Coverage::Partial { factor } => factor <= 0.0,
        }
    }

    /// Whether a ray passes the surface where its texture's alpha is
    /// `alpha`: for a cut-out where the coverage is below the cutoff; for
    /// partial coverage where `u` (uniform in `[0, 1)`, see
    /// [`ray_number`]) is at least the coverage.
    #[inline]
    pub fn passes(&self, alpha: f32, u: f32) -> bool {
        match *self {
            Coverage::Cutout { cutoff, factor } => factor * alpha < cutoff,
            Coverage::Partial { factor } => u >= factor * alpha,
        }
    }

    /// Whether the rule needs a number per ray ([`Coverage::passes`]'s
    /// `u`).
    #[inline]
    pub fn is_stochastic(&self) -> bool {
        matches!(self, Coverage::Partial { .. })
    }
}

/// A number uniform in `[0, 1)` for `ray` meeting `primitive`: the bits
/// of the ray's origin and direction and the primitive's index, mixed by
/// SplitMix64's finaliser (Steele et al. 2014, "Fast splittable
/// pseudorandom number generators") after each word, so that rays that
/// differ in any bit, and the primitives along one ray, get independent
/// numbers.
#[inline]
pub fn ray_number(ray: &Ray, primitive: u32) -> f32 {
    let words = [
        ray.origin.x.to_bits(),
        ray.origin.y.to_bits(),
        ray.origin.z.to_bits(),
        ray.direction.x.to_bits(),
        ray.direction.y.to_bits(),
        ray.direction.z.to_bits(),
        primitive,
    ];
    let mut h = 0x9E37_79B9_7F4A_7C15u64;
    for word in words {
        h = mix(h ^ u64::from(word));
    }
    // The top 24 bits, exactly representable: [0, 1 − 2⁻²⁴].
    (h >> 40) as f32 / (1u32 << 24) as f32
}

/// SplitMix64's finaliser: every input bit flips each output bit with
/// probability about ½.
#[inline]
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// The numbers of nearby rays, and of one ray against successive
    /// primitives, are uniform: each tenth of [0, 1) gets its share of
    /// 10⁵ numbers within 5σ of the binomial, and the numbers of one ray
    /// against primitives k and k + 1 are uncorrelated (their product's
    /// mean ¼ within 5σ).
    #[test]
    fn ray_numbers_are_uniform_and_independent() {
        let n = 100_000;
        let mut bins = [0u32; 10];
        let mut product = 0.0f64;
        for i in 0..n {
            // Camera rays through neighbouring film positions.
            let x = (i % 400) as f32 / 400.0;
            let y = (i / 400) as f32 / 250.0;
            let ray = Ray::new(Vec3::new(0.0, 1.0, 5.0), Vec3::new(x - 0.5, 0.5 - y, -1.0));
            let u = ray_number(&ray, 7);
            assert!((0.0..1.0).contains(&u));
            bins[(u * 10.0) as usize] += 1;
            product += f64::from(u * ray_number(&ray, 8));
        }
        let expected = f64::from(n) / 10.0;
        let sigma = (expected * 0.9).sqrt();
        for (k, &count) in bins.iter().enumerate() {
            assert!(
                (f64::from(count) - expected).abs() < 5.0 * sigma,
                "tenth {k}: {count} of {n}"
            );
        }
        // Var(u·v) = E[u²]E[v²] − 1/16 = 1/9 − 1/16.
        let sigma = ((1.0 / 9.0 - 1.0 / 16.0) / f64::from(n)).sqrt();
        let mean = product / f64::from(n);
        assert!((mean - 0.25).abs() < 5.0 * sigma, "E[u·v] = {mean}");
    }

    /// A cut-out is a hole below its cutoff; partial coverage is passed
    /// where the number reaches the coverage.
    #[test]
    fn rules_pass_as_they_say() {
        let mask = Coverage::Cutout {
            cutoff: 0.5,
            factor: 0.8,
        };
        assert!(mask.passes(0.6, 0.0) && !mask.passes(0.7, 0.99));
        assert!(!mask.is_empty() && !mask.is_stochastic());
        let blend = Coverage::Partial { factor: 0.5 };
        assert!(blend.passes(1.0, 0.5) && !blend.passes(1.0, 0.49));
        assert!(blend.passes(0.0, 0.0) && blend.is_stochastic());
        assert!(Coverage::Partial { factor: 0.0 }.is_empty());
        assert!(
            Coverage::Cutout {
                cutoff: 0.5,
                factor: 0.4
            }
            .is_empty()
        );
    }
}
