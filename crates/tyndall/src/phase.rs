//! Phase functions: the angular distribution of light scattered in a medium.
//!
//! Convention: `cos_theta` is the cosine between the direction light was
//! travelling before scattering and the direction it travels after
//! (both propagation directions). `cos_theta = 1` is no deflection, so
//! Henyey–Greenstein with `g > 0` scatters forward: looking towards a
//! light through fog, a forward-scattering medium looks brighter.

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

    #[test]
    fn forward_scattering_peaks_forward() {
        let p = PhaseFunction::from_asymmetry(0.6);
        assert!(p.eval(1.0) > p.eval(0.0) && p.eval(0.0) > p.eval(-1.0));
    }
}
