//! The first-surface guides (AOVs, issue 24) against closed forms: a
//! wall seen straight, through a glass pane, in a mirror and through a
//! dielectric sphere, and the sky. The radiance is the same with and
//! without them, and parts carry them as they carry the radiance.

mod common;

use common::{Loaded, scene};
use glam::Vec3;
use tyndall::aov::Aov;
use tyndall::guides::Guides;
use tyndall::{IntegratorKind, Rgb};

/// The camera of every scene here: at (0, 0, 5) looking down −z, 40°
/// vertical field of view, over `W`×`H` pixels.
const CAMERA: &str = r#"
[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov_y_deg = 40.0
"#;
const W: u32 = 61;
const H: u32 = 45;

/// The wall's colour, and the wall: a diffuse quad of side 100 in the
/// plane z = `z` (two-sided, so its winding does not matter; the normal
/// guide faces the ray).
const WALL: [f32; 3] = [0.2, 0.5, 0.7];
fn wall(z: f32) -> String {
    format!(
        r#"
[materials.wall]
type = "diffuse"
reflectance = {WALL:?}

[[shapes]]
type = "quad"
corners = [[-50.0, -50.0, {z:?}], [50.0, -50.0, {z:?}], [50.0, 50.0, {z:?}], [-50.0, 50.0, {z:?}]]
material = "wall"
"#
    )
}

fn rig(extra: &str) -> Loaded {
    scene(&format!(
        "{CAMERA}\n[render]\nwidth = {W}\nheight = {H}\nspp = 4\nintegrator = \"single\"\n{extra}\n[[lights]]\ntype = \"point\"\nposition = [0.0, 0.0, 4.0]\nintensity = 1.0\n"
    ))
}

/// The guides of a whole render of `desc` (its settings, guides on).
fn guides(desc: &Loaded) -> Guides {
    let settings = tyndall::RenderSettings {
        guides: true,
        threads: Some(2),
        ..desc.settings
    };
    let sums = common::accumulate(desc, &settings);
    sums.resolve_guides().expect("guides kept")
}

/// The camera ray's direction through film point (x, y) in pixels, not
/// normalised, with z = −1: the pinhole camera's geometry written out.
fn film_direction(x: f32, y: f32) -> Vec3 {
    let t = 20f32.to_radians().tan();
    let aspect = W as f32 / H as f32;
    Vec3::new(
        (2.0 * x / W as f32 - 1.0) * t * aspect,
        -(2.0 * y / H as f32 - 1.0) * t,
        -1.0,
    )
}

/// The range of distances from the camera to the plane z = `z` over the
/// footprint of pixel (x, y): `(5 − z)·|d|` with d = (a, b, −1), which is
/// convex in (a, b): its largest value is at a corner, its smallest where
/// (a, b) is closest to 0.
fn depth_range(x: u32, y: u32, z: f32) -> (f32, f32) {
    let (x, y) = (x as f32, y as f32);
    let corners =
        [(x, y), (x + 1.0, y), (x, y + 1.0), (x + 1.0, y + 1.0)].map(|(u, v)| film_direction(u, v));
    let a = corners.map(|d| d.x);
    let b = corners.map(|d| d.y);
    let closest = |v: [f32; 4]| {
        let (lo, hi) = (
            v.iter().cloned().fold(f32::MAX, f32::min),
            v.iter().cloned().fold(f32::MIN, f32::max),
        );
        if lo <= 0.0 && hi >= 0.0 {
            0.0
        } else {
            lo.abs().min(hi.abs())
        }
    };
    let far = corners.iter().map(|d| d.length()).fold(0.0, f32::max);
    let near = Vec3::new(closest(a), closest(b), -1.0).length();
    ((5.0 - z) * near, (5.0 - z) * far)
}

fn assert_close(got: Rgb, expected: Rgb, tolerance: f32, what: &str) {
    assert!(
        (got - expected).abs().max_element() <= tolerance,
        "{what}: {got} vs {expected}"
    );
}

/// Every pixel of the wall seen straight: its albedo and normal exactly,
/// its points on the plane inside the pixel's footprint, its depth within
/// the footprint's range of distances.
#[test]
fn a_wall_seen_straight() {
    let g = guides(&rig(&wall(0.0)));
    let wall = Rgb::from(WALL);
    for y in 0..H {
        for x in 0..W {
            let what = format!("pixel ({x}, {y})");
            assert_eq!(g.albedo.pixel(x, y), wall, "{what}");
            assert_eq!(g.normal.pixel(x, y), Rgb::Z, "{what}");
            let (near, far) = depth_range(x, y, 0.0);
            let depth = g.depth.pixel(x, y).x;
            let slack = 1e-5 * far;
            assert!(
                depth >= near - slack && depth <= far + slack,
                "{what}: depth {depth} outside [{near}, {far}]"
            );
            // The footprint on the plane: 5·(a, b) over the pixel.
            let p = g.position.pixel(x, y);
            let (lo, hi) = (
                5.0 * film_direction(x as f32, y as f32 + 1.0),
                5.0 * film_direction(x as f32 + 1.0, y as f32),
            );
            assert!(p.z.abs() < 1e-5, "{what}: {p}");
            assert!(
                p.x >= lo.x - 1e-5
                    && p.x <= hi.x + 1e-5
                    && p.y >= lo.y - 1e-5
                    && p.y <= hi.y + 1e-5,
                "{what}: {p} outside {lo}..{hi}"
            );
        }
    }
}

/// A pane of thin glass (colour c, opacity α) in front of the wall: the
/// albedo is the wall's times the pane's transmittance (1 − α) + α·c, the
/// normal the wall's, and the depth the pane's.
#[test]
fn a_wall_through_a_glass_pane() {
    let (c, alpha) = ([0.9f32, 0.3, 0.6], 0.75f32);
    let pane = format!(
        "{}\n[materials.pane]\ntype = \"glass\"\ncolor = {c:?}\nalpha = {alpha}\n\n[[shapes]]\ntype = \"quad\"\ncorners = [[-50.0, -50.0, 2.0], [50.0, -50.0, 2.0], [50.0, 50.0, 2.0], [-50.0, 50.0, 2.0]]\nmaterial = \"pane\"\n",
        wall(0.0)
    );
    let g = guides(&rig(&pane));
    let t = Rgb::splat(1.0 - alpha) + alpha * Rgb::from(c);
    for (x, y) in [(0, 0), (30, 22), (60, 44)] {
        assert_close(g.albedo.pixel(x, y), t * Rgb::from(WALL), 1e-6, "albedo");
        assert_eq!(g.normal.pixel(x, y), Rgb::Z);
        let (near, far) = depth_range(x, y, 2.0);
        let depth = g.depth.pixel(x, y).x;
        assert!(
            depth >= near * (1.0 - 1e-5) && depth <= far * (1.0 + 1e-5),
            "depth {depth} outside [{near}, {far}]"
        );
    }
}

/// A mirror of reflectance 0.5 facing the camera, and behind the camera
/// the wall facing it: the albedo is half the wall's, the normal the
/// wall's (facing the reflected ray, −z), the depth the mirror's.
#[test]
fn a_wall_in_a_mirror() {
    let mirror = format!(
        "{}\n[materials.mirror]\ntype = \"mirror\"\nreflectance = 0.5\n\n[[shapes]]\ntype = \"quad\"\ncorners = [[-50.0, -50.0, 0.0], [50.0, -50.0, 0.0], [50.0, 50.0, 0.0], [-50.0, 50.0, 0.0]]\nmaterial = \"mirror\"\n",
        wall(10.0)
    );
    let g = guides(&rig(&mirror));
    for (x, y) in [(0, 0), (30, 22), (60, 44), (5, 40)] {
        assert_close(g.albedo.pixel(x, y), 0.5 * Rgb::from(WALL), 1e-6, "albedo");
        assert_eq!(g.normal.pixel(x, y), -Rgb::Z);
        let (near, far) = depth_range(x, y, 0.0);
        let depth = g.depth.pixel(x, y).x;
        assert!(depth >= near * (1.0 - 1e-5) && depth <= far * (1.0 + 1e-5));
    }
}

/// A dielectric sphere (radius 1, index 1.5) before the wall: near normal
/// incidence the Fresnel reflectance is 4 %, so the guide refracts, and
/// the centre pixel holds the wall's albedo and normal; its depth is the
/// sphere's front, 4 units away (the pixel's rays are within 0.4° of the
/// axis: 1/cos and the sphere's curvature add under 10⁻²).
#[test]
fn a_wall_through_a_dielectric_sphere() {
    let sphere = format!(
        "{}\n[materials.glass]\ntype = \"dielectric\"\nior = 1.5\n\n[[shapes]]\ntype = \"sphere\"\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"glass\"\n",
        wall(-3.0)
    );
    let g = guides(&rig(&sphere));
    let (x, y) = (W / 2, H / 2);
    assert_eq!(g.albedo.pixel(x, y), Rgb::from(WALL));
    assert_close(g.normal.pixel(x, y), Rgb::Z, 1e-6, "normal");
    let depth = g.depth.pixel(x, y).x;
    assert!((4.0..4.01).contains(&depth), "depth {depth}");
}

/// Rays that meet nothing: the background's albedo clamped to [0, 1],
/// normal 0, depth +∞ and position 0.
#[test]
fn the_sky() {
    let desc = rig(&format!("background = [0.3, 2.0, 0.0]\n{}", wall(10.0)));
    let g = guides(&desc);
    for (x, y) in [(0, 0), (30, 22)] {
        assert_eq!(g.albedo.pixel(x, y), Rgb::new(0.3, 1.0, 0.0));
        assert_eq!(g.normal.pixel(x, y), Rgb::ZERO);
        assert_eq!(g.depth.pixel(x, y), Rgb::splat(f32::INFINITY));
        assert_eq!(g.position.pixel(x, y), Rgb::ZERO);
    }
}

/// Keeping the guides and the components changes no sample of the
/// radiance (bit for bit), for every integrator on the demo.
#[test]
fn aovs_change_no_sample() {
    let desc = common::demo().expect("demo");
    for kind in IntegratorKind::ALL {
        let settings = |kept| tyndall::RenderSettings {
            width: 32,
            height: 18,
            spp: 2,
            integrator: kind,
            step: 0.25,
            threads: Some(2),
            guides: kept,
            components: kept,
            ..desc.settings
        };
        let without = tyndall::render(&desc.scene, &settings(false), &|_| {}).expect("render");
        let with = tyndall::render(&desc.scene, &settings(true), &|_| {}).expect("render");
        assert_eq!(with.image, without.image, "{kind:?}");
    }
}

/// AOV names: every one parses back, and a list with an unknown or a
/// repeated name is refused saying which.
#[test]
fn aov_names() {
    for aov in Aov::ALL {
        assert_eq!(Aov::from_name(aov.name()), Some(aov));
    }
    assert_eq!(
        Aov::parse_list("albedo, depth,volume").expect("parses"),
        vec![
            Aov::Albedo,
            Aov::Depth,
            Aov::Component(tyndall::aov::Component::Volume)
        ]
    );
    let e = Aov::parse_list("albedo,shadow").expect_err("unknown");
    assert!(e.contains("`shadow`") && e.contains("position"), "{e}");
    let e = Aov::parse_list("depth,depth").expect_err("twice");
    assert!(e.contains("twice"), "{e}");
}
