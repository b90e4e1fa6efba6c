//! Transmittance to an emitter, `exp(−σt·d)` (docs/physics.md §2.3):
//! through fog, and through a medium filling an inline mesh.
mod common;

use common::{Loaded, estimate_ray, scene};
use glam::Vec3;
use tyndall::IntegratorKind;
use tyndall::color::Rgb;
use tyndall::ray::Ray;

/// The wall's radiance.
const GLOW: Rgb = Rgb::new(2.0, 3.0, 4.0);

/// A camera at the origin looking down −z at an emissive wall at z = −5,
/// through `medium` (a `[fog]` or `[[media]]` table; `integrator` the
/// scene's).
fn wall_behind(medium: &str, integrator: &str) -> Loaded {
    scene(&format!(
        r#"
        [camera]
        position = [0, 0, 0]
        look_at = [0, 0, -1]
        fov_y_deg = 30
        [render]
        integrator = "{integrator}"
        {medium}
        [materials.glow]
        type = "emissive"
        radiance = [{}, {}, {}]
        [[shapes]]
        type = "quad"
        corners = [[-10, -10, -5], [10, -10, -5], [10, 10, -5], [-10, 10, -5]]
        material = "glow"
        "#,
        GLOW.x, GLOW.y, GLOW.z
    ))
}

/// A camera looking at an emissive wall at distance 5 through
/// non-scattering fog (albedo 0): radiance `L·exp(−σt·ℓ)` where ℓ is the
/// length inside the fog. `march` and `single` apply transmittance
/// analytically, so they are exact up to float rounding.
#[test]
fn emitter_seen_through_fog() {
    for (fog_box, length) in [
        ("", 5.0f32),
        ("box = { min = [-9, -9, -3.5], max = [9, 9, -1.5] }", 2.0),
    ] {
        let desc = wall_behind(
            &format!("[fog]\nsigma_t = 0.37\nalbedo = 0.0\n{fog_box}"),
            "single",
        );
        let ray = Ray::new(Vec3::ZERO, -Vec3::Z);
        let expected = GLOW * (-0.37f32 * length).exp();
        for kind in [IntegratorKind::March, IntegratorKind::Single] {
            let (mean, _) = estimate_ray(&desc, kind, 0.1, ray, 4);
            assert!(
                (mean - expected).abs().max_element() < 1e-5 * 4.0,
                "{kind:?} {fog_box}: {mean} vs {expected}"
            );
        }
        // `volpath` samples free flights: a path reaches the wall with
        // probability exp(−σt·ℓ); within 5 standard errors.
        let (mean, stderr) = estimate_ray(&desc, IntegratorKind::Volpath, 0.1, ray, 4096);
        assert!(
            (mean - expected).abs().cmple(5.0 * stderr + 1e-5).all(),
            "volpath {fog_box}: {mean} ± {stderr} vs {expected}"
        );
    }
}

/// A medium whose region is a cube written into the scene (`mesh = {
/// positions, indices }`, as the Blender add-on gives a mesh filled by a
/// volume material): non-scattering fog before an emissive wall, seen
/// along rays whose chords through the cube the test finds by slabs. The
/// radiance is `L·exp(−σt·ℓ)`; `volpath` samples free flights, so within
/// 5 standard errors.
#[test]
fn a_medium_fills_an_inline_mesh() {
    let (lo, hi) = (Vec3::new(-1.0, -1.0, -3.5), Vec3::new(1.0, 1.0, -1.5));
    let corner = |i: usize| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    let positions: Vec<String> = (0..8)
        .map(|i| {
            let c = corner(i);
            format!("{}, {}, {}", c.x, c.y, c.z)
        })
        .collect();
    // Two triangles per face of the cube (vertex i has bit 0 for x, 1
    // for y, 2 for z).
    let indices =
        "0,1,3, 0,3,2, 4,6,7, 4,7,5, 0,4,5, 0,5,1, 2,3,7, 2,7,6, 0,2,6, 0,6,4, 1,5,7, 1,7,3";
    let mesh = format!(
        "[[media]]\nsigma_t = 0.6\nalbedo = 0.0\nmesh = {{ positions = [{}], indices = [{indices}] }}",
        positions.join(", ")
    );
    let desc = wall_behind(&mesh, "volpath");
    for direction in [Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.3, 0.1, -1.0)] {
        let ray = Ray::new(Vec3::ZERO, direction);
        // The chord by slabs: the overlap of the three axes' intervals.
        let d = ray.direction;
        let (t0, t1) = (lo / d, hi / d);
        let enter = t0.min(t1).max_element();
        let exit = t0.max(t1).min_element();
        let chord = (exit - enter).max(0.0);
        assert!(chord > 1.5, "{chord}");
        let expected = GLOW * (-0.6 * chord).exp();
        let (mean, stderr) = estimate_ray(&desc, IntegratorKind::Volpath, 0.1, ray, 4096);
        assert!(
            (mean - expected).abs().cmple(5.0 * stderr + 1e-5).all(),
            "{direction}: {mean} ± {stderr} vs {expected} (chord {chord})"
        );
    }
}
