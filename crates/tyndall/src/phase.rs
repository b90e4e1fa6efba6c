//! Phase functions: the angular distribution of light scattered in a medium.
//!
//! Convention: `cos_theta` is the cosine between the direction light was
//! travelling before scattering and the direction it travels after
//! (both propagation directions). `cos_theta = 1` is no deflection, so
//! Henyey–Greenstein with `g > 0` scatters forward: looking towards a
//! light through fog, a forward-scattering medium looks brighter.

use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// `1/(4π)`: the isotropic phase function's value (sr⁻¹).
pub const INV_FOUR_PI: f32 = 1.0 / (4.0 * PI);

/// A phase function (normalised over the sphere, units sr⁻¹).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhaseFunction {
    Isotropic,
    /// Henyey–Greenstein with asymmetry `g ∈ (−1, 1)`, the mean cosine of
    /// the scattering angle.
    HenyeyGreenstein {
        g: f32,
    },
}

impl PhaseFunction {
    /// Isotropic for `g = 0`, Henyey–Greenstein otherwise.
    pub fn from_asymmetry(g: f32) -> Self {
        if g == 0.0 {
            PhaseFunction::Isotropic
        } else {
            PhaseFunction::HenyeyGreenstein { g }
        }
    }

    /// Value for the cosine between incoming and outgoing propagation
    /// directions (see the module documentation).
    #[inline]
    pub fn eval(&self, cos_theta: f32) -> f32 {
        match *self {
            PhaseFunction::Isotropic => INV_FOUR_PI,
            PhaseFunction::HenyeyGreenstein { g } => {
                let denom = 1.0 + g * g - 2.0 * g * cos_theta;
                INV_FOUR_PI * (1.0 - g * g) / (denom * denom.max(0.0).sqrt())
            }
        }
    }
}

impl PhaseFunction {
    /// Samples the next path direction at a scattering event reached by a
    /// path travelling along `direction` (from the camera), with density
    /// (sr⁻¹) equal to the phase function: light that arrives along
    /// `−next` leaves along `−direction`, so `cos θ = next · direction`.
    /// Returns the direction and its density.
    pub fn sample(&self, direction: Vec3, u: Vec2) -> (Vec3, f32) {
        let cos_theta = match *self {
            PhaseFunction::Isotropic => 1.0 - 2.0 * u.x,
            PhaseFunction::HenyeyGreenstein { g } => {
                // Inverse of the HG distribution of cos θ (u = 1 → θ = 0).
                let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
                ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
            }
        };
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let (t, b) = direction.any_orthonormal_pair();
        let next =
            (t * (sin_theta * phi.cos()) + b * (sin_theta * phi.sin()) + direction * cos_theta)
                .normalize();
        (next, self.eval(cos_theta))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ p dω = 2π ∫₋₁¹ p(μ) dμ = 1, by Simpson's rule in the test.
    #[test]
    fn phase_functions_are_normalised() {
        for g in [-0.7, -0.2, 0.0, 0.3, 0.8] {
            let p = PhaseFunction::from_asymmetry(g);
            let n = 20_000;
            let h = 2.0 / n as f64;
            let mut sum = 0.0;
            for i in 0..=n {
                let mu = -1.0 + i as f64 * h;
                let w = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                sum += w * p.eval(mu as f32) as f64;
            }
            let integral = 2.0 * std::f64::consts::PI * sum * h / 3.0;
            assert!((integral - 1.0).abs() < 1e-3, "g = {g}: {integral}");
        }
    }

    /// The mean cosine of sampled directions is the asymmetry g (the
    /// definition of g), and densities returned match `eval`.
    #[test]
    fn sampling_has_mean_cosine_g() {
        for g in [-0.6f32, 0.0, 0.4, 0.85] {
            let p = PhaseFunction::from_asymmetry(g);
            let n = 4096;
            let mut sum = 0.0f64;
            for i in 0..n {
                let u = Vec2::new(
                    (i as f32 + 0.5) / n as f32,
                    (i * 7919 % n) as f32 / n as f32,
                );
                let (dir, pdf) = p.sample(Vec3::Z, u);
                assert!((pdf - p.eval(dir.z)).abs() <= 1e-3 * pdf);
                sum += dir.z as f64;
            }
            assert!(
                (sum / n as f64 - g as f64).abs() < 2e-3,
                "g = {g}: {}",
                sum / n as f64
            );
        }
    }

    #[test]
    fn forward_scattering_peaks_forward() {
        let p = PhaseFunction::from_asymmetry(0.6);
        assert!(p.eval(1.0) > p.eval(0.0) && p.eval(0.0) > p.eval(-1.0));
    }
}
