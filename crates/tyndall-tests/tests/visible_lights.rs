//! A point light seen in fog: the pixel holding its image, whose
//! in-scattered radiance grows as `1/r` towards the image, against the
//! pixel's value by a quadrature written here (tyndall::render's
//! `LightImages` draws part of that pixel's samples around the image,
//! which makes its variance finite; the mean must not move).
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
    let w = direction(f);
    let p = light_position();
    let s0 = p.dot(w);
    let d_line = (p - s0 * w).length();
    let sigma_s = SIGMA_T * ALBEDO;
    let integrand = |phi: f64| {
        let s = s0 + d_line * phi.tan();
        let d = d_line / phi.cos();
        sigma_s / (4.0 * PI) * INTENSITY * (-SIGMA_T * (s + d)).exp() / d_line
    };
    // The ray starts at the pinhole (s = 0); φ → π/2 is s → ∞.
    simpson(integrand, (-s0 / d_line).atan(), 0.5 * PI - 1e-9, 400)
}

/// The mean of [`radiance`] over pixel `(x, y)`: in polar coordinates
/// about `centre` (8-point Gauss–Legendre in the radius to the pixel's
/// edge, midpoints in the angle).
fn pixel_value(x: u32, y: u32, centre: DVec2) -> f64 {
    const NODES: [(f64, f64); 4] = [
        (0.183_434_642_495_649_8, 0.362_683_783_378_362),
        (0.525_532_409_916_329, 0.313_706_645_877_887_3),
        (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
        (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
    ];
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
        for &(node, weight) in &NODES {
            for r in [0.5 * (1.0 - node) * edge, 0.5 * (1.0 + node) * edge] {
                sum += radiance(centre + r * dir) * r * 0.5 * weight * edge;
            }
        }
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
    let desc = scene(&format!(
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
        type = "point"
        position = [{}, {}, {}]
        intensity = {INTENSITY}
        "#,
        p.x, p.y, p.z
    ));
    assert_eq!(desc.settings.integrator, IntegratorKind::Single);
    let images: Vec<_> = (0..16u64)
        .map(|seed| common::render(&desc, |s| s.seed = 100 + seed))
        .collect();
    // The neighbour's integrand is smooth: about its own centre.
    let cases = [
        (3, 3, IMAGE, "the pixel holding the image"),
        (4, 3, DVec2::new(4.5, 3.5), "its neighbour"),
    ];
    for (x, y, centre, what) in cases {
        let values: Vec<f64> = images
            .iter()
            .map(|im| f64::from(im.pixel(x, y).x))
            .collect();
        let (mean, stderr) = common::mean_and_stderr(&values);
        let expected = pixel_value(x, y, centre);
        assert!(
            (mean - expected).abs() <= 5.0 * stderr + 1e-3 * expected,
            "{what}: {mean} ± {stderr} against the quadrature's {expected}"
        );
    }
}
