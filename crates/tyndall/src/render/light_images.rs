//! Where a pixel's camera samples are drawn: uniformly over the pixel, or,
//! in a pixel that holds the image of a point or spot light inside a
//! participating medium, with a share of them concentrated around that
//! image.
//!
//! Why: a camera ray passing a point light in fog at distance `D`
//! gathers in-scattered light `∫ σs·f_p·I·T / (D² + t²) dt ≈ σs·f_p·I·T·Δθ/D`
//! (Δθ the angle the lit part of the ray subtends from the light: the
//! closed form equiangular sampling is built on, Kulla & Fajardo 2012,
//! "Importance Sampling Techniques for Path Tracing in Participating
//! Media", §4.1). Over the pixel holding the light's image, `D` is
//! proportional to the film distance `r` from the image, so the pixel's
//! value `∫ dA/r` is finite but the second moment of uniformly placed
//! samples, `∫ dA/r²`, diverges (logarithmically). Whatever estimates the
//! radiance along each ray, the pixel's samples then have infinite
//! variance: fireflies at every visible luminaire that never average away
//! at the `1/N` rate (on the 64-spot stage rig at 256 spp, one such
//! sample held 99 % of the image's squared error, docs/benchmarks.md).
//!
//! The remedy is to importance-sample the film position. In such a pixel a
//! share [`FOCUS_SHARE`] of the samples is drawn with density `∝ 1/r`
//! around the image (exactly over the pixel's square, so no sample leaves
//! the pixel), the rest uniformly; each sample is weighed by the pixel's
//! area over the mixture's density `p = (1 − α) + α·q`. The mixture is
//! defensive (Hesterberg 1995, "Weighted Average Importance Sampling and
//! Defensive Mixture Distributions", Technometrics 37(2)): the weight is
//! at most `1/(1 − α)` anywhere, so nothing else in the pixel grows
//! noisier by more than that, and near the image `f/p` stays bounded by
//! `c·Z/α` (`f ≈ c/r`, `Z = ∫_pixel dA/r`), so the variance is finite.
//! The estimate is unbiased for any integrand: `∫ f/p · p dA = ∫ f dA`.
//!
//! Only pinhole cameras focus: behind a thin lens the image moves with
//! the lens sample (and is blurred over many pixels), so those renders
//! sample uniformly as before.

use crate::camera::Camera;
use crate::sampler::ONE_MINUS_EPSILON;
use crate::scene::Scene;
use glam::Vec2;

/// The share α of a focused pixel's samples drawn around the images it
/// holds. Half: the weight of any sample is then at most 2, and the
/// bound on the samples near the image, `c·Z/α`, twice what focusing all
/// of them would give.
pub const FOCUS_SHARE: f32 = 0.5;

/// The pixels that hold the image of a point or spot light inside a
/// medium, with those images: sorted by row, then column.
#[derive(Clone, Debug, Default)]
pub struct LightImages {
    pixels: Vec<FocusedPixel>,
}

/// A pixel holding the images of one or more lights, and the densities
/// its focused samples are drawn from.
#[derive(Clone, Debug)]
struct FocusedPixel {
    y: u32,
    x: u32,
    /// One per image, about its position in the pixel.
    images: Vec<InverseDistance>,
}

impl LightImages {
    /// The images through `camera` of `scene`'s point and spot lights
    /// that lie inside its fog or one of its volumes' bounds, by pixel;
    /// none for a camera with a lens.
    pub fn new(scene: &Scene, camera: &Camera) -> Self {
        if camera.has_lens() {
            return Self::default();
        }
        let mut films: Vec<Vec2> = scene
            .lights
            .iter()
            .filter_map(|light| light.position())
            .filter(|&x| scene.in_medium(x))
            .filter_map(|x| Some(camera.project(x, Vec2::ZERO)?.film))
            .collect();
        let pixel_of = |film: &Vec2| (film.y as u32, film.x as u32);
        films.sort_by_key(pixel_of);
        let mut pixels: Vec<FocusedPixel> = Vec::new();
        for film in films {
            let (y, x) = pixel_of(&film);
            let image = InverseDistance::around(film - Vec2::new(x as f32, y as f32));
            match pixels.last_mut() {
                Some(last) if (last.y, last.x) == (y, x) => last.images.push(image),
                _ => pixels.push(FocusedPixel {
                    y,
                    x,
                    images: vec![image],
                }),
            }
        }
        Self { pixels }
    }

    /// The focused pixels of row `y`, for [`RowImages::sample`].
    pub fn row(&self, y: u32) -> RowImages<'_> {
        let start = self.pixels.partition_point(|p| p.y < y);
        let end = start + self.pixels[start..].partition_point(|p| p.y == y);
        RowImages {
            pixels: &self.pixels[start..end],
        }
    }
}

/// The focused pixels of one row, for its pixels in increasing `x`.
pub struct RowImages<'a> {
    pixels: &'a [FocusedPixel],
}

impl RowImages<'_> {
    /// The film position and weight of the sample of pixel `(x, y)` (of
    /// this row; `x` never smaller than the last call's) that
    /// `u ∈ [0, 1)²` draws: `(x, y) + u` with weight 1 in a pixel that
    /// holds no light's image, else from the defensive mixture of
    /// [`focused_sample`].
    #[inline]
    pub fn sample(&mut self, x: u32, y: u32, u: Vec2) -> (Vec2, f32) {
        let corner = Vec2::new(x as f32, y as f32);
        // The pixels left of `x` are done with.
        while self.pixels.first().is_some_and(|p| p.x < x) {
            self.pixels = &self.pixels[1..];
        }
        match self.pixels.first() {
            Some(pixel) if pixel.x == x => {
                let (at, weight) = focused_sample(&pixel.images, u);
                (corner + at, weight)
            }
            _ => (corner + u, 1.0),
        }
    }
}

/// A point of the unit square drawn by `u ∈ [0, 1)²`, and its weight
/// `1/p`: with probability `1 − α` uniformly, with probability `α` from
/// the density `q_k ∝ 1/r_k` about one of the `K` images (each with
/// probability `1/K`), so that `p = (1 − α) + (α/K)·Σ q_k`; α is
/// [`FOCUS_SHARE`].
fn focused_sample(images: &[InverseDistance], u: Vec2) -> (Vec2, f32) {
    let alpha = FOCUS_SHARE;
    let k = images.len();
    let x = if u.x < alpha {
        // Which image, then a point of its density by the rest of u.x.
        let scaled = u.x / alpha * k as f32;
        let which = (scaled as usize).min(k - 1);
        let rest = (scaled - which as f32).clamp(0.0, ONE_MINUS_EPSILON);
        images[which].sample(Vec2::new(rest, u.y))
    } else {
        Vec2::new(((u.x - alpha) / (1.0 - alpha)).min(ONE_MINUS_EPSILON), u.y)
    };
    let q = images.iter().map(|d| d.density(x)).sum::<f32>() / k as f32;
    (x, 1.0 / ((1.0 - alpha) + alpha * q))
}

/// The density `q(x) = 1/(Z·r)` over the unit square, `r = |x − a|` the
/// distance from a point `a` of the square, `Z = ∫ dA/r`.
///
/// The square is cut into the four triangles between `a` and its edges.
/// In polar coordinates about `a`, `q·dA = dr·dφ/Z`: over the triangle on
/// an edge at distance `d`, whose points along the edge lie at `s = d·tan φ`
/// from the foot of the perpendicular, the mass is `∫ d/cos φ dφ / Z =
/// d·[asinh(s/d)] / Z` between the edge's ends. So a sample picks a
/// triangle by mass, `φ` by inverting `asinh(tan φ)` (uniform in it: `s =
/// d·sinh v`), and then `r` uniformly along the ray from `a` to the edge.
#[derive(Clone, Copy, Debug)]
struct InverseDistance {
    a: Vec2,
    /// Per edge: the distance `d` from `a`, and `asinh(s/d)` at its two
    /// ends.
    edges: [(f32, f32, f32); 4],
    /// The masses' running sums (`d·Δasinh`), the last being `Z`.
    cumulative: [f32; 4],
}

impl InverseDistance {
    /// The density about the point `a` of the unit square (clamped into
    /// it).
    fn around(a: Vec2) -> Self {
        let a = a.clamp(Vec2::ZERO, Vec2::ONE);
        // (distance to the edge, the ends' offsets along it from the foot).
        let spans = [
            (a.y, -a.x, 1.0 - a.x),       // bottom edge y = 0
            (1.0 - a.x, -a.y, 1.0 - a.y), // right edge x = 1
            (1.0 - a.y, -a.x, 1.0 - a.x), // top edge y = 1
            (a.x, -a.y, 1.0 - a.y),       // left edge x = 0
        ];
        let mut edges = [(0.0, 0.0, 0.0); 4];
        let mut cumulative = [0.0; 4];
        let mut total = 0.0;
        for (i, &(d, s0, s1)) in spans.iter().enumerate() {
            let (v0, v1) = if d > 0.0 {
                ((s0 / d).asinh(), (s1 / d).asinh())
            } else {
                (0.0, 0.0)
            };
            edges[i] = (d, v0, v1);
            total += d * (v1 - v0);
            cumulative[i] = total;
        }
        Self {
            a,
            edges,
            cumulative,
        }
    }

    /// The point of the square `u ∈ [0, 1)²` picks.
    fn sample(&self, u: Vec2) -> Vec2 {
        let total = self.cumulative[3];
        let target = u.x * total;
        let edge = self
            .cumulative
            .iter()
            .position(|&c| target < c)
            .unwrap_or(3);
        let below = if edge == 0 {
            0.0
        } else {
            self.cumulative[edge - 1]
        };
        let (d, v0, v1) = self.edges[edge];
        let mass = self.cumulative[edge] - below;
        let share = if mass > 0.0 {
            ((target - below) / mass).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let s = d * (v0 + share * (v1 - v0)).sinh();
        // The point of the edge at offset s from the foot.
        let a = self.a;
        let on_edge = match edge {
            0 => Vec2::new(a.x + s, 0.0),
            1 => Vec2::new(1.0, a.y + s),
            2 => Vec2::new(a.x + s, 1.0),
            _ => Vec2::new(0.0, a.y + s),
        };
        // r uniform along the ray from `a` to the edge. `u.y = 0` would
        // land on `a` itself, where the density is infinite and the
        // weight 0: that null set is moved to the middle of the ray.
        let along = if u.y > 0.0 { u.y } else { 0.5 };
        (a + along * (on_edge - a)).clamp(Vec2::ZERO, Vec2::splat(ONE_MINUS_EPSILON))
    }

    /// `q(x)`: `1/(Z·|x − a|)`.
    fn density(&self, x: Vec2) -> f32 {
        let r = (x - self.a).length();
        1.0 / (self.cumulative[3] * r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points of the unit square where images may sit: inside, near an
    /// edge, near a corner, on an edge and on a corner.
    const IMAGES: [Vec2; 5] = [
        Vec2::new(0.37, 0.61),
        Vec2::new(0.93, 0.42),
        Vec2::new(0.04, 0.03),
        Vec2::new(0.5, 0.0),
        Vec2::new(1.0, 1.0),
    ];

    /// `∫ g` over the square in polar coordinates about `a`, by the
    /// midpoint rule in the angle and Gauss–Legendre in the radius: for
    /// `g = c/r + b` the radial integrand `g·r` is smooth. The distance
    /// `R(θ)` to the square's boundary is the exit of a ray from `a`.
    fn polar_integral(a: Vec2, g: impl Fn(Vec2) -> f64) -> f64 {
        // 8-point Gauss–Legendre on [0, 1].
        const NODES: [(f64, f64); 4] = [
            (0.183_434_642_495_649_8, 0.362_683_783_378_362),
            (0.525_532_409_916_329, 0.313_706_645_877_887_3),
            (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
            (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
        ];
        let angles = 20_000;
        let mut sum = 0.0;
        for k in 0..angles {
            let theta = (k as f64 + 0.5) / angles as f64 * std::f64::consts::TAU;
            let (s, c) = theta.sin_cos();
            let exit = |p: f64, d: f64| {
                if d > 0.0 {
                    (1.0 - p) / d
                } else if d < 0.0 {
                    -p / d
                } else {
                    f64::INFINITY
                }
            };
            let big_r = exit(a.x as f64, c).min(exit(a.y as f64, s));
            if big_r <= 0.0 {
                continue;
            }
            for &(x, w) in &NODES {
                for r in [0.5 * (1.0 - x) * big_r, 0.5 * (1.0 + x) * big_r] {
                    let p = Vec2::new((a.x as f64 + r * c) as f32, (a.y as f64 + r * s) as f32);
                    sum += g(p) * r * 0.5 * w * big_r;
                }
            }
        }
        sum * std::f64::consts::TAU / angles as f64
    }

    /// `∫ dA/r` over the rectangle `[x0, x1] × [y0, y1]`, `r` the
    /// distance from `a`, in closed form: `F(x, y) = x·ln(y + r) +
    /// y·ln(x + r)` has `∂²F/∂x∂y = 1/r` (coordinates relative to `a`; a
    /// term whose factor is 0 is 0, its logarithm's singularity
    /// notwithstanding).
    fn inverse_distance_over(a: Vec2, [x0, x1]: [f64; 2], [y0, y1]: [f64; 2]) -> f64 {
        let f = |x: f64, y: f64| {
            let (x, y) = (x - f64::from(a.x), y - f64::from(a.y));
            let r = x.hypot(y);
            let term = |k: f64, other: f64| if k == 0.0 { 0.0 } else { k * (other + r).ln() };
            term(x, y) + term(y, x)
        };
        f(x1, y1) - f(x0, y1) - f(x1, y0) + f(x0, y0)
    }

    /// The density integrates to 1 over the square (by the polar
    /// quadrature above, not by the sampler's own `Z`), and its samples
    /// fall in each of 8 × 8 cells as often as the cell's share of
    /// `∫ dA/r` says (closed form, [`inverse_distance_over`]), within 5
    /// binomial standard errors.
    #[test]
    fn inverse_distance_samples_follow_their_density() {
        for a in IMAGES {
            let q = InverseDistance::around(a);
            let total = polar_integral(a, |x| f64::from(q.density(x)));
            assert!((total - 1.0).abs() < 1e-3, "{a}: ∫q = {total}");
            let z = inverse_distance_over(a, [0.0, 1.0], [0.0, 1.0]);
            let n = 1 << 18;
            let side = 8;
            let mut counts = vec![0u32; side * side];
            for k in 0..n {
                // A 2-D lattice (Fibonacci-like): well spread, no RNG.
                let u = Vec2::new(
                    (k as f32 + 0.5) / n as f32,
                    (k as f64 * 0.618_033_988_75).fract() as f32,
                );
                let x = q.sample(u);
                assert!(x.cmpge(Vec2::ZERO).all() && x.cmplt(Vec2::ONE).all(), "{x}");
                let cell = (x * side as f32).as_uvec2();
                counts[cell.y as usize * side + cell.x as usize] += 1;
            }
            for (c, &count) in counts.iter().enumerate() {
                let (i, j) = ((c % side) as f64, (c / side) as f64);
                let h = 1.0 / side as f64;
                let mass =
                    inverse_distance_over(a, [i * h, (i + 1.0) * h], [j * h, (j + 1.0) * h]) / z;
                let expected = mass * n as f64;
                let sigma = (expected * (1.0 - mass)).sqrt().max(1.0);
                assert!(
                    (f64::from(count) - expected).abs() <= 5.0 * sigma,
                    "{a}, cell {c}: {count} samples, {expected:.0} expected"
                );
            }
        }
    }

    /// For an integrand `f = c/r + b` singular at the image (the
    /// in-scattering of a point light seen past it), the weighted samples
    /// average to `∫ f` (the quadrature above) within 5 standard errors,
    /// and none exceeds `c·Z/α + b/(1 − α)` (`Z = ∫ dA/r`): bounded where
    /// uniform samples are not (their second moment `∫ f²` diverges).
    /// With two images in the pixel, each is covered by its density.
    #[test]
    fn focused_samples_are_unbiased_and_bounded() {
        let (c, b) = (0.3f64, 0.7f64);
        let alpha = f64::from(FOCUS_SHARE);
        for pair in [false, true] {
            for a in IMAGES {
                let images: Vec<Vec2> = if pair {
                    vec![a, Vec2::new(0.71, 0.18)]
                } else {
                    vec![a]
                };
                let f = |x: Vec2| {
                    images
                        .iter()
                        .map(|&a| c / f64::from((x - a).length()))
                        .sum::<f64>()
                        + b
                };
                // Each singular term about its own image (about another
                // point its 1/r is not smooth in the radius).
                let exact = images
                    .iter()
                    .map(|&a| polar_integral(a, |x| c / f64::from((x - a).length())))
                    .sum::<f64>()
                    + b;
                let densities: Vec<InverseDistance> =
                    images.iter().map(|&a| InverseDistance::around(a)).collect();
                let n = 1 << 16;
                let (mut sum, mut sum2, mut most) = (0.0, 0.0, 0.0f64);
                for k in 0..n {
                    let u = Vec2::new(
                        (k as f32 + 0.5) / n as f32,
                        (k as f64 * 0.754_877_666_2).fract() as f32,
                    );
                    let (x, weight) = focused_sample(&densities, u);
                    let estimate = f(x) * f64::from(weight);
                    sum += estimate;
                    sum2 += estimate * estimate;
                    most = most.max(estimate);
                }
                let mean = sum / n as f64;
                let stderr = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
                assert!(
                    (mean - exact).abs() <= 5.0 * stderr + 1e-4 * exact,
                    "{images:?}: {mean} ± {stderr} against {exact}"
                );
                if !pair {
                    let z = polar_integral(a, |x| 1.0 / f64::from((x - a).length()));
                    let bound = c * z / alpha + b / (1.0 - alpha);
                    assert!(most <= bound * 1.001, "{a}: {most} > {bound}");
                }
            }
        }
    }
}
