//! Depth of field: a thin-lens camera against the geometry of its cones.
//!
//! A small emissive sphere of radius ρ and radiance L sits on the axis at
//! depth z, in front of the plane of focus at F, seen through a lens of
//! radius r. The camera ray of a film point q runs from a uniformly chosen
//! lens point towards Q, the point of the plane of focus that q images, so
//! the pixel's value is L times the share of the lens from which Q sees
//! the sphere. From Q the sphere fills a cone of solid angle
//! Ω = 2π(1 − √(1 − ρ²/|QC|²)); on the lens plane, F away along the
//! axis and tilted by β against the cone, it covers Ω·F²/cos³β, so the
//! share is that over πr² while the whole silhouette lies on the lens
//! (the thin-cone error is O(ρ²/|QC|²) = 2·10⁻⁴ here). The silhouette's
//! centre is Q's offset δ mirrored by z/(F − z) = 1: the plateau holds for
//! δ + F·tan α < r, and no ray from Q meets the sphere once δ > r + F·tan α.

mod common;

use common::scene;
use glam::{DVec2, DVec3};
use tyndall::{IntegratorKind, RenderSettings};

const SIZE: u32 = 64;
const FOV_Y_DEG: f64 = 10.0;
/// The lens's radius and focus distance.
const RADIUS: f64 = 0.1;
const FOCUS: f64 = 4.0;
/// The sphere's radius, depth and radiance.
const RHO: f64 = 0.03;
const DEPTH: f64 = 2.0;
const RADIANCE: f64 = 20.0;
const SPP: u32 = 4096;

fn blurred_sphere() -> Vec<f64> {
    let desc = scene(&format!(
        r#"
        [camera]
        position = [0, 0, 0]
        look_at = [0, 0, -1]
        fov_y_deg = {FOV_Y_DEG}
        aperture_radius = {RADIUS}
        focus_distance = {FOCUS}
        [materials.glow]
        type = "emissive"
        radiance = {RADIANCE}
        [[shapes]]
        type = "sphere"
        center = [0, 0, -{DEPTH}]
        radius = {RHO}
        material = "glow"
        "#
    ));
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        spp: SPP,
        seed: 3,
        integrator: IntegratorKind::Single,
        ..desc.settings
    };
    let image = tyndall::render(&desc.scene, &settings, &|_| {}).expect("render");
    image.image.pixels().iter().map(|p| p.x as f64).collect()
}

/// The size of a pixel on the plane of focus.
fn pixel_on_focus_plane() -> f64 {
    2.0 * FOCUS * (0.5 * FOV_Y_DEG).to_radians().tan() / SIZE as f64
}

/// The offset on the plane of focus of film position `film` (pixels).
fn offset(film: DVec2) -> DVec2 {
    (film - DVec2::splat(SIZE as f64 / 2.0)) * pixel_on_focus_plane()
}

/// The share of the lens from which the focus-plane point at `delta` sees
/// the sphere, while its silhouette lies on the lens (module docs).
fn lens_share(delta: DVec2) -> f64 {
    let q = DVec3::new(delta.x, delta.y, -FOCUS);
    let to_centre = DVec3::new(0.0, 0.0, -DEPTH) - q;
    let solid_angle =
        std::f64::consts::TAU * (1.0 - (1.0 - RHO * RHO / to_centre.length_squared()).sqrt());
    let cos_tilt = to_centre.normalize().z.abs();
    solid_angle * FOCUS * FOCUS / cos_tilt.powi(3) / (std::f64::consts::PI * RADIUS * RADIUS)
}

#[test]
fn a_sphere_before_the_focus_blurs_into_its_circle_of_confusion() {
    let image = blurred_sphere();
    let pixel = pixel_on_focus_plane();
    let half_diagonal = pixel * std::f64::consts::FRAC_1_SQRT_2;
    let silhouette = FOCUS * (RHO / (FOCUS - DEPTH)).asin().tan();
    let (mut measured, mut expected, mut plateau) = (0.0, 0.0, 0usize);
    let (mut outside, mut inside) = (0usize, 0usize);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let value = image[(y * SIZE + x) as usize];
            let centre = DVec2::new(x as f64 + 0.5, y as f64 + 0.5);
            let delta = offset(centre).length();
            if delta + half_diagonal < RADIUS - silhouette {
                // The pixel's mean share by a 4×4 midpoint rule.
                let share: f64 = (0..16)
                    .map(|k| {
                        let sub = DVec2::new((k % 4) as f64 + 0.5, (k / 4) as f64 + 0.5) / 4.0;
                        lens_share(offset(DVec2::new(x as f64, y as f64) + sub))
                    })
                    .sum::<f64>()
                    / 16.0;
                measured += value;
                expected += RADIANCE * share;
                plateau += 1;
            } else if delta - half_diagonal > RADIUS + silhouette {
                assert_eq!(value, 0.0, "pixel ({x}, {y}) beyond the blur is lit");
                outside += 1;
            } else if delta + half_diagonal < 0.8 * (RADIUS + silhouette) {
                // Well inside the blur (a pinhole would image the sphere
                // over ρ/z·F = 0.06 only): some lens points see it.
                assert!(value > 0.0, "pixel ({x}, {y}) inside the blur is dark");
                inside += 1;
            }
        }
    }
    assert!(
        plateau >= 20 && outside > 3000 && inside > 300,
        "{plateau} {outside} {inside}"
    );
    // Each sample is L or 0 (a Bernoulli draw of the share p), so the
    // plateau's mean has a relative standard error of at most
    // √((1 − p)/(p·n)) over its n = pixels·spp samples (stratified lens
    // samples only lower it); 4 of them bound it.
    let p = expected / (RADIANCE * plateau as f64);
    let n = (plateau as u32 * SPP) as f64;
    let tolerance = 4.0 * ((1.0 - p) / (p * n)).sqrt();
    let error = measured / expected - 1.0;
    assert!(
        error.abs() < tolerance,
        "plateau {measured:.4} vs {expected:.4}: {error:+.4} (tolerance {tolerance:.4}, share {p:.3})"
    );
}
