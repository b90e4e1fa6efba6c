//! Comparing a render with a reference image: what `tyndall compare`
//! reports.

use crate::format::{ImageError, read_exr};
use crate::metrics::{error_concentration, pixel_relative_se, relative_mse};
use std::fmt;
use std::path::Path;
use tyndall::{Image, Rgb};

/// The share of pixels whose part of the error [`Comparison`] reports:
/// the worst 0.1% (a firefly measure, see [`error_concentration`]).
pub const WORST_FRACTION: f64 = 0.001;

/// A candidate image measured against a reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// [`relative_mse`] of the candidate against the reference.
    pub relative_mse: f64,
    /// The share of the error in the worst [`WORST_FRACTION`] of pixels;
    /// `None` when no worst pixels were asked for.
    pub worst_share: Option<f64>,
    /// The pixels with the largest error, largest first (ties in raster
    /// order).
    pub worst_pixels: Vec<PixelError>,
}

/// One pixel's relative squared error ([`pixel_relative_se`]) and values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelError {
    /// Column, from the left.
    pub x: u32,
    /// Row, from the top.
    pub y: u32,
    /// The pixel's relative squared error, averaged over its channels.
    pub error: f64,
    /// The candidate's linear radiance.
    pub candidate: Rgb,
    /// The reference's linear radiance.
    pub reference: Rgb,
}

/// Why two image files could not be compared.
#[derive(Debug, thiserror::Error)]
pub enum CompareError {
    #[error(transparent)]
    Image(#[from] ImageError),
    #[error("{candidate} is {}×{} but {reference} is {}×{}", .candidate_size.0, .candidate_size.1, .reference_size.0, .reference_size.1)]
    SizeMismatch {
        candidate: String,
        candidate_size: (u32, u32),
        reference: String,
        reference_size: (u32, u32),
    },
}

/// Measures `candidate` against `reference` and lists the `worst` pixels
/// with the largest error (none for `worst = 0`).
///
/// # Panics
/// If the images differ in size.
pub fn compare(candidate: &Image, reference: &Image, worst: usize) -> Comparison {
    let (c, r) = (candidate, reference);
    let mut pixels: Vec<PixelError> = (0..c.height())
        .flat_map(|y| (0..c.width()).map(move |x| (x, y)))
        .map(|(x, y)| PixelError {
            x,
            y,
            error: pixel_relative_se(c.pixel(x, y), r.pixel(x, y)),
            candidate: c.pixel(x, y),
            reference: r.pixel(x, y),
        })
        .collect();
    pixels.sort_by(|a, b| b.error.total_cmp(&a.error));
    pixels.truncate(worst);
    Comparison {
        relative_mse: relative_mse(c, r),
        worst_share: (worst > 0).then(|| error_concentration(c, r, WORST_FRACTION)),
        worst_pixels: pixels,
    }
}

/// Reads two OpenEXR files and [`compare`]s them.
pub fn compare_files(
    candidate: &Path,
    reference: &Path,
    worst: usize,
) -> Result<Comparison, CompareError> {
    let c = read_exr(candidate)?;
    let r = read_exr(reference)?;
    if (c.width(), c.height()) != (r.width(), r.height()) {
        return Err(CompareError::SizeMismatch {
            candidate: candidate.display().to_string(),
            candidate_size: (c.width(), c.height()),
            reference: reference.display().to_string(),
            reference_size: (r.width(), r.height()),
        });
    }
    Ok(compare(&c, &r, worst))
}

/// The report `tyndall compare` prints: the relative MSE on the first
/// line, then (when worst pixels were asked for) the worst pixels' share
/// of the error and one line per worst pixel.
impl fmt::Display for Comparison {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{:.6e}", self.relative_mse)?;
        if let Some(share) = self.worst_share {
            writeln!(
                f,
                "  the worst 0.1% of pixels carry {:.1}% of the error",
                100.0 * share
            )?;
        }
        for p in &self.worst_pixels {
            writeln!(
                f,
                "  pixel ({}, {}): {:.3e}  candidate {:?}  reference {:?}",
                p.x,
                p.y,
                p.error,
                p.candidate.to_array(),
                p.reference.to_array()
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reports_the_error_and_the_worst_pixels_in_order() {
        let reference = Image::from_pixels(3, 1, vec![Rgb::splat(1.0); 3]);
        let candidate = Image::from_pixels(
            3,
            1,
            vec![Rgb::splat(1.0), Rgb::splat(3.0), Rgb::splat(2.0)],
        );
        let c = compare(&candidate, &reference, 2);
        let expected = (0.0 + 4.0 / 1.01 + 1.0 / 1.01) / 3.0;
        assert!((c.relative_mse - expected).abs() < 1e-12, "{c:?}");
        assert_eq!(
            c.worst_pixels.iter().map(|p| p.x).collect::<Vec<_>>(),
            [1, 2]
        );
        let share = c.worst_share.expect("asked for worst pixels");
        assert!((share - 0.8).abs() < 1e-12, "{share}");
        let text = c.to_string();
        assert_eq!(text.lines().count(), 4, "{text}");
        assert!(text.starts_with(&format!("{:.6e}\n", expected)), "{text}");
        assert!(text.contains("pixel (1, 0): 3.960e0"), "{text}");
        // Without worst pixels: the relative MSE alone.
        let plain = compare(&candidate, &reference, 0);
        assert_eq!(plain.to_string().lines().count(), 1);
        assert_eq!(plain.worst_share, None);
    }
}
