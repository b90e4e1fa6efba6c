//! Linear RGB radiometry and the sRGB transfer function.
//!
//! Radiance, intensity and reflectance are linear RGB triples: three
//! independent channels (docs/physics.md §1.2). [`Rgb`] is glam's `Vec3`, so colour
//! arithmetic is component-wise. [`blackbody`] holds Planck's law and
//! its colour in linear Rec. 709.

pub mod blackbody;
pub mod cie1931;

/// A linear-RGB triple: radiance (W·sr⁻¹·m⁻²), intensity (W/sr), irradiance
/// (W/m²) or a dimensionless reflectance/transmittance, per channel.
pub type Rgb = glam::Vec3;

/// Rec. 709 / sRGB relative luminance of a linear colour.
#[inline]
pub fn luminance(c: Rgb) -> f32 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

/// The sRGB electro-optical transfer function: encoded value → linear.
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// The inverse sRGB transfer function: linear → encoded value (unclamped).
pub fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trip() {
        for i in 0..=100 {
            let v = i as f32 / 100.0;
            assert!((linear_to_srgb(srgb_to_linear(v)) - v).abs() < 1e-5);
        }
    }

    #[test]
    fn luminance_of_white_is_one() {
        assert!((luminance(Rgb::ONE) - 1.0).abs() < 1e-6);
    }
}
