//! Image error metrics.

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
        .flat_map(|(c, r)| (0..3).map(move |i| (c[i] as f64, r[i] as f64)))
        .map(|(c, r)| (c - r) * (c - r) / (r * r + RELATIVE_MSE_EPSILON))
        .sum();
    sum / (3 * candidate.pixels().len()) as f64
}
