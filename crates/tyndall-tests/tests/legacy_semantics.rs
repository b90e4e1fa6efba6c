//! What the paper's legacy scenes mean (issue 9): a spotlight's lamp quad
//! is not a second light, thin glass tints light whichever way it crosses
//! a pane, and a `c` after a non-emissive material block is the statement
//! it must be.
mod common;

use common::{estimate_ray_with, simpson};
use glam::Vec3;
use std::f64::consts::PI;
use tyndall::lights::Light;
use tyndall::ray::Ray;
use tyndall::{IntegratorKind, RenderSettings};
use tyndall_load::LegacyOptions;
use tyndall_load::SourceText;

fn parse(text: &str) -> common::Loaded {
    common::parse_legacy(&SourceText::new("test.obj", text), LegacyOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
}

const SIGMA_T: f64 = 0.2;
const ALBEDO: f64 = 0.8;
/// The lamp: a 2 × 2 quad at y = 2 above the point (0, 2, −3),
/// facing down, emitting radiance `EMITTED`, cutoff 30°.
const EMITTED: f64 = 2.0;
const LAMP_SIDE: f64 = 2.0;
const CUTOFF_DEG: f64 = 30.0;

/// One spot in fog and nothing else, in the paper's format; the camera
/// at the origin looks along −z.
fn spot_in_fog() -> common::Loaded {
    let h = LAMP_SIDE / 2.0;
    let text = format!(
        "material
diffuse 0 0 0
reflective 0 0 0
emitted {EMITTED} {EMITTED} {EMITTED}
c {CUTOFF_DEG}

m 0
v {a} 2 {b}
v {c} 2 {b}
v {c} 2 {d}
v {a} 2 {d}
f 1 2 3 4

PerspectiveCamera {{
  camera_position < 0, 0, 0 >
  point_of_interest < 0, 0, -1 >
  up < 0, 1, 0 >
  angle 30
}}
",
        a = -h,
        c = h,
        b = -3.0 - h,
        d = -3.0 + h,
    );
    let mut desc = parse(&text);
    // The quad's normal (v1 − v0) × (v2 − v0) = x̂ × ẑ = −ŷ points down.
    let Light::Spot(spot) = &desc.scene.lights()[0] else {
        panic!("the lamp should be a spot")
    };
    assert!((spot.direction - Vec3::NEG_Y).length() < 1e-6);
    desc.override_fog(Some(SIGMA_T as f32), Some(ALBEDO as f32))
        .expect("fog");
    desc
}

/// Eq. 1 along the ray from the origin along −z, by Simpson quadrature
/// written here: a spot at (0, 2, −3) pointing down with the paper's
/// linear profile (eq. 5), on-axis intensity emitted × area (docs/scene-format.md, legacy format),
/// isotropic phase 1/4π.
fn quadrature() -> f64 {
    let intensity = EMITTED * LAMP_SIDE * LAMP_SIDE;
    let cos_c = CUTOFF_DEG.to_radians().cos();
    let f = |s: f64| {
        let to_light = [0.0, 2.0, -3.0 + s];
        let d2: f64 = to_light.iter().map(|v| v * v).sum();
        let d = d2.sqrt();
        let cos_axis = to_light[1] / d;
        let profile = if cos_axis > cos_c {
            1.0 - (1.0 - cos_axis) / (1.0 - cos_c)
        } else {
            0.0
        };
        (-SIGMA_T * s).exp() * SIGMA_T * ALBEDO * intensity * profile * (-SIGMA_T * d).exp()
            / d2
            / (4.0 * PI)
    };
    simpson(f, 0.0, 250.0, 400_000)
}

/// Issue 9.1: `volpath --max-depth 1` counted the spot twice, once as the
/// spot light by NEE and again as the emission of its lamp quad when a
/// phase-sampled ray hit it. Each estimate must agree with the quadrature
/// within 5 standard errors (from the sample count) plus 2·10⁻⁴ relative
/// for float rounding.
#[test]
fn legacy_spot_is_counted_once() {
    let desc = spot_in_fog();
    let expected = quadrature();
    let ray = Ray::new(Vec3::ZERO, Vec3::NEG_Z);
    for (kind, max_depth) in [(IntegratorKind::Single, 1), (IntegratorKind::Volpath, 1)] {
        let settings = RenderSettings {
            integrator: kind,
            max_depth,
            ..desc.settings
        };
        let (mean, stderr) = estimate_ray_with(&desc, settings, ray, 8192);
        let (mean, stderr) = (mean.x as f64, stderr.x as f64);
        let tol = 5.0 * stderr + 2e-4 * expected;
        assert!(
            (mean - expected).abs() <= tol,
            "{kind:?}: {mean} ± {stderr} vs quadrature {expected} (tolerance {tol})"
        );
    }
}

/// The paper's fig. 8–9 set-up in its own format: a spot (cutoff 30°) at
/// y = 4 pointing down over a red pane (x < 0) and a blue pane (x > 0) at
/// y = 2, both facing up (their normals point at the spot), a grey floor
/// at y = 0 facing up. Light reaches everything below the panes only
/// through them.
const GLASS_PAIR: &str = "material
diffuse 0 0 0
reflective 0 0 0
emitted 1000 1000 1000
c 30

material
diffuse 1 0 0
reflective 0 0 0
emitted 0 0 0
alpha 0.5

material
diffuse 0 0 1
reflective 0 0 0
emitted 0 0 0
alpha 0.5

material
diffuse 0.5 0.5 0.5
reflective 0 0 0
emitted 0 0 0

m 0
v -0.1 4 -0.1
v 0.1 4 -0.1
v 0.1 4 0.1
v -0.1 4 0.1
f 1 2 3 4

m 1
v -3 2 -3
v -3 2 3
v 0 2 3
v 0 2 -3
f 5 6 7 8

m 2
v 0 2 -3
v 0 2 3
v 3 2 3
v 3 2 -3
f 9 10 11 12

m 3
v -5 0 -5
v -5 0 5
v 5 0 5
v 5 0 -5
f 13 14 15 16

PerspectiveCamera {
  camera_position < 0, 1, 8 >
  point_of_interest < 0, 1, 0 >
  up < 0, 1, 0 >
  angle 40
}
";

/// Issue 9.2: shadow rays from below met the up-facing panes from behind
/// and passed untinted (one-sided culling), so fog and floor under red
/// and blue glass stayed white. Under the blend model one pane of colour
/// c and opacity 0.5 turns white light into 0.5 + 0.5·c; fog and floor
/// are grey, so every sample along these rays carries exactly that tint,
/// and the ratio of the channels is the tint whatever the noise.
#[test]
fn glass_tints_light_crossing_it_from_either_side() {
    use tyndall::settings::VisibilityMode;
    let mut desc = parse(GLASS_PAIR);
    let Light::Spot(spot) = &desc.scene.lights()[0] else {
        panic!("the lamp should be a spot")
    };
    assert!((spot.direction - Vec3::NEG_Y).length() < 1e-6);
    desc.override_fog(Some(0.1), Some(0.5)).expect("fog");
    let red = Vec3::new(1.0, 0.5, 0.5);
    let blue = Vec3::new(0.5, 0.5, 1.0);
    // Rays from the camera staying below the panes: through the fog at
    // x = ∓1 (lit only through one pane), and onto the floor at x = ∓0.5.
    let camera = Vec3::new(0.0, 1.0, 8.0);
    let rays = [
        (
            Ray::new(Vec3::new(-1.0, 1.0, 8.0), Vec3::NEG_Z),
            red,
            "fog under red",
        ),
        (
            Ray::new(Vec3::new(1.0, 1.0, 8.0), Vec3::NEG_Z),
            blue,
            "fog under blue",
        ),
        (
            Ray::new(camera, (Vec3::new(-0.5, 0.0, 0.0) - camera).normalize()),
            red,
            "floor under red",
        ),
        (
            Ray::new(camera, (Vec3::new(0.5, 0.0, 0.0) - camera).normalize()),
            blue,
            "floor under blue",
        ),
    ];
    let configs = [
        (IntegratorKind::March, VisibilityMode::ShadowRays),
        (IntegratorKind::Single, VisibilityMode::ShadowRays),
        (IntegratorKind::Volpath, VisibilityMode::ShadowRays),
        (
            IntegratorKind::Single,
            VisibilityMode::Maps { resolution: 256 },
        ),
    ];
    for (kind, visibility) in configs {
        for (ray, tint, what) in rays {
            let settings = RenderSettings {
                integrator: kind,
                visibility,
                max_depth: 1,
                step: 0.05,
                ..desc.settings
            };
            let (mean, _) = estimate_ray_with(&desc, settings, ray, 256);
            assert!(mean.max_element() > 1e-3, "{what}, {kind:?}: unlit {mean}");
            let ratio = mean / mean.max_element();
            assert!(
                (ratio - tint).abs().max_element() < 1e-3,
                "{what}, {kind:?} {visibility:?}: colour {ratio} (radiance {mean}), expected tint {tint}"
            );
        }
    }
}

/// The 1-based line of the first line of `text` that is exactly `line`.
fn line_of(text: &str, line: &str) -> usize {
    text.lines().position(|l| l == line).expect("line in text") + 1
}

/// A lamp material (no cutoff of its own), then a glass block, then a
/// `c 35` line meant for the lamp's faces, then the lamp face. `extra`
/// goes before the lamp face.
fn lamp_after_glass(extra: &str) -> String {
    format!(
        "material
diffuse 0 0 0
reflective 0 0 0
emitted 40 40 40

material
diffuse 0.2 0.4 0.9
reflective 0 0 0
emitted 0 0 0
alpha 0.5
c 35

m 0
v -0.5 3 -0.5
v 0.5 3 -0.5
v 0.5 3 0.5
v -0.5 3 0.5
{extra}f 1 2 3 4
"
    )
}

/// Issue 9.3: a `c` after the last field of a non-emissive (glass) block
/// cannot be that material's: it is the statement for the lamp face that
/// follows, and the loader says where it read it so.
#[test]
fn cutoff_after_glass_block_is_a_statement() {
    let text = lamp_after_glass("");
    let desc = parse(&text);
    assert_eq!(desc.scene.lights().len(), 1);
    let Light::Spot(spot) = &desc.scene.lights()[0] else {
        panic!(
            "the lamp should be a spot, got {:?}",
            desc.scene.lights()[0]
        )
    };
    assert!((spot.cos_cutoff - 35f32.to_radians().cos()).abs() < 1e-6);
    let at = format!("test.obj:{}:1:", line_of(&text, "c 35"));
    let warned: Vec<_> = desc
        .warnings
        .iter()
        .filter(|w| w.contains("`c 35`"))
        .collect();
    assert_eq!(warned.len(), 1, "{:?}", desc.warnings);
    assert!(
        warned[0].starts_with(&at) && warned[0].contains("statement"),
        "{}",
        warned[0]
    );
}

/// A `c` ending an emissive block is that material's cutoff; the loader
/// warns when reading it as a statement would have changed a face (here
/// a second lamp of another emissive material that follows it), and
/// stays quiet when both readings give the same scene (the paper's own
/// fig. 7 file; the course format description's example with `c` in its lamp block).
#[test]
fn cutoff_ending_an_emissive_block_is_the_materials() {
    let text = "material
diffuse 0 0 0
reflective 0 0 0
emitted 40 40 40
c 30

material
diffuse 0 0 0
reflective 0 0 0
emitted 10 10 10

m 0
v -0.5 3 -0.5
v 0.5 3 -0.5
v 0.5 3 0.5
v -0.5 3 0.5
f 1 2 3 4
m 1
v 2 3 -0.5
v 3 3 -0.5
v 3 3 0.5
v 2 3 0.5
f 5 6 7 8
";
    let desc = parse(text);
    // Lights are numbered area lights first (SceneDesc's order).
    let kinds: Vec<_> = desc
        .scene
        .lights()
        .iter()
        .map(|l| match l {
            Light::Spot(s) => format!("spot {:.4}", s.cos_cutoff),
            Light::Quad(_) => "quad".to_string(),
            other => format!("{other:?}"),
        })
        .collect();
    assert_eq!(
        kinds,
        [
            "quad".into(),
            format!("spot {:.4}", 30f32.to_radians().cos())
        ]
    );
    let at = format!("test.obj:{}:1:", line_of(text, "c 30"));
    assert!(
        desc.warnings
            .iter()
            .any(|w| w.starts_with(&at) && w.contains("material 0 emits")),
        "{:?}",
        desc.warnings
    );

    // Unambiguous in effect: no warning about `c`.
    let fig7 = common::load_legacy(
        &common::repo().join("scenes/legacy/fig07-spot-sphere.obj"),
        LegacyOptions::default(),
    )
    .expect("fig. 7");
    assert!(
        fig7.warnings.iter().all(|w| !w.contains("`c ")),
        "{:?}",
        fig7.warnings
    );
    // A statement `c` after `m` is not ambiguous either.
    let plain = parse(&lamp_after_glass("c 20\n").replace("alpha 0.5\nc 35\n", "alpha 0.5\n"));
    assert!(matches!(plain.scene.lights()[0], Light::Spot(_)));
    assert!(plain.warnings.iter().all(|w| !w.contains("`c ")));
}

/// Shadow maps are an acceleration of shadow rays and must say the same.
/// Rays are traced towards the light, maps from it: below a one-sided
/// floor that faces a spot above it, a shadow ray meets the floor from
/// behind and passes (the course code's one-sidedness, docs/scene-format.md),
/// so the maps must pass that light too rather than stop it at the
/// floor's front face. The fog under the floor is compared along a ray
/// that never meets the floor, with `single` under both visibilities
/// (5 standard errors, from the sample count).
#[test]
fn shadow_maps_see_one_sided_quads_as_shadow_rays_do() {
    use tyndall::settings::VisibilityMode;
    let text = "material
diffuse 0 0 0
reflective 0 0 0
emitted 1000 1000 1000
c 40

material
diffuse 0.5 0.5 0.5
reflective 0 0 0
emitted 0 0 0

m 0
v -0.1 4 -0.1
v 0.1 4 -0.1
v 0.1 4 0.1
v -0.1 4 0.1
f 1 2 3 4

m 1
v -5 0 -5
v -5 0 5
v 5 0 5
v 5 0 -5
f 5 6 7 8
";
    let mut desc = parse(text);
    desc.override_fog(Some(0.1), Some(0.9)).expect("fog");
    let ray = Ray::new(Vec3::new(0.0, -1.0, 8.0), Vec3::NEG_Z);
    let estimate = |visibility| {
        let settings = RenderSettings {
            integrator: IntegratorKind::Single,
            visibility,
            ..desc.settings
        };
        estimate_ray_with(&desc, settings, ray, 1024)
    };
    let (rays, rays_err) = estimate(VisibilityMode::ShadowRays);
    let (maps, maps_err) = estimate(VisibilityMode::Maps { resolution: 256 });
    assert!(rays.x > 1e-3, "the fog below the floor is lit: {rays}");
    let tol = 5.0 * (rays_err.x.powi(2) + maps_err.x.powi(2)).sqrt() + 1e-3 * rays.x;
    assert!(
        (rays.x - maps.x).abs() <= tol,
        "shadow rays {rays} vs maps {maps} (tolerance {tol})"
    );
}

/// A spot sits on its own lamp quad, so a shadow map's rays start on that
/// quad. Shadow rays end short of the light; the maps must likewise not
/// let the lamp shadow its own light, however rounding places the hit of
/// a ray leaving a tilted quad's centroid (before, about half of tilted
/// lamps lost all their light under `--visibility maps`). Eight tilted
/// lamps in fog: `single` with maps agrees with shadow rays within 5
/// standard errors (from the sample count).
#[test]
fn shadow_maps_do_not_let_a_lamp_shadow_its_spot() {
    use tyndall::settings::VisibilityMode;
    for k in 0..8 {
        let (x0, z0) = (0.37 * k as f32 - 1.3, 0.23 * k as f32 - 0.8);
        let (slope_x, slope_z) = (0.31 * (k as f32 * 1.7).sin(), 0.27 * (k as f32 * 2.3).cos());
        let corner = |dx: f32, dz: f32| {
            let (x, z) = (x0 + dx, z0 + dz);
            format!("v {x} {} {z}\n", 4.0 + slope_x * dx + slope_z * dz)
        };
        let text = format!(
            "material\ndiffuse 0 0 0\nreflective 0 0 0\nemitted 1000 1000 1000\nc 40\nm 0\n{}{}{}{}f 1 2 3 4\n",
            corner(-0.1, -0.1),
            corner(0.1, -0.1),
            corner(0.1, 0.1),
            corner(-0.1, 0.1)
        );
        let mut desc = parse(&text);
        desc.override_fog(Some(0.1), Some(0.9)).expect("fog");
        let ray = Ray::new(Vec3::new(x0, 1.0, 8.0), Vec3::NEG_Z);
        let estimate = |visibility| {
            let settings = RenderSettings {
                integrator: IntegratorKind::Single,
                visibility,
                ..desc.settings
            };
            estimate_ray_with(&desc, settings, ray, 256)
        };
        let (rays, rays_err) = estimate(VisibilityMode::ShadowRays);
        let (maps, maps_err) = estimate(VisibilityMode::Maps { resolution: 128 });
        assert!(rays.x > 1e-3, "lamp {k}: the fog is lit: {rays}");
        let tol = 5.0 * (rays_err.x.powi(2) + maps_err.x.powi(2)).sqrt() + 1e-3 * rays.x;
        assert!(
            (rays.x - maps.x).abs() <= tol,
            "lamp {k}: shadow rays {rays} vs maps {maps} (tolerance {tol})"
        );
    }
}
