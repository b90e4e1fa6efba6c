//! Fog transmittance to an emitter: `exp(−σt·d)` (docs/physics.md §2.3).
mod common;

use common::{estimate_ray, scene};
use tyndall::IntegratorKind;
use tyndall::ray::Ray;

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
        let desc = scene(&format!(
            r#"
            [camera]
            position = [0, 0, 0]
            look_at = [0, 0, -1]
            fov_y_deg = 30
            [fog]
            sigma_t = 0.37
            albedo = 0.0
            {fog_box}
            [materials.glow]
            type = "emissive"
            radiance = [2.0, 3.0, 4.0]
            [[shapes]]
            type = "quad"
            corners = [[-10, -10, -5], [10, -10, -5], [10, 10, -5], [-10, 10, -5]]
            material = "glow"
            "#
        ));
        let ray = Ray::new(glam::Vec3::ZERO, -glam::Vec3::Z);
        let expected = tyndall::Rgb::new(2.0, 3.0, 4.0) * (-0.37f32 * length).exp();
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
