//! Per-pixel sample sequences.
//!
//! Each pixel has its own Owen-scrambled Sobol sequence (Burley 2020,
//! `sobol_burley`), seeded from the scene seed and the pixel's index, so a
//! pixel's samples depend on nothing but (seed, pixel, sample index):
//! images are identical whatever the thread count. Consecutive dimensions
//! are drawn in a fixed order by the integrators; all samples of a pixel
//! are jointly stratified in the first [`SOBOL_DIMENSIONS`] dimensions;
//! past them, a hashed random number takes over.

use glam::Vec2;

/// The largest f32 below 1: where a uniform number remapped into a
/// sub-interval (a choice's share, a tree's branch) is clamped, so it
/// stays in `[0, 1)`.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// Dimensions drawn from the Sobol sequence; later ones are hashed
/// random numbers. The first 24 cover a camera sample and its first
/// scattering events (pixel position, lens, the first flights, light
/// choices and directions), where stratification pays. Deeper events
/// gain little from it, and Sobol's higher dimensions cost more to draw
/// than a hash: hashing past 24 instead of the crate's 256 made the fog
/// references 7–12 % more efficient at equal error (docs/benchmarks.md,
/// "Sobol to dimension 24").
pub const SOBOL_DIMENSIONS: u32 = 24;
const _: () = assert!(SOBOL_DIMENSIONS <= sobol_burley::NUM_DIMENSIONS);

/// A sample point of one pixel, drawn dimension by dimension.
#[derive(Clone, Debug)]
pub struct PixelSampler {
    seed: u32,
    index: u32,
    dimension: u32,
    /// Dimensions `4k..4k+4` of the sequence, where `4k` is the last
    /// multiple of four below `dimension`: the crate computes four
    /// dimensions at once (SIMD) for about the cost of one, with the same
    /// values as one at a time.
    block: [f32; 4],
}

impl PixelSampler {
    /// The `sample_index`-th sample of pixel `pixel_index` under `seed`.
    pub fn new(seed: u64, pixel_index: u64, sample_index: u32) -> Self {
        let h = mix64(seed ^ mix64(pixel_index.wrapping_add(0x9e37_79b9_7f4a_7c15)));
        Self {
            seed: (h ^ (h >> 32)) as u32,
            index: sample_index,
            dimension: 0,
            block: [0.0; 4],
        }
    }

    /// The next dimension, uniform in [0, 1).
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        let d = self.dimension;
        self.dimension += 1;
        if d < SOBOL_DIMENSIONS {
            if d.is_multiple_of(4) {
                self.block = sobol_burley::sample_4d(self.index, d / 4, self.seed);
            }
            self.block[(d % 4) as usize]
        } else {
            let bits = mix64(((self.seed as u64) << 32 | self.index as u64) ^ mix64(d as u64));
            unit_f32(bits)
        }
    }

    /// The next two dimensions.
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.next_1d(), self.next_1d())
    }

    /// An independent random stream for this sample, for estimators that
    /// draw a random count of numbers (delta and ratio tracking): drawing
    /// them from the sequence would shift every later dimension. Depends
    /// only on (seed, pixel, sample index, `purpose`); uses no dimension.
    pub fn stream(&self, purpose: u64) -> RandomStream {
        RandomStream {
            state: mix64(((self.seed as u64) << 32 | self.index as u64) ^ mix64(!purpose)),
        }
    }
}

/// A SplitMix64 pseudo-random stream (Steele et al. 2014): fast, 2⁶⁴
/// period, good enough for the stochastic tracking estimators it feeds.
#[derive(Clone, Debug)]
pub struct RandomStream {
    state: u64,
}

impl RandomStream {
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        unit_f32(mix64(self.state))
    }
}

/// The 24 high bits of `bits` as an exactly representable f32 in [0, 1).
#[inline]
fn unit_f32(bits: u64) -> f32 {
    (bits >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

/// A 64-bit finaliser (Stafford's mix13, as in SplitMix64): a bijection
/// that spreads every input bit over the output.
#[inline]
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_are_uniform_and_stratified() {
        // 64 samples of one dimension fall one per 1/64 stratum.
        let mut strata = [0u32; 64];
        for i in 0..64 {
            let mut s = PixelSampler::new(7, 12345, i);
            let u = s.next_1d();
            assert!((0.0..1.0).contains(&u));
            strata[(u * 64.0) as usize] += 1;
        }
        assert!(strata.iter().all(|&c| c == 1));
    }

    #[test]
    fn streams_are_uniform_and_distinct_per_purpose() {
        let s = PixelSampler::new(3, 4, 5);
        let (mut a, mut b) = (s.stream(1), s.stream(2));
        let n = 20_000;
        let mut mean = 0.0;
        let mut same = 0;
        for _ in 0..n {
            let (x, y) = (a.next_f32(), b.next_f32());
            assert!((0.0..1.0).contains(&x));
            mean += x as f64 / n as f64;
            same += (x == y) as u32;
        }
        // Mean of n uniforms: standard error 1/sqrt(12n) ≈ 0.002; 5σ.
        assert!((mean - 0.5).abs() < 5.0 / (12.0 * n as f64).sqrt());
        assert!(same < 5);
    }

    /// Drawing four dimensions at once changes no value.
    #[test]
    fn blocks_of_four_equal_single_dimensions() {
        for index in [0, 1, 37, 4095] {
            let mut s = PixelSampler::new(11, 987, index);
            let seed = s.seed;
            for d in 0..SOBOL_DIMENSIONS {
                assert_eq!(
                    s.next_1d(),
                    sobol_burley::sample(index, d, seed),
                    "dimension {d}"
                );
            }
        }
    }

    /// Past the Sobol dimensions, every dimension is uniform and
    /// uncorrelated with the next, over the samples of many pixels: the
    /// mean within 5 standard errors (1/√(12n)) of 1/2 and the
    /// correlation within 5 of 0 (1/√n).
    #[test]
    fn hashed_dimensions_are_uniform_and_uncorrelated() {
        let n = 8192;
        for d in SOBOL_DIMENSIONS..SOBOL_DIMENSIONS + 40 {
            let (mut mean, mut product) = (0.0, 0.0);
            for k in 0..n {
                let mut s = PixelSampler::new(5, k / 64, (k % 64) as u32);
                for _ in 0..d {
                    s.next_1d();
                }
                let (x, y) = (s.next_1d() as f64, s.next_1d() as f64);
                mean += x / n as f64;
                // 12·(x − ½)(y − ½) has variance 1 for independent uniforms.
                product += 12.0 * (x - 0.5) * (y - 0.5) / n as f64;
            }
            let n = n as f64;
            assert!(
                (mean - 0.5).abs() < 5.0 / (12.0 * n).sqrt(),
                "dimension {d}: mean {mean}"
            );
            assert!(
                product.abs() < 5.0 / n.sqrt(),
                "dimensions {d}, {}: correlation {product}",
                d + 1
            );
        }
    }

    #[test]
    fn hashed_dimensions_are_in_range_and_deterministic() {
        let mut a = PixelSampler::new(1, 2, 3);
        let mut b = PixelSampler::new(1, 2, 3);
        for _ in 0..600 {
            let (x, y) = (a.next_1d(), b.next_1d());
            assert_eq!(x, y);
            assert!((0.0..1.0).contains(&x));
        }
    }
}
