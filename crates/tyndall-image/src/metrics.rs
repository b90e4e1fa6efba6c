//! Image error metrics: how far a render is from a reference.

use tyndall::{Image, Rgb};

/// The regulariser ε of [`relative_mse`] (docs/physics.md §6,
/// scenes/reference/REFERENCE-README.md).
pub const RELATIVE_MSE_EPSILON: f64 = 0.01;

/// Relative mean squared error of `candidate` against `reference`: the
/// mean over pixels and channels of `(c − r)² / (r² + ε)` with ε = 0.01,
/// the metric the reference images are published with (docs/physics.md
/// §6).
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

/// The share of the total relative squared error carried by the worst
/// `fraction` of pixels: a firefly measure. Smooth noise spreads error
/// over many pixels (for Gaussian noise of uniform relative variance the
/// worst 0.1% carry about 1%); fireflies concentrate it in a few.
///
/// # Panics
/// If the images differ in size.
pub fn error_concentration(candidate: &Image, reference: &Image, fraction: f64) -> f64 {
    assert_eq!(
        (candidate.width(), candidate.height()),
        (reference.width(), reference.height()),
        "images must be the same size"
    );
    let mut errors = pixel_errors(candidate, reference);
    errors.sort_by(|a, b| b.total_cmp(a));
    let total: f64 = errors.iter().sum();
    let worst = ((errors.len() as f64 * fraction).ceil() as usize).max(1);
    if total > 0.0 {
        errors[..worst].iter().sum::<f64>() / total
    } else {
        0.0
    }
}

/// Every pixel's relative squared error ([`pixel_relative_se`]), in
/// pixel order; the images must be the same size.
pub fn pixel_errors(candidate: &Image, reference: &Image) -> Vec<f64> {
    candidate
        .pixels()
        .iter()
        .zip(reference.pixels())
        .map(|(c, r)| pixel_relative_se(*c, *r))
        .collect()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_firefly_carries_the_error() {
        let reference = Image::from_pixels(100, 10, vec![Rgb::splat(0.5); 1000]);
        let mut pixels = vec![Rgb::splat(0.51); 1000];
        pixels[7] = Rgb::splat(50.0);
        let candidate = Image::from_pixels(100, 10, pixels);
        assert!(error_concentration(&candidate, &reference, 0.001) > 0.99);
        let smooth = Image::from_pixels(100, 10, vec![Rgb::splat(0.51); 1000]);
        let share = error_concentration(&smooth, &reference, 0.01);
        assert!((share - 0.01).abs() < 1e-9, "{share}");
    }
}
