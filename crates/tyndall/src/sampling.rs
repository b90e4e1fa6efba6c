//! Distance sampling along a ray in homogeneous fog.
//!
//! Two strategies for choosing where along a camera ray light scatters:
//! [`EquiangularSampler`] (Kulla & Fajardo 2012), whose density is
//! proportional to the 1/r² fall-off of a point emitter, and
//! [`ExponentialSampler`], proportional to the camera-side transmittance.
//! The `single` integrator combines them with multiple importance sampling.

use crate::ray::Ray;
use glam::Vec3;

/// Equiangular sampling of `t ∈ [a, b]` for an emitting point `y`: the
/// density `D / ((θ_b − θ_a)(D² + (t − Δ)²))` cancels the `1/|x(t) − y|²`
/// of the point's irradiance, where `Δ` is the ray parameter of the point
/// closest to `y` and `D` its distance from `y`.
#[derive(Clone, Copy, Debug)]
pub struct EquiangularSampler {
    delta: f32,
    distance: f32,
    theta_a: f32,
    theta_b: f32,
    a: f32,
    b: f32,
}

/// Smallest ray-to-emitter distance `D` used: a ray through the emitter
/// itself would divide by zero, and below this the density is already far
/// sharper than any pixel's worth of ray.
const MIN_EQUIANGULAR_DISTANCE: f32 = 1e-5;

impl EquiangularSampler {
    /// `None` for an empty interval.
    pub fn new(ray: &Ray, y: Vec3, a: f32, b: f32) -> Option<Self> {
        let non_empty = a < b; // false for NaN too
        if !non_empty {
            return None;
        }
        let delta = (y - ray.origin).dot(ray.direction);
        let distance = (y - ray.at(delta)).length().max(MIN_EQUIANGULAR_DISTANCE);
        let theta_a = ((a - delta) / distance).atan();
        let theta_b = ((b - delta) / distance).atan();
        (theta_b > theta_a).then_some(Self {
            delta,
            distance,
            theta_a,
            theta_b,
            a,
            b,
        })
    }

    /// A distance and its density for `u ∈ [0, 1)`.
    #[inline]
    pub fn sample(&self, u: f32) -> (f32, f32) {
        let theta = self.theta_a + u * (self.theta_b - self.theta_a);
        let t = (self.delta + self.distance * theta.tan()).clamp(self.a, self.b);
        (t, self.pdf(t))
    }

    /// The density at `t` (0 outside `[a, b]`).
    #[inline]
    pub fn pdf(&self, t: f32) -> f32 {
        if t < self.a || t > self.b {
            return 0.0;
        }
        let x = t - self.delta;
        self.distance / ((self.theta_b - self.theta_a) * (self.distance * self.distance + x * x))
    }
}

/// `∫ ds/(D² + s²)` over `[s_a, s_b]` (`s_b` may be infinite), the
/// inverse-square falloff along a line at distance `D` from a point,
/// with `s` measured from the line's point nearest it: `(θ_b − θ_a)/D`
/// with `θ = atan(s/D)`, the normalisation of [`EquiangularSampler`],
/// here as one `atan2` (the difference of two angles in (−π/2, π/2)).
/// `D` is held no less than the sampler's smallest distance.
#[inline]
pub fn inverse_square_integral(distance: f32, s_a: f32, s_b: f32) -> f32 {
    let distance = distance.max(MIN_EQUIANGULAR_DISTANCE);
    let (x_a, x_b) = (s_a / distance, s_b / distance);
    let spanned = if x_b.is_finite() {
        (x_b - x_a).atan2(1.0 + x_a * x_b)
    } else {
        std::f32::consts::FRAC_PI_2 - x_a.atan()
    };
    spanned.max(0.0) / distance
}

/// Sampling `t ∈ [a, b]` proportionally to the transmittance from `a`,
/// `σ e^{−σ(t−a)} / (1 − e^{−σ(b−a)})`; `b` may be infinite.
#[derive(Clone, Copy, Debug)]
pub struct ExponentialSampler {
    sigma_t: f32,
    a: f32,
    b: f32,
    /// `1 − e^{−σ(b−a)}`, the probability of the interval under the
    /// untruncated exponential.
    mass: f32,
}

impl ExponentialSampler {
    /// `None` when `σ ≤ 0` or the interval is empty.
    pub fn new(sigma_t: f32, a: f32, b: f32) -> Option<Self> {
        if !(sigma_t > 0.0 && a < b) {
            return None;
        }
        let mass = -(-sigma_t * (b - a)).exp_m1();
        (mass > 0.0).then_some(Self {
            sigma_t,
            a,
            b,
            mass,
        })
    }

    /// A distance and its density for `u ∈ [0, 1)`, by inverting the
    /// truncated exponential's distribution function.
    #[inline]
    pub fn sample(&self, u: f32) -> (f32, f32) {
        let t = (self.a - (-u * self.mass).ln_1p() / self.sigma_t).clamp(self.a, self.b);
        (t, self.pdf(t))
    }

    /// The density at `t` (per unit length; 0 outside `[a, b]`).
    #[inline]
    pub fn pdf(&self, t: f32) -> f32 {
        if t < self.a || t > self.b {
            return 0.0;
        }
        self.sigma_t * (-self.sigma_t * (t - self.a)).exp() / self.mass
    }
}

/// A cosine-distributed direction about the unit `normal` (density
/// `cos θ/π` per steradian) from `u ∈ [0, 1)²` (Malley's method).
pub fn cosine_hemisphere(normal: Vec3, u: glam::Vec2) -> Vec3 {
    let r = u.x.sqrt();
    let phi = std::f32::consts::TAU * u.y;
    let (t, b) = normal.any_orthonormal_pair();
    let z = (1.0 - u.x).max(0.0).sqrt();
    (t * (r * phi.cos()) + b * (r * phi.sin()) + normal * z).normalize()
}

/// A point uniformly distributed on the unit disk (density 1/π per unit
/// area) from `u ∈ [0, 1)²`, by Shirley and Chiu's concentric map ("A
/// Low Distortion Map Between Disk and Square", JGT 1997): squares about
/// the centre go to rings, so strata of `u` stay compact on the disk.
pub fn concentric_disk(u: glam::Vec2) -> glam::Vec2 {
    let o = 2.0 * u - glam::Vec2::ONE;
    if o == glam::Vec2::ZERO {
        return glam::Vec2::ZERO;
    }
    let quarter = std::f32::consts::FRAC_PI_4;
    let (r, phi) = if o.x.abs() > o.y.abs() {
        (o.x, quarter * (o.y / o.x))
    } else {
        (o.y, 2.0 * quarter - quarter * (o.x / o.y))
    };
    r * glam::Vec2::new(phi.cos(), phi.sin())
}

/// A direction uniformly distributed in the cone of half-angle θmax about
/// the unit `axis` (density [`uniform_cone_pdf`] per steradian) from
/// `u ∈ [0, 1)²`: cos θ uniform on [cos θmax, 1], φ uniform.
pub fn uniform_cone(axis: Vec3, cos_max: f32, u: glam::Vec2) -> Vec3 {
    let cos = 1.0 - u.x * (1.0 - cos_max);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * u.y;
    let (a, b) = axis.any_orthonormal_pair();
    (a * (sin * phi.cos()) + b * (sin * phi.sin()) + axis * cos).normalize()
}

/// The density of [`uniform_cone`]: one over the cone's solid angle
/// `2π(1 − cos θmax)`.
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    uniform_cone_pdf_from_gap(1.0 - cos_max)
}

/// [`uniform_cone_pdf`] from `1 − cos θmax` given directly, for cones too
/// narrow for `cos θmax` to differ from 1 in f32 (a sphere of radius `r`
/// at distance `d ≫ r` has `1 − cos θmax = (r/d)²/(1 + cos θmax)`, below
/// f32's ε = 2⁻²³ once `d > 2900 r`).
pub fn uniform_cone_pdf_from_gap(one_minus_cos_max: f32) -> f32 {
    1.0 / (std::f32::consts::TAU * one_minus_cos_max)
}

/// For tests of densities and lobes: `∫ f(ω) dω` over the hemisphere
/// about +y by the midpoint rule in cos θ and φ, `k × k` cells.
#[cfg(test)]
pub(crate) fn hemisphere_integral(k: usize, f: impl Fn(Vec3) -> f64) -> f64 {
    let cell = 2.0 * std::f64::consts::PI / (k * k) as f64;
    let mut total = 0.0;
    for i in 0..k {
        let cos = (i as f64 + 0.5) / k as f64;
        let sin = (1.0 - cos * cos).sqrt();
        for j in 0..k {
            let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / k as f64;
            let omega = Vec3::new(
                (sin * phi.cos()) as f32,
                cos as f32,
                (sin * phi.sin()) as f32,
            );
            total += f(omega) * cell;
        }
    }
    total
}

/// For tests: point `i` of the R₂ sequence in [0, 1)² (Roberts 2018, the
/// plastic number's Kronecker sequence), low-discrepancy in both numbers
/// at once, where a grid's rows would fall together.
#[cfg(test)]
pub(crate) fn r2_point(i: usize) -> glam::Vec2 {
    let g = 1.324_717_957_244_746_f64;
    glam::Vec2::new(
        (0.5 + i as f64 / g).fract() as f32,
        (0.5 + i as f64 / (g * g)).fract() as f32,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The concentric map is uniform on the disk: over a 64² grid of `u`
    /// cell centres (equal areas of the square), the share of points
    /// inside radius r is r² and in each quadrant ¼, to the grid's
    /// resolution (a cell maps to an area of π/64², so a ring boundary
    /// cuts at most ~2·64 cells: 2/64 of the points).
    #[test]
    fn concentric_disk_is_uniform_over_the_disk() {
        let k = 64;
        let points: Vec<glam::Vec2> = (0..k * k)
            .map(|c| {
                let u = glam::Vec2::new((c % k) as f32 + 0.5, (c / k) as f32 + 0.5) / k as f32;
                concentric_disk(u)
            })
            .collect();
        assert!(points.iter().all(|p| p.length() <= 1.0 + 1e-6));
        let n = points.len() as f32;
        for r in [0.3f32, 0.5, 0.8] {
            let inside = points.iter().filter(|p| p.length() < r).count() as f32 / n;
            assert!((inside - r * r).abs() < 2.0 / k as f32, "r {r}: {inside}");
        }
        let first = points.iter().filter(|p| p.x > 0.0 && p.y > 0.0).count() as f32 / n;
        assert!((first - 0.25).abs() < 2.0 / k as f32, "{first}");
        assert_eq!(concentric_disk(glam::Vec2::splat(0.5)), glam::Vec2::ZERO);
    }

    /// Cone samples stay in the cone, and their mean cosine is the
    /// density's, `∫ cos θ dω / Ω = (1 + cos θmax)/2`.
    #[test]
    fn cone_samples_match_their_density() {
        let axis = Vec3::new(0.3, -0.8, 0.52).normalize();
        for cos_max in [-1.0f32, 0.0, 0.8, 0.999] {
            let n = 64;
            let mut mean = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let u =
                        glam::Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    let c = uniform_cone(axis, cos_max, u).dot(axis);
                    assert!(c >= cos_max - 1e-5, "{c} < {cos_max}");
                    mean += c as f64 / (n * n) as f64;
                }
            }
            assert!(
                (mean - (1.0 + cos_max as f64) / 2.0).abs() < 1e-3,
                "{cos_max}: {mean}"
            );
            // The density integrates to one over the cone.
            let omega = std::f64::consts::TAU * (1.0 - cos_max as f64);
            assert!((uniform_cone_pdf(cos_max) as f64 * omega - 1.0).abs() < 1e-5);
        }
    }

    /// ∫ pdf dt = 1 over the interval, by the midpoint rule, and samples
    /// fall inside the interval.
    #[test]
    fn densities_integrate_to_one() {
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        let eq = EquiangularSampler::new(&ray, Vec3::new(2.0, 0.5, 0.0), 0.5, 6.0).unwrap();
        let ex = ExponentialSampler::new(0.7, 0.5, 6.0).unwrap();
        let n = 200_000;
        let h = 5.5 / n as f64;
        let (mut ieq, mut iex) = (0.0f64, 0.0f64);
        for i in 0..n {
            let t = (0.5 + (i as f64 + 0.5) * h) as f32;
            ieq += eq.pdf(t) as f64 * h;
            iex += ex.pdf(t) as f64 * h;
        }
        assert!((ieq - 1.0).abs() < 1e-3, "{ieq}");
        assert!((iex - 1.0).abs() < 1e-3, "{iex}");
        for i in 0..100 {
            let u = (i as f32 + 0.5) / 100.0;
            let (t, p) = eq.sample(u);
            assert!((0.5..=6.0).contains(&t) && p > 0.0);
            let (t, p) = ex.sample(u);
            assert!((0.5..=6.0).contains(&t) && p > 0.0);
        }
    }

    /// The sample at `u` is the `u`-quantile: the density integrates from
    /// `a` to the sample to `u`.
    #[test]
    fn samples_invert_the_cdf() {
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        let eq =
            EquiangularSampler::new(&ray, Vec3::new(2.0, 0.5, 0.0), 0.0, f32::INFINITY).unwrap();
        let ex = ExponentialSampler::new(0.3, 1.0, f32::INFINITY).unwrap();
        for u in [0.1f32, 0.5, 0.9] {
            for (t, pdf_fn, a) in [
                (
                    eq.sample(u).0,
                    &(|t| eq.pdf(t)) as &dyn Fn(f32) -> f32,
                    0.0f32,
                ),
                (ex.sample(u).0, &(|t| ex.pdf(t)) as &dyn Fn(f32) -> f32, 1.0),
            ] {
                let n = 100_000;
                let h = (t - a) as f64 / n as f64;
                let cdf: f64 = (0..n)
                    .map(|i| pdf_fn(a + ((i as f64 + 0.5) * h) as f32) as f64 * h)
                    .sum();
                assert!((cdf - u as f64).abs() < 2e-3, "u {u}: {cdf}");
            }
        }
    }
}
