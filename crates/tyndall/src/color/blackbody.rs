//! Blackbody radiation: Planck's law in physical units and the linear
//! Rec. 709 (sRGB primaries, D65 white) colour of a blackbody
//! (docs/physics.md §2.5). The one place Tyndall computes Planck's law.
//!
//! * [`spectral_radiance`]: Planck's law
//!   `L_λ(T) = 2hc² / λ⁵ / (exp(hc/(λ k_B T)) − 1)`, W·sr⁻¹·m⁻² per metre
//!   of wavelength (CODATA 2018 constants, exact in the SI).
//! * [`xyz`]: CIE 1931 tristimulus values `X = ∫ L_λ x̄(λ) dλ` (and Y, Z),
//!   in W·sr⁻¹·m⁻² — radiometric, not photometric: without the 683 lm/W
//!   of luminance, so `Y` is the radiance weighted by the luminous
//!   efficiency ȳ ≤ 1. The matching functions are the multi-lobe Gaussian
//!   fit of Wyman, Sloan & Shirley, "Simple Analytic Approximations to the
//!   CIE XYZ Color Matching Functions", JCGT 2(2), 2013 (their eq. 2),
//!   integrated by the midpoint rule at 1 nm over 360–830 nm.
//! * [`rgb`]: those XYZ values in linear Rec. 709 (IEC 61966-2-1's XYZ →
//!   linear sRGB matrix), the radiance a blackbody's colour has in
//!   Tyndall's RGB (docs/physics.md §1.2), unnormalised: 1 K and 6500 K
//!   differ by the factor Planck's law gives them.
//! * [`BlackbodyTable`]: [`rgb`] tabulated in temperature, linearly
//!   interpolated, for evaluation at every tracking step.

use super::Rgb;

/// Planck's constant h, J·s.
pub const PLANCK: f64 = 6.626_070_15e-34;
/// The speed of light in vacuum c, m/s.
pub const LIGHT_SPEED: f64 = 299_792_458.0;
/// Boltzmann's constant k_B, J/K.
pub const BOLTZMANN: f64 = 1.380_649e-23;

/// Shortest and longest wavelength of the colour integral, nm.
const LAMBDA_RANGE_NM: (u32, u32) = (360, 830);

/// Planck's law: the spectral radiance of a blackbody at `kelvin` at
/// wavelength `lambda_m` (metres), in W·sr⁻¹·m⁻² per metre of wavelength
/// (W·sr⁻¹·m⁻³). 0 at 0 K.
pub fn spectral_radiance(lambda_m: f64, kelvin: f64) -> f64 {
    if kelvin <= 0.0 || lambda_m <= 0.0 {
        return 0.0;
    }
    let x = PLANCK * LIGHT_SPEED / (lambda_m * BOLTZMANN * kelvin);
    2.0 * PLANCK * LIGHT_SPEED * LIGHT_SPEED / lambda_m.powi(5) / x.exp_m1()
}

/// Piecewise Gaussian of Wyman et al. 2013: width `below` left of `mu`,
/// `above` right of it (all in nm).
fn lobe(lambda_nm: f64, mu: f64, below: f64, above: f64) -> f64 {
    let s = if lambda_nm < mu { below } else { above };
    let t = (lambda_nm - mu) / s;
    (-0.5 * t * t).exp()
}

/// The CIE 1931 2° colour matching functions x̄, ȳ, z̄ at `lambda_nm`
/// (Wyman, Sloan & Shirley 2013, multi-lobe fit).
pub fn cie_1931(lambda_nm: f64) -> [f64; 3] {
    let l = lambda_nm;
    [
        1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7)
            - 0.065 * lobe(l, 501.1, 20.4, 26.2),
        0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1),
        1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8),
    ]
}

/// CIE 1931 XYZ of a blackbody at `kelvin`: `∫ L_λ(T)·{x̄, ȳ, z̄} dλ` over
/// 360–830 nm, W·sr⁻¹·m⁻² (radiometric: no 683 lm/W).
pub fn xyz(kelvin: f64) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    for nm in LAMBDA_RANGE_NM.0..LAMBDA_RANGE_NM.1 {
        let l = nm as f64 + 0.5;
        // dλ = 1 nm = 1e-9 m.
        let radiance = spectral_radiance(l * 1e-9, kelvin) * 1e-9;
        let cmf = cie_1931(l);
        for k in 0..3 {
            sum[k] += radiance * cmf[k];
        }
    }
    sum
}

/// XYZ → linear Rec. 709 / sRGB (D65), IEC 61966-2-1.
pub fn xyz_to_rec709(xyz: [f64; 3]) -> [f64; 3] {
    let [x, y, z] = xyz;
    [
        3.2406 * x - 1.5372 * y - 0.4986 * z,
        -0.9689 * x + 1.8758 * y + 0.0415 * z,
        0.0557 * x - 0.2040 * y + 1.0570 * z,
    ]
}

/// The radiance of a blackbody at `kelvin` in linear Rec. 709, W·sr⁻¹·m⁻²
/// per channel (docs/physics.md §2.5). A channel below 0 (a blackbody
/// colour outside the Rec. 709 gamut, as deep reds below about 1000 K
/// are in blue) is clipped to 0.
pub fn rgb(kelvin: f64) -> Rgb {
    let [r, g, b] = xyz_to_rec709(xyz(kelvin));
    Rgb::new(r.max(0.0) as f32, g.max(0.0) as f32, b.max(0.0) as f32)
}

/// [`rgb`] on `[0, max_kelvin]` at [`BlackbodyTable::ENTRIES`] evenly
/// spaced temperatures, linearly interpolated (clamped past the ends):
/// the colour integral costs 470 exponentials, a lookup two loads. The
/// interpolation error is about `(ΔT)²/8` times the second derivative of
/// Planck's law in T: with ΔT ≤ 2 K (tables up to 4000 K) below 10⁻³
/// relative from 800 K up, where the radiance is not negligible (the unit
/// test checks this).
#[derive(Clone, Debug, PartialEq)]
pub struct BlackbodyTable {
    step: f32,
    values: Vec<Rgb>,
}

impl BlackbodyTable {
    /// Entries of a table.
    pub const ENTRIES: usize = 2049;

    /// The table up to `max_kelvin` (> 0, finite).
    pub fn new(max_kelvin: f32) -> Self {
        let max = max_kelvin.max(1.0);
        let step = max / (Self::ENTRIES - 1) as f32;
        let values = (0..Self::ENTRIES)
            .map(|i| rgb(i as f64 * step as f64))
            .collect();
        Self { step, values }
    }

    /// The blackbody's linear Rec. 709 radiance at `kelvin` (W·sr⁻¹·m⁻²).
    #[inline]
    pub fn eval(&self, kelvin: f32) -> Rgb {
        let x = (kelvin / self.step).clamp(0.0, (Self::ENTRIES - 1) as f32);
        let i = (x as usize).min(Self::ENTRIES - 2);
        let f = x - i as f32;
        self.values[i] * (1.0 - f) + self.values[i + 1] * f
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planck_peaks_at_wiens_wavelength() {
        // Wien's displacement constant b = 2.897771955e-3 m·K.
        let t = 3000.0;
        let peak = 2.897_771_955e-3 / t;
        let at = spectral_radiance(peak, t);
        assert!(at > spectral_radiance(peak * 0.99, t));
        assert!(at > spectral_radiance(peak * 1.01, t));
    }

    #[test]
    fn table_interpolates_the_integral() {
        let table = BlackbodyTable::new(4000.0);
        for kelvin in [900.0f32, 1500.0, 2321.7, 3999.0] {
            let (a, b) = (table.eval(kelvin), rgb(kelvin as f64));
            assert!(
                ((a - b).abs() / b.max_element()).max_element() < 1e-3,
                "{kelvin}: {a} vs {b}"
            );
        }
        assert_eq!(table.eval(0.0), Rgb::ZERO);
    }
}
