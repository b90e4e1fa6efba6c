//! Exact, order-independent sums of radiance: fixed point with 64
//! fractional bits in an `i128` per channel.
//!
//! Float addition is not associative, so sums of the same splats added in
//! different groupings differ in their last bits. Light-tracing splats land
//! on arbitrary pixels from paths that different tiles trace, and merging
//! those tiles must give the single render bit for bit; so each splat is
//! rounded once, on its own (towards zero at 2⁻⁶⁴ ≈ 5·10⁻²⁰), to a fixed-
//! point integer, and integers add exactly in any order. Range: sums up to
//! 2⁶³ ≈ 9·10¹⁸ per pixel (beyond, they saturate).

use crate::color::Rgb;
use glam::DVec3;

/// 2⁶⁴: one unit of the fixed-point scale.
const ONE: f64 = 18_446_744_073_709_551_616.0;

/// A sum of RGB values in fixed point (64 fractional bits per channel).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ExactRgb(pub [i128; 3]);

impl ExactRgb {
    pub const ZERO: Self = Self([0; 3]);

    /// Adds `v` (finite), each channel rounded towards zero to 2⁻⁶⁴.
    #[inline]
    pub fn add(&mut self, v: Rgb) {
        for (s, x) in self.0.iter_mut().zip(v.to_array()) {
            // Exact in f64 (a power-of-two scale of an f32); `as`
            // truncates and saturates.
            *s = s.saturating_add((x as f64 * ONE) as i128);
        }
    }

    /// Adds another exact sum.
    #[inline]
    pub fn add_exact(&mut self, other: &ExactRgb) {
        for (s, o) in self.0.iter_mut().zip(other.0) {
            *s = s.saturating_add(o);
        }
    }

    /// The sum as f64 (rounded once).
    pub fn to_dvec3(&self) -> DVec3 {
        DVec3::from_array(self.0.map(|s| s as f64 / ONE))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_do_not_depend_on_order_or_grouping() {
        let values: Vec<Rgb> = (0..1000)
            .map(|i| {
                let x = ((i * 7919) % 1000) as f32;
                Rgb::new(x * 1e-3, x * 1e3 + 0.1, 1.0 / (x + 1.0))
            })
            .collect();
        let mut forward = ExactRgb::ZERO;
        values.iter().for_each(|v| forward.add(*v));
        let mut backward = ExactRgb::ZERO;
        values.iter().rev().for_each(|v| backward.add(*v));
        let (mut a, mut b) = (ExactRgb::ZERO, ExactRgb::ZERO);
        values[..333].iter().for_each(|v| a.add(*v));
        values[333..].iter().for_each(|v| b.add(*v));
        b.add_exact(&a);
        assert_eq!(forward, backward);
        assert_eq!(forward, b);
        // And it is the sum: against f64, to within 1000 roundings.
        let f: DVec3 = values.iter().map(|v| v.as_dvec3()).sum();
        let d = (forward.to_dvec3() - f).abs();
        assert!(d.max_element() <= 1e-9 * f.max_element(), "{d:?}");
    }
}
