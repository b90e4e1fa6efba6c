//! Image error metrics.

use crate::color::Rgb;
use crate::film::Image;

/// The regulariser ε of [`relative_mse`] (shared/reference/README.md).
pub const RELATIVE_MSE_EPSILON: f64 = 0.01;

/// Relative mean squared error of `candidate` against `reference`: the
/// mean over pixels and channels of `(c − r)² / (r² + ε)` with ε = 0.01,
/// the metric the reference images are published with.
///
/// # Panics
/// If the images differ in size.
pub fn relative_mse(candidate: &Image, reference: &Image) -> f64 {
    assert_eq!(
        (candidate.width(), candidate.height()),
        (reference.width(), reference.height()),
        "images must be the same size"
    );
    let sum: f64 = candidate
        .pixels()
        .iter()
        .zip(reference.pixels())
        .map(|(c, r)| 3.0 * pixel_relative_se(*c, *r))
        .sum();
    sum / (3 * candidate.pixels().len()) as f64
}

/// One pixel's relative squared error, averaged over its channels.
pub fn pixel_relative_se(c: Rgb, r: Rgb) -> f64 {
    (0..3)
        .map(|i| {
            let (c, r) = (c[i] as f64, r[i] as f64);
            (c - r) * (c - r) / (r * r + RELATIVE_MSE_EPSILON)
        })
        .sum::<f64>()
        / 3.0
}
