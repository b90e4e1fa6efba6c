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
//!   efficiency ȳ ≤ 1. The matching functions are the CIE's own table of
//!   the 1931 2° observer ([`super::cie1931`]), summed at its 1 nm steps
//!   over 360–830 nm as CIE 015:2004 §7.1 prescribes.
//! * [`rgb`]: those XYZ values in linear Rec. 709 (IEC 61966-2-1's XYZ →
//!   linear sRGB matrix), the radiance a blackbody's colour has in
//!   Tyndall's RGB (docs/physics.md §1.2), unnormalised: 1 K and 6500 K
//!   differ by the factor Planck's law gives them.
//! * [`unit_luminance_rgb`]: the same colour scaled to luminance 1, the
//!   normalisation Cycles' blackbody colour has (docs/physics.md §2.5).
//! * [`BlackbodyTable`]: a function of temperature tabulated and linearly
//!   interpolated, for evaluation at every tracking step.

use super::{Rgb, cie1931};

/// Planck's constant h, J·s.
pub const PLANCK: f64 = 6.626_070_15e-34;
/// The speed of light in vacuum c, m/s.
pub const LIGHT_SPEED: f64 = 299_792_458.0;
/// Boltzmann's constant k_B, J/K.
pub const BOLTZMANN: f64 = 1.380_649e-23;

/// The Stefan–Boltzmann constant σ = 2π⁵k_B⁴/(15h³c²), W·m⁻²·K⁻⁴
/// (5.670374419·10⁻⁸, CODATA 2018), from the constants above: a
/// blackbody's radiance over all wavelengths is σT⁴/π.
pub fn stefan_boltzmann() -> f64 {
    use std::f64::consts::PI;
    2.0 * PI.powi(5) * BOLTZMANN.powi(4) / (15.0 * PLANCK.powi(3) * LIGHT_SPEED.powi(2))
}

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

/// CIE 1931 XYZ of a blackbody at `kelvin`: `Σ L_λ(T)·{x̄, ȳ, z̄}·Δλ` over
/// the table's wavelengths, 360–830 nm at Δλ = 1 nm, W·sr⁻¹·m⁻²
/// (radiometric: no 683 lm/W).
pub fn xyz(kelvin: f64) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    for (row, cmf) in cie1931::CMF.iter().enumerate() {
        let nm = (cie1931::FIRST_NM as usize + row) as f64;
        // Δλ = 1 nm = 1e-9 m.
        let radiance = spectral_radiance(nm * 1e-9, kelvin) * 1e-9;
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

/// Below this temperature [`unit_luminance_rgb`] keeps the colour it has
/// here, K: the light is negligible there (Planck's Y at 800 K is 10⁻⁶
/// of 1500 K's), and the ratio of two vanishing integrals is not worth
/// computing.
pub const UNIT_LUMINANCE_FLOOR_K: f64 = 800.0;

/// The blackbody's colour at `kelvin` scaled to luminance 1 — its XYZ
/// divided by Y, in linear Rec. 709 — dimensionless: Cycles'
/// normalisation of its blackbody colour (docs/physics.md §2.5). Below
/// [`UNIT_LUMINANCE_FLOOR_K`] the colour there. Not clipped: outside the
/// Rec. 709 gamut (blue below about 1900 K, green below about 1000 K) a
/// channel is negative, as Cycles' Principled Volume leaves it.
pub fn unit_luminance_rgb(kelvin: f64) -> Rgb {
    let t = kelvin.max(UNIT_LUMINANCE_FLOOR_K);
    let [x, y, z] = xyz(t);
    let [r, g, b] = xyz_to_rec709([x / y, 1.0, z / y]);
    Rgb::new(r as f32, g as f32, b as f32)
}

/// A function of temperature, RGB-valued, tabulated on `[0, max_kelvin]`
/// at [`BlackbodyTable::ENTRIES`] evenly spaced temperatures and linearly
/// interpolated (clamped past the ends): the colour integral costs 471
/// exponentials, a lookup two loads. For [`rgb`] the interpolation error
/// is about `(ΔT)²/8` times the second derivative of Planck's law in T:
/// with ΔT ≤ 2 K (tables up to 4000 K) below 10⁻³ relative from 800 K up,
/// where the radiance is not negligible (the unit test checks this).
#[derive(Clone, Debug, PartialEq)]
pub struct BlackbodyTable {
    step: f32,
    values: Vec<Rgb>,
    /// Largest channel of any entry up to each entry.
    running_max: Vec<f32>,
}

impl BlackbodyTable {
    /// Entries of a table.
    pub const ENTRIES: usize = 2049;

    /// [`rgb`] up to `max_kelvin` (> 0, finite).
    pub fn new(max_kelvin: f32) -> Self {
        Self::of(max_kelvin, rgb)
    }

    /// `f` (of kelvin) up to `max_kelvin` (> 0, finite).
    pub fn of(max_kelvin: f32, f: impl Fn(f64) -> Rgb) -> Self {
        let max = max_kelvin.max(1.0);
        let step = max / (Self::ENTRIES - 1) as f32;
        let values: Vec<Rgb> = (0..Self::ENTRIES)
            .map(|i| f(i as f64 * step as f64))
            .collect();
        let running_max = values
            .iter()
            .scan(0.0f32, |m, v| {
                *m = m.max(v.max_element());
                Some(*m)
            })
            .collect();
        Self {
            step,
            values,
            running_max,
        }
    }

    /// The tabulated function at `kelvin`.
    #[inline]
    pub fn eval(&self, kelvin: f32) -> Rgb {
        let x = (kelvin / self.step).clamp(0.0, (Self::ENTRIES - 1) as f32);
        let i = (x as usize).min(Self::ENTRIES - 2);
        let f = x - i as f32;
        self.values[i] * (1.0 - f) + self.values[i + 1] * f
    }

    /// An upper bound of every channel of [`Self::eval`] at temperatures
    /// up to `kelvin`.
    pub fn max_up_to(&self, kelvin: f32) -> f32 {
        let x = (kelvin / self.step).clamp(0.0, (Self::ENTRIES - 1) as f32);
        self.running_max[(x.ceil() as usize).min(Self::ENTRIES - 1)]
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
