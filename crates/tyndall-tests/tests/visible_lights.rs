//! Lights seen in fog: the pixel holding a point light's or a spot's
//! image, whose in-scattered radiance grows as `1/r` towards the image,
//! against the pixel's value by a quadrature written here
//! (tyndall::render's `LightImages` draws part of that pixel's samples
//! around the image, which makes its variance finite; the mean must not
//! move).
//!
//! Along a ray from the pinhole with unit direction `w`, the light at `P`
//! passes at `D = |P − (P·w)·w|`, and with `s = P·w + D·tan φ` the single
//! scattering integral of docs/physics.md §5.1 becomes smooth in φ:
//! `L = ∫ σs·p·I·e^{−σt·(s + d)} / D dφ` (`d = D/cos φ`, `p = 1/4π`). The
//! pixel's value is the mean of `L` over the pixel, integrated in polar
//! coordinates about the image, where `L·r` is bounded.
mod common;

use common::{scene, simpson};
use glam::{DVec2, DVec3};
use std::f64::consts::{PI, TAU};
use tyndall::IntegratorKind;

/// Gauss–Legendre nodes and weights on [−1, 1] (8 points, by symmetry).
const GAUSS_8: [(f64, f64); 4] = [
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
];

/// `∫ f` over `[a, b]` by 8-point Gauss–Legendre on each of `pieces`
/// equal parts.
fn gauss(f: impl Fn(f64) -> f64, a: f64, b: f64, pieces: usize) -> f64 {
    let h = (b - a) / pieces as f64;
    (0..pieces)
        .map(|k| {
            let mid = a + (k as f64 + 0.5) * h;
            GAUSS_8
                .iter()
                .map(|&(x, w)| w * (f(mid - 0.5 * h * x) + f(mid + 0.5 * h * x)))
                .sum::<f64>()
                * 0.5
                * h
        })
        .sum()
}

const SIGMA_T: f64 = 0.1;
const ALBEDO: f64 = 0.8;
const INTENSITY: f64 = 2.0;
/// The image is 7 × 7 pixels, 20° high.
const SIZE: u32 = 7;
const FOV_DEG: f64 = 20.0;
/// Where the light's image falls on the film (pixels, y down): in pixel
/// (3, 3), off its centre.
const IMAGE: DVec2 = DVec2::new(3.3, 3.6);
const DISTANCE: f64 = 4.0;

/// The direction of the camera ray through film position `f` (pixels),
/// as a pinhole at the origin looking down −z maps it.
fn direction(f: DVec2) -> DVec3 {
    let half = (0.5 * FOV_DEG).to_radians().tan();
    let ndc = 2.0 * f / f64::from(SIZE) - DVec2::ONE;
    DVec3::new(ndc.x * half, -ndc.y * half, -1.0).normalize()
}

fn light_position() -> DVec3 {
    direction(IMAGE) * DISTANCE
}

/// In-scattered radiance along the ray through film position `f`.
fn radiance(f: DVec2) -> f64 {
    scattered_along(direction(f), light_position(), 0.0, f64::INFINITY, 400)
}

/// The single-scattering integral along the ray from the pinhole with
/// unit direction `w` over `[t0, t1]` (`t1` may be ∞) from a light of
/// intensity [`INTENSITY`] at `light`, by Simpson's rule with `intervals`
/// in the equiangular variable φ (`t = s0 + D·tan φ`), where it is smooth.
fn scattered_along(w: DVec3, light: DVec3, t0: f64, t1: f64, intervals: usize) -> f64 {
    let s0 = light.dot(w);
    let d_line = (light - s0 * w).length();
    let sigma_s = SIGMA_T * ALBEDO;
    let integrand = |phi: f64| {
        let s = s0 + d_line * phi.tan();
        let d = d_line / phi.cos();
        sigma_s / (4.0 * PI) * INTENSITY * (-SIGMA_T * (s + d)).exp() / d_line
    };
    // φ → π/2 is t → ∞.
    let phi = |t: f64| {
        if t.is_finite() {
            ((t - s0) / d_line).atan()
        } else {
            0.5 * PI - 1e-9
        }
    };
    simpson(integrand, phi(t0), phi(t1), intervals)
}

/// The mean of [`radiance`] over pixel `(x, y)`: in polar coordinates
/// about `centre` (8-point Gauss–Legendre in the radius to the pixel's
/// edge, midpoints in the angle).
fn pixel_value(x: u32, y: u32, centre: DVec2) -> f64 {
    let (lo, hi) = (
        DVec2::new(f64::from(x), f64::from(y)),
        DVec2::new(f64::from(x + 1), f64::from(y + 1)),
    );
    let angles = 720;
    let mut sum = 0.0;
    for k in 0..angles {
        let theta = (k as f64 + 0.5) / angles as f64 * TAU;
        let dir = DVec2::new(theta.cos(), theta.sin());
        let exit = |c: f64, d: f64, lo: f64, hi: f64| {
            if d > 0.0 {
                (hi - c) / d
            } else if d < 0.0 {
                (lo - c) / d
            } else {
                f64::INFINITY
            }
        };
        let edge = exit(centre.x, dir.x, lo.x, hi.x).min(exit(centre.y, dir.y, lo.y, hi.y));
        sum += gauss(|r| radiance(centre + r * dir) * r, 0.0, edge, 1);
    }
    sum * TAU / angles as f64
}

/// The pixel holding the image, and its neighbour, against their
/// quadratures: the mean over 16 seeds within 5 standard errors of the
/// seeds' scatter (plus 10⁻³ relative for the quadrature and float
/// rounding); each seed's render is 1024 samples per pixel.
///
/// The test sees a bias, not the noise focusing removes (the bound on
/// focused samples is the core's `focused_samples_are_unbiased_and_bounded`):
/// measured once with focusing turned off, this pixel's standard error
/// over the 16 seeds was 3.2·10⁻³, against 2.0·10⁻⁵ focused; a density
/// 10 % off in the weights moved the mean by 1200 standard errors.
#[test]
fn the_pixel_holding_a_point_light_converges_to_its_quadrature() {
    let p = light_position();
    let desc = fog_scene(&format!(
        r#"
        type = "point"
        position = [{}, {}, {}]
        intensity = {INTENSITY}
        "#,
        p.x, p.y, p.z
    ));
    assert_eq!(desc.settings.integrator, IntegratorKind::Single);
    // The neighbour's integrand is smooth: about its own centre.
    let cases = [
        (
            3,
            3,
            pixel_value(3, 3, IMAGE),
            "the pixel holding the image",
        ),
        (
            4,
            3,
            pixel_value(4, 3, DVec2::new(4.5, 3.5)),
            "its neighbour",
        ),
    ];
    assert_pixels_match(&desc, 100, &cases);
}

/// A 7 × 7 image through fog everywhere (isotropic, so `p = 1/4π`) lit
/// by the one light `light` (the body of its `[[lights]]` table), with
/// `single` at 1024 spp.
fn fog_scene(light: &str) -> common::Loaded {
    scene(&format!(
        r#"
        [camera]
        position = [0, 0, 0]
        look_at = [0, 0, -1]
        fov_y_deg = {FOV_DEG}
        [render]
        width = {SIZE}
        height = {SIZE}
        spp = 1024
        integrator = "single"
        [fog]
        sigma_t = {SIGMA_T}
        albedo = {ALBEDO}
        g = 0.0
        [[lights]]
        {light}
        "#
    ))
}

/// Renders `desc` with 16 seeds from `first_seed` and asserts each
/// `(x, y, expected, what)`: the seeds' mean of the pixel within 5 of
/// their standard errors of `expected` (plus 10⁻³ relative for the
/// quadrature and float rounding).
fn assert_pixels_match(desc: &common::Loaded, first_seed: u64, cases: &[(u32, u32, f64, &str)]) {
    let images: Vec<_> = (0..16u64)
        .map(|seed| common::render(desc, |s| s.seed = first_seed + seed))
        .collect();
    for &(x, y, expected, what) in cases {
        let values: Vec<f64> = images
            .iter()
            .map(|im| f64::from(im.pixel(x, y).x))
            .collect();
        let (mean, stderr) = common::mean_and_stderr(&values);
        assert!(
            (mean - expected).abs() <= 5.0 * stderr + 1e-3 * expected,
            "{what}: {mean} ± {stderr} against the quadrature's {expected}"
        );
    }
}

/// The side-on spot: 22 m straight ahead at the camera's height,
/// pointing down, a hard cone of 10°.
const SPOT_DISTANCE: f64 = 22.0;
const SPOT_CUTOFF_DEG: f64 = 10.0;

/// In-scattered radiance of the side-on spot along the ray through film
/// position `f`: the integral above over the part of the ray inside the
/// cone. The cosine of the angle off the cone's axis is unimodal along a
/// line (the directions from the apex sweep one great-circle arc), so a
/// golden-section search finds the ray's point nearest the axis in
/// angle: outside the cone there, the ray misses it; else bisection (in
/// f64) finds where it enters and leaves.
fn spot_radiance(f: DVec2) -> f64 {
    let w = direction(f);
    let apex = DVec3::new(0.0, 0.0, -SPOT_DISTANCE);
    let cos_cutoff = SPOT_CUTOFF_DEG.to_radians().cos();
    let cos_off_axis = |t: f64| {
        let p = t * w - apex;
        -p.y / p.length()
    };
    let inside = |t: f64| cos_off_axis(t) > cos_cutoff;
    let s0 = apex.dot(w);
    let (mut lo, mut hi) = (s0 - SPOT_DISTANCE, s0 + SPOT_DISTANCE);
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        let (a, b) = (hi - golden * (hi - lo), lo + golden * (hi - lo));
        if cos_off_axis(a) > cos_off_axis(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    let most = 0.5 * (lo + hi);
    if !inside(most) {
        return 0.0;
    }
    let edge = |outward: f64| {
        let (mut lo, mut hi) = (most, most + outward);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if inside(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    };
    let (enter, leave) = (edge(-SPOT_DISTANCE), edge(SPOT_DISTANCE));
    scattered_along(w, apex, enter, leave, 200)
}

/// A spot seen side-on from 22 m at its apex's height, its image at the
/// film's centre: the pixel holding the apex and the one below it
/// against their quadratures, as in the test above. Seen from the apex's
/// height, the lines that meet the cone are those whose film point lies
/// in the wedge below the image within the cutoff of straight down (the
/// planes through the camera tangent to the cone), so each pixel's value
/// is a polar integral over that wedge, where `L·r` is smooth: Gauss–
/// Legendre in the angle and the radius.
///
/// Sampled uniformly, this pixel's samples have infinite variance: four
/// renders of 16384 spp before focusing gave it 5.67–5.99·10⁻⁵ against
/// the quadrature's 5.95·10⁻⁵. (The cone's lost crossings within
/// millimetres of the apex, fixed with focusing, are too small a share
/// of this pixel to show here: spot.rs and the GPU's thin_beams.rs test
/// them.)
#[test]
fn the_pixel_holding_a_spots_apex_converges_to_its_quadrature() {
    let desc = fog_scene(&format!(
        r#"
        type = "spot"
        position = [0, 0, -{SPOT_DISTANCE}]
        look_at = [0, -1, -{SPOT_DISTANCE}]
        cutoff_deg = {SPOT_CUTOFF_DEG}
        profile = "hard"
        intensity = {INTENSITY}
        "#
    ));
    let image = DVec2::splat(0.5 * f64::from(SIZE));
    let cutoff = SPOT_CUTOFF_DEG.to_radians();
    // Film y points down: straight down is the angle π/2.
    let (a, b) = (0.5 * PI - cutoff, 0.5 * PI + cutoff);
    // From the image at (3.5, 3.5) the wedge leaves pixel (3, 3) through
    // its bottom edge y = 4 and crosses pixel (3, 4) to y = 5 (within
    // x ∈ [3, 4]: 1.52·sin 10° < 0.5).
    let wedge = |near: f64, far: f64| {
        gauss(
            |theta| {
                let dir = DVec2::new(theta.cos(), theta.sin());
                let (r0, r1) = (near / dir.y, far / dir.y);
                gauss(|r| spot_radiance(image + r * dir) * r, r0, r1, 2)
            },
            a,
            b,
            32,
        )
    };
    let cases = [
        (3, 3, wedge(0.0, 0.5), "the pixel holding the apex"),
        (3, 4, wedge(0.5, 1.5), "the pixel below it"),
    ];
    assert_pixels_match(&desc, 200, &cases);
}
