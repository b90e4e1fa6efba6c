//! Piecewise-constant distributions over `[0, 1)` and `[0, 1)²`, sampled
//! by inverting their CDFs (pbrt-v4, `PiecewiseConstant1D` and
//! `PiecewiseConstant2D`, Pharr, Jakob & Humphreys 2023, §A.1): the
//! importance sampling of an environment map by its brightness.
//!
//! A distribution's density is exactly the one its samples have: each
//! cell of width `1/n` is chosen with probability `f_i / Σf` and its
//! interior uniformly, so the density there is `n·f_i / Σf`. Cells of
//! weight 0 are never chosen and have density 0.

use glam::Vec2;

/// A piecewise-constant density over `[0, 1)` of `n` equal cells with
/// non-negative weights.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseConstant1D {
    /// The cells' weights.
    weights: Vec<f32>,
    /// `cdf[i]` = the probability of the cells before `i`; `n + 1` entries
    /// from 0 to 1.
    cdf: Vec<f32>,
    /// The weights' sum.
    total: f64,
}

impl PiecewiseConstant1D {
    /// The distribution proportional to `weights` (each finite and ≥ 0,
    /// at least one); a sum of 0 gives the uniform distribution, so that
    /// sampling stays defined.
    pub fn new(weights: Vec<f32>) -> Self {
        assert!(!weights.is_empty(), "a distribution needs a cell");
        debug_assert!(weights.iter().all(|w| w.is_finite() && *w >= 0.0));
        let total: f64 = weights.iter().map(|&w| f64::from(w)).sum();
        let (weights, total) = if total > 0.0 {
            (weights, total)
        } else {
            let n = weights.len();
            (vec![1.0; n], n as f64)
        };
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        let mut running = 0.0f64;
        cdf.push(0.0);
        for &w in &weights {
            running += f64::from(w);
            cdf.push((running / total) as f32);
        }
        // Exactly 1 at the end, whatever the rounding.
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        Self {
            weights,
            cdf,
            total,
        }
    }

    /// How many cells.
    pub fn len(&self) -> usize {
        self.weights.len()
    }

    /// Whether there are no cells (never, for a distribution made by
    /// [`PiecewiseConstant1D::new`] from at least one weight).
    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }

    /// The weights' sum (the integral of the step function is this over
    /// the number of cells).
    pub fn total(&self) -> f64 {
        self.total
    }

    /// The point `x ∈ [0, 1)` at quantile `u ∈ [0, 1)`, with its density
    /// and its cell.
    pub fn sample(&self, u: f32) -> (f32, f32, usize) {
        // The last cell whose start is ≤ u; skips zero-weight cells (equal
        // consecutive CDF values).
        let cell = self
            .cdf
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(self.len() - 1);
        let (lo, hi) = (self.cdf[cell], self.cdf[cell + 1]);
        let within = if hi > lo { (u - lo) / (hi - lo) } else { 0.5 };
        let mut x = (cell as f32 + within.clamp(0.0, 1.0)) / self.len() as f32;
        // Rounding may carry x onto the next cell's start (or 1): step
        // back into the chosen cell, so that `pdf(x)` is this cell's.
        while x >= 1.0 || (x > 0.0 && self.cell_of(x) > cell) {
            x = f32::from_bits(x.to_bits() - 1);
        }
        (x, self.density_of_cell(cell), cell)
    }

    /// The density at `x ∈ [0, 1)`.
    pub fn pdf(&self, x: f32) -> f32 {
        self.density_of_cell(self.cell_of(x))
    }

    /// The cell `x ∈ [0, 1)` lies in (clamped to the cells).
    pub fn cell_of(&self, x: f32) -> usize {
        ((x * self.len() as f32) as usize).min(self.len() - 1)
    }

    fn density_of_cell(&self, cell: usize) -> f32 {
        (f64::from(self.weights[cell]) * self.len() as f64 / self.total) as f32
    }
}

/// A piecewise-constant density over `[0, 1)²` of `width × height` equal
/// cells, row-major, sampled as a marginal over rows (`v`) and a
/// conditional over the columns of the chosen row (`u`).
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseConstant2D {
    rows: Vec<PiecewiseConstant1D>,
    marginal: PiecewiseConstant1D,
}

impl PiecewiseConstant2D {
    /// The distribution proportional to `weights` (`width·height` of them,
    /// row `v` after row, each finite and ≥ 0).
    pub fn new(weights: &[f32], width: usize, height: usize) -> Self {
        assert!(width > 0 && height > 0 && weights.len() == width * height);
        let rows: Vec<PiecewiseConstant1D> = weights
            .chunks_exact(width)
            .map(|row| PiecewiseConstant1D::new(row.to_vec()))
            .collect();
        // A row's share is its weights' sum; a row of zeros made uniform
        // within still has share 0.
        let sums = weights
            .chunks_exact(width)
            .map(|row| row.iter().map(|&w| f64::from(w)).sum::<f64>() as f32)
            .collect();
        Self {
            rows,
            marginal: PiecewiseConstant1D::new(sums),
        }
    }

    /// The point `(u, v)` for `sample ∈ [0, 1)²`, with its density.
    pub fn sample(&self, sample: Vec2) -> (Vec2, f32) {
        let (v, p_v, row) = self.marginal.sample(sample.y);
        let (u, p_u, _) = self.rows[row].sample(sample.x);
        (Vec2::new(u, v), p_v * p_u)
    }

    /// The density at `uv ∈ [0, 1)²`.
    pub fn pdf(&self, uv: Vec2) -> f32 {
        let row = self.marginal.cell_of(uv.y);
        self.marginal.pdf(uv.y) * self.rows[row].pdf(uv.x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples fall in each cell as often as its weight says, their
    /// density is the one `pdf` gives there, and the density integrates to
    /// one.
    #[test]
    fn samples_follow_the_weights() {
        let d = PiecewiseConstant1D::new(vec![0.0, 1.0, 3.0, 0.0, 4.0]);
        let n = 100_000;
        let mut hits = [0usize; 5];
        for i in 0..n {
            let u = (i as f32 + 0.5) / n as f32;
            let (x, pdf, cell) = d.sample(u);
            assert!((0.0..1.0).contains(&x));
            assert_eq!(cell, d.cell_of(x), "{u}: {x}");
            assert_eq!(pdf, d.pdf(x));
            hits[cell] += 1;
        }
        let shares: Vec<f64> = hits.iter().map(|&h| h as f64 / n as f64).collect();
        for (share, expected) in shares.iter().zip([0.0, 0.125, 0.375, 0.0, 0.5]) {
            assert!((share - expected).abs() < 1e-4, "{shares:?}");
        }
        let integral: f64 = (0..1000)
            .map(|i| f64::from(d.pdf((i as f32 + 0.5) / 1000.0)) / 1000.0)
            .sum();
        assert!((integral - 1.0).abs() < 1e-6, "{integral}");
        // Within a cell the samples are uniform: the cell [0.4, 0.6) of
        // weight 3 maps u ∈ [0.125, 0.5) linearly onto it.
        let (x, _, _) = d.sample(0.125 + 0.375 / 2.0);
        assert!((x - 0.5).abs() < 1e-6, "{x}");
    }

    /// All weights 0: uniform, so sampling stays defined.
    #[test]
    fn zero_weights_are_uniform() {
        let d = PiecewiseConstant1D::new(vec![0.0; 4]);
        assert_eq!(d.pdf(0.3), 1.0);
        assert!((d.sample(0.6).0 - 0.6).abs() < 1e-6);
    }

    /// The 2D density integrates to one, each sample's density is the one
    /// `pdf` gives its point, and the samples of an m × m grid of `u`
    /// fall in each cell as often as its weight says: the grid points
    /// mapped into a cell fill a rectangle of `[0, 1)²`, whose count of
    /// points is its area·m² up to one row and one column of points,
    /// `(2m + 1)/m²` of the share.
    #[test]
    fn two_dimensional_density_is_its_samples() {
        let (w, h) = (7, 5);
        let weights: Vec<f32> = (0..w * h)
            .map(|i| ((i % w) as f32 + 1.0) * ((i / w) as f32 * 0.5 + 0.2))
            .collect();
        let total: f64 = weights.iter().map(|&x| f64::from(x)).sum();
        let d = PiecewiseConstant2D::new(&weights, w, h);
        let m = 400;
        let mut integral = 0.0f64;
        let mut hits = vec![0usize; w * h];
        for i in 0..m {
            for j in 0..m {
                let s = Vec2::new((i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
                integral += f64::from(d.pdf(s)) / (m * m) as f64;
                let (p, pdf) = d.sample(s);
                assert_eq!(pdf, d.pdf(p));
                let cell = (p.y * h as f32) as usize * w + (p.x * w as f32) as usize;
                hits[cell] += 1;
            }
        }
        assert!((integral - 1.0).abs() < 1e-5, "{integral}");
        let slack = (2 * m + 1) as f64 / (m * m) as f64;
        for (cell, &count) in hits.iter().enumerate() {
            let share = count as f64 / (m * m) as f64;
            let expected = f64::from(weights[cell]) / total;
            assert!(
                (share - expected).abs() <= slack,
                "cell {cell}: {share} vs {expected}"
            );
        }
    }
}
