//! Stained glass (the paper's §3.3, eq. 6) seen through shadow rays: a
//! point light shines through two panes onto a diffuse floor. The tint is
//! computed here from the definitions, independently of the renderer:
//! filter `t = (1 − α) + α·c` per crossing (commutes); blend
//! `b₁ = b₀(1 − α) + c·α` from white in the order light meets the panes.
mod common;

use common::{estimate_ray, scene};
use std::f32::consts::PI;
use tyndall::ray::Ray;
use tyndall::{IntegratorKind, Rgb};

const RED: ([f32; 3], f32) = ([0.9, 0.1, 0.1], 0.6);
const BLUE: ([f32; 3], f32) = ([0.1, 0.2, 0.9], 0.8);

/// Floor radiance under the light with `upper` pane at y = 2 and `lower`
/// at y = 1; light at y = 4, intensity 16, floor reflectance 0.5.
fn floor_radiance(model: &str, upper: ([f32; 3], f32), lower: ([f32; 3], f32)) -> Rgb {
    let pane = |y: f32, name: &str| {
        format!(
            "[[shapes]]\ntype = \"quad\"\ncorners = [[-2, {y}, -2], [-2, {y}, 2], [2, {y}, 2], [2, {y}, -2]]\nmaterial = \"{name}\"\n"
        )
    };
    let desc = scene(&format!(
        r#"
        [camera]
        position = [0, 0.5, 0]
        look_at = [0, 0, 0]
        up = [0, 0, 1]
        fov_y_deg = 1
        [render]
        glass_model = "{model}"
        [materials.floor]
        type = "diffuse"
        reflectance = 0.5
        [materials.upper]
        type = "glass"
        color = {:?}
        alpha = {}
        [materials.lower]
        type = "glass"
        color = {:?}
        alpha = {}
        [[shapes]]
        type = "quad"
        corners = [[-5, 0, -5], [-5, 0, 5], [5, 0, 5], [5, 0, -5]]
        material = "floor"
        {}
        {}
        [[lights]]
        type = "point"
        position = [0, 4, 0]
        intensity = 16
        "#,
        upper.0,
        upper.1,
        lower.0,
        lower.1,
        pane(2.0, "upper"),
        pane(1.0, "lower"),
    ));
    let ray = Ray::new(glam::Vec3::new(0.0, 0.5, 0.0), -glam::Vec3::Y);
    estimate_ray(&desc, IntegratorKind::Single, 0.1, ray, 1).0
}

fn filter(g: ([f32; 3], f32)) -> Rgb {
    Rgb::splat(1.0 - g.1) + g.1 * Rgb::from_array(g.0)
}

fn blend(b0: Rgb, g: ([f32; 3], f32)) -> Rgb {
    b0 * (1.0 - g.1) + Rgb::from_array(g.0) * g.1
}

/// E = I/d² = 16/16 = 1 on the floor below the light; L = ρ/π·E·tint.
fn expected(tint: Rgb) -> Rgb {
    0.5 / PI * tint
}

fn assert_close(a: Rgb, b: Rgb, what: &str) {
    assert!((a - b).abs().max_element() <= 1e-5, "{what}: {a} vs {b}");
}

#[test]
fn filter_model_multiplies_and_commutes() {
    let both = filter(RED) * filter(BLUE);
    assert_close(
        floor_radiance("filter", RED, BLUE),
        expected(both),
        "red over blue",
    );
    assert_close(
        floor_radiance("filter", BLUE, RED),
        expected(both),
        "blue over red",
    );
}

#[test]
fn blend_model_is_eq6_in_light_order() {
    let red_first = blend(blend(Rgb::ONE, RED), BLUE);
    let blue_first = blend(blend(Rgb::ONE, BLUE), RED);
    assert!(
        (red_first - blue_first).abs().max_element() > 0.1,
        "the test needs order to matter"
    );
    assert_close(
        floor_radiance("blend", RED, BLUE),
        expected(red_first),
        "red over blue",
    );
    assert_close(
        floor_radiance("blend", BLUE, RED),
        expected(blue_first),
        "blue over red",
    );
}

/// Eq. 6 at values worked by hand: white through (c = red, α = 0.5) is
/// (1, 0.5, 0.5); then through (c = blue, α = 0.5) is (0.5, 0.25, 0.75).
#[test]
fn eq6_hand_values() {
    let red = tyndall::glass::Glass {
        color: Rgb::X,
        alpha: 0.5,
    };
    let blue = tyndall::glass::Glass {
        color: Rgb::Z,
        alpha: 0.5,
    };
    let once = red.blend(Rgb::ONE);
    assert_close(once, Rgb::new(1.0, 0.5, 0.5), "one pane");
    assert_close(blue.blend(once), Rgb::new(0.5, 0.25, 0.75), "two panes");
    let model = tyndall::glass::GlassModel::Blend;
    assert_close(
        model.tint([&red, &blue]),
        Rgb::new(0.5, 0.25, 0.75),
        "GlassModel::tint",
    );
    assert_close(
        red.filter_transmittance(),
        Rgb::new(1.0, 0.5, 0.5),
        "filter, one pane",
    );
}

/// A solid dielectric's absorbing inside (`absorption`, glTF's
/// `KHR_materials_volume`) is Beer–Lambert along the path inside: an
/// index-matched sphere (ior 1, so no ray reflects or bends) of radius r
/// before a uniform sky of radiance 1 passes `exp(−σa·2√(r² − b²))` along a
/// ray at distance b from its centre, per channel, in every integrator.
/// The paths are deterministic, so the estimates are exact but for the
/// rays' moves off each interface (`offset_distance`, along the normal):
/// the chord inside is shorter by at most twice that over cos θ, which
/// bounds the error at `T·σa·Δ`.
#[test]
fn absorbing_dielectric_is_beer_lambert() {
    let sigma = Rgb::new(0.2, 0.9, 2.5);
    let desc = scene(&format!(
        r#"[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
fov_y_deg = 30

[materials.tinted]
type = "dielectric"
ior = 1.0
absorption = [{}, {}, {}]

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "tinted"

[[lights]]
type = "environment"
radiance = 1
"#,
        sigma.x, sigma.y, sigma.z
    ));
    let text = |absorption: &str| {
        format!(
            "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov_y_deg = 30\n\n\
             [materials.tinted]\ntype = \"dielectric\"\nior = 1.0\nabsorption = {absorption}\n"
        )
    };
    let refused = common::parse_native(&tyndall_load::SourceText::new("glass.toml", text("-1")));
    let e = refused
        .err()
        .expect("a negative absorption is refused")
        .to_string();
    assert!(
        e.starts_with("glass.toml:") && e.contains("absorption"),
        "{e}"
    );
    for kind in IntegratorKind::ALL {
        for b in [0.0f32, 0.5, 0.9, 1.2] {
            let ray = Ray::new(glam::Vec3::new(b, 0.0, 5.0), -glam::Vec3::Z);
            let (mean, _) = estimate_ray(&desc, kind, 0.1, ray, 16);
            let chord = 2.0 * (1.0 - b * b).max(0.0).sqrt();
            let expected = Rgb::new(
                (-sigma.x * chord).exp(),
                (-sigma.y * chord).exp(),
                (-sigma.z * chord).exp(),
            );
            let cos = (1.0 - b * b).max(0.0).sqrt();
            let shortened = if cos > 0.0 {
                2.0 * tyndall::ray::offset_distance(glam::Vec3::ONE) / cos
            } else {
                0.0
            };
            let bound = expected * sigma * shortened + Rgb::splat(1e-6);
            assert!(
                (mean - expected).abs().cmple(bound).all(),
                "{kind:?}, b = {b}: {mean} vs {expected}, bound {bound}"
            );
        }
    }
}
