//! Unoccluded single scattering from point and spot lights against the
//! 1-D integral of docs/physics.md §5.1, evaluated by Simpson quadrature written here,
//! independently of the renderer:
//!
//! `L = ∫₀^∞ e^{−σt s} · σs · I(dir)/d(s)² · e^{−σt d(s)} · p(cos θ(s)) ds`.
mod common;

use common::{estimate_ray, estimate_ray_with, scene, simpson};
use std::f64::consts::PI;
use tyndall::ray::Ray;
use tyndall::{IntegratorKind, RenderSettings};

const SIGMA_T: f64 = 0.2;
const ALBEDO: [f64; 3] = [0.8, 0.6, 0.4];
const G: f64 = 0.5;

fn hg(cos: f64) -> f64 {
    (1.0 - G * G) / (4.0 * PI * (1.0 + G * G - 2.0 * G * cos).powf(1.5))
}

/// Quadrature of the in-scattering integral along the ray from the origin
/// along −z, for a light at `light` with angular profile `profile(cos)`
/// (cos of the angle off the light's axis) and intensity `intensity`.
fn quadrature(light: [f64; 3], intensity: [f64; 3], profile: impl Fn([f64; 3]) -> f64) -> [f64; 3] {
    let f = |s: f64, channel: usize| {
        let x = [0.0, 0.0, -s];
        let to_light = [light[0] - x[0], light[1] - x[1], light[2] - x[2]];
        let d2 = to_light.iter().map(|v| v * v).sum::<f64>();
        let d = d2.sqrt();
        // Light travels −to_light, then along −(ray direction) = +z... the
        // camera ray points along −z, so cos θ = (to_light/d)·(0, 0, −1).
        let cos = -to_light[2] / d;
        let from_light = [-to_light[0] / d, -to_light[1] / d, -to_light[2] / d];
        (-SIGMA_T * s).exp() * SIGMA_T * ALBEDO[channel] * intensity[channel] * profile(from_light)
            / d2
            * (-SIGMA_T * d).exp()
            * hg(cos)
    };
    // Beyond s = 250 the camera-side transmittance is e^{−50}.
    [0, 1, 2].map(|c| simpson(|s| f(s, c), 0.0, 250.0, 400_000))
}

fn fog_scene(light: &str) -> common::Loaded {
    scene(&format!(
        r#"
        [camera]
        position = [0, 0, 0]
        look_at = [0, 0, -1]
        fov_y_deg = 30
        [fog]
        sigma_t = {SIGMA_T}
        albedo = [{}, {}, {}]
        g = {G}
        [[lights]]
        {light}
        "#,
        ALBEDO[0], ALBEDO[1], ALBEDO[2]
    ))
}

/// Asserts each channel within 5 standard errors (plus 2·10⁻⁴ relative for
/// float rounding and the march's documented 10⁻⁴ truncation). The Sobol
/// samples are stratified, so the i.i.d. standard error is an upper bound
/// of the real one.
/// `single` is checked with 1, 3 and 8 equiangular samples per ray (the
/// multi-sample MIS weights must stay unbiased for any count).
fn check(desc: &common::Loaded, expected: [f64; 3], what: &str) {
    let ray = Ray::new(glam::Vec3::ZERO, -glam::Vec3::Z);
    let configs = [
        (IntegratorKind::Single, 1),
        (IntegratorKind::Single, 3),
        (IntegratorKind::Single, 8),
        (IntegratorKind::March, 1),
    ];
    for (kind, volume_samples) in configs {
        let settings = RenderSettings {
            integrator: kind,
            step: 0.05,
            volume_samples,
            ..desc.settings
        };
        let (mean, stderr) = estimate_ray_with(desc, settings, ray, 4096);
        for c in 0..3 {
            let tol = 5.0 * stderr[c] as f64 + 2e-4 * expected[c];
            let err = (mean[c] as f64 - expected[c]).abs();
            assert!(
                err <= tol,
                "{what}, {kind:?} ×{volume_samples}, channel {c}: {} vs quadrature {} (tolerance {tol})",
                mean[c],
                expected[c]
            );
        }
    }
}

#[test]
fn point_light_matches_quadrature() {
    let desc = fog_scene("type = \"point\"\nposition = [0.3, 1.0, -3.0]\nintensity = [10, 20, 30]");
    let expected = quadrature([0.3, 1.0, -3.0], [10.0, 20.0, 30.0], |_| 1.0);
    check(&desc, expected, "point light");
}

/// A spotlight pointing down with the paper's linear profile (eq. 5,
/// written again here): the cone clips the integral.
#[test]
fn linear_spot_matches_quadrature() {
    let desc = fog_scene(
        "type = \"spot\"\nposition = [0.0, 2.0, -3.0]\ndirection = [0, -1, 0]\ncutoff_deg = 30\nprofile = \"linear\"\nintensity = [10, 20, 30]",
    );
    let cos_c = 30f64.to_radians().cos();
    let eq5 = |dir: [f64; 3]| {
        let cos = -dir[1];
        if cos > cos_c {
            1.0 - (1.0 - cos) / (1.0 - cos_c)
        } else {
            0.0
        }
    };
    let expected = quadrature([0.0, 2.0, -3.0], [10.0, 20.0, 30.0], eq5);
    check(&desc, expected, "linear spot");
}

/// Henyey–Greenstein with g > 0 brightens a beam seen looking towards the
/// light and g < 0 darkens it (the phase-function direction convention):
/// the camera looks into a spot aimed at it, so all scattering it sees is
/// within 25° of straight on.
#[test]
fn forward_scattering_brightens_beam_towards_light() {
    let light = "type = \"spot\"\nposition = [0.0, 0.3, -8.0]\ndirection = [0, 0, 1]\ncutoff_deg = 20\nprofile = \"hard\"\nintensity = 10";
    let ray = Ray::new(glam::Vec3::ZERO, -glam::Vec3::Z);
    let with_g = |g: f32| {
        let mut desc = fog_scene(light);
        desc.override_fog_asymmetry(g).expect("fog");
        estimate_ray(&desc, IntegratorKind::Single, 0.1, ray, 256)
            .0
            .x
    };
    let (back, iso, fwd) = (with_g(-0.5), with_g(0.0), with_g(0.5));
    assert!(
        fwd > 1.5 * iso && iso > 1.5 * back,
        "g −0.5: {back}, 0: {iso}, 0.5: {fwd}"
    );
}
