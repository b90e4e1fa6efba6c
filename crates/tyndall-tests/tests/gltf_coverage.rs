//! glTF alpha coverage (`alphaMode`, glTF 2.0 §3.9.4): `MASK` cut-outs
//! and `BLEND` partial coverage, each against the closed form of a
//! sunlit floor under leaves, for camera and shadow rays alike.

mod common;
mod gltf_files;

use common::{mean_and_stderr, render};
use glam::Vec3;
use gltf_files::{camera_looking_down, square, sunlit, test_dir, write_gltf};
use serde_json::json;
use std::f32::consts::PI;
use tyndall::IntegratorKind;
use tyndall::color::Rgb;
use tyndall::ray::Ray;

/// Alpha cut-outs (glTF `alphaMode` `MASK`): a leaf quad at height 1,
/// its base colour texture a 2×2 checker of alpha 1 and 0 (clamped, so
/// coverage ≥ ½ exactly on the quadrants of its opaque texels), over a
/// floor, under a sun straight down (E = 1 W/m²). Every ray passes the
/// holes and stops at the rest, so with direct light only (`single`, and
/// `volpath` of one scattering event) the radiance up from each point is
/// a closed form:
/// - seen from above, an opaque quadrant is the lit leaf (`0.5/π`), a hole
///   the lit floor beneath it (`0.8/π`): camera rays and shadow rays pass
///   holes;
/// - seen from between leaf and floor, the floor is dark under an opaque
///   quadrant and lit under a hole: shadow rays stop at the rest.
///
/// A `MASK` material below its cutoff without a texture (a pane over
/// everything) is left out; shadow maps, which cannot see holes, are
/// refused.
#[test]
fn alpha_cutouts_are_holes_for_every_ray() {
    let dir = test_dir("cutout");
    let checker = image::RgbaImage::from_fn(2, 2, |x, y| {
        image::Rgba([255, 255, 255, if x == y { 255 } else { 0 }])
    });
    checker.save(dir.join("leaf.png")).expect("png");
    let no_specular = json!({"KHR_materials_specular": {"specularFactor": 0.0}});
    let doc = |leaf_mode: &str| {
        sunlit(
            3,
            json!({
                "images": [{"uri": "leaf.png"}],
                "samplers": [{"wrapS": 33071, "wrapT": 33071}],
                "textures": [{"source": 0, "sampler": 0}],
                "materials": [
                    {"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1.0],
                                              "baseColorTexture": {"index": 0}, "metallicFactor": 0.0},
                     "alphaMode": leaf_mode, "extensions": no_specular},
                    {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0},
                     "extensions": no_specular},
                    {"pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.3, 0.3, 0.3], "metallicFactor": 0.0},
                     "alphaMode": "MASK", "extensions": no_specular}
                ]
            }),
        )
    };
    // The leaf's coordinates spread the image over it: u along x, v along z.
    let meshes = [
        square(
            1.0,
            1.0,
            0,
            Some(|p| [(p[0] + 1.0) / 2.0, (p[2] + 1.0) / 2.0]),
        ),
        square(0.0, 2.0, 1, None),
        square(1.5, 3.0, 2, None),
    ];
    let desc = common::load_gltf(&write_gltf(&dir, "leaf", &meshes, doc("MASK"))).expect("loads");
    assert!(desc.scene.has_coverage());
    let (leaf, floor, dark) = (0.5 / PI, 0.8 / PI, 0.0);
    // (x, z, from height, expected): quadrant (−, −) and (+, +) opaque.
    let cases = [
        (-0.5, -0.5, 2.0, leaf),
        (0.5, 0.5, 2.0, leaf),
        (0.5, -0.5, 2.0, floor),
        (-0.5, 0.5, 2.0, floor),
        (1.5, 0.3, 2.0, floor),
        (-0.3, -0.7, 0.5, dark),
        (0.7, 0.2, 0.5, dark),
        (0.3, -0.7, 0.5, floor),
        (-0.7, 0.2, 0.5, floor),
    ];
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        let settings = tyndall::RenderSettings {
            integrator: kind,
            max_depth: 1,
            ..desc.settings
        };
        for (x, z, y, expected) in cases {
            let ray = Ray::new(Vec3::new(x, y, z), Vec3::new(0.0, -1.0, 0.0));
            let (got, _) = common::estimate_ray_with(&desc, settings, ray, 8);
            assert!(
                (got - Rgb::splat(expected)).abs().max_element() < 1e-5,
                "{kind:?} from ({x}, {y}, {z}): {got} vs {expected}"
            );
        }
    }
    // The guides see through the holes too.
    let guide = tyndall::guides::first_surface(
        &desc.scene,
        Ray::new(Vec3::new(0.5, 2.0, -0.5), Vec3::new(0.0, -1.0, 0.0)),
        None,
    );
    assert!((guide.albedo - Rgb::splat(0.8)).abs().max_element() < 1e-6);

    shadow_maps_are_refused(&desc);
}

/// `BLEND` is partial coverage: a ray meets the surface with probability
/// its coverage `a` (`baseColorFactor` alpha, here without a texture) and
/// passes it otherwise. Two broad leaves over a floor, under a sun
/// straight down (E = 1 W/m²), seen from above by a narrow camera whose
/// every ray crosses both: the upper leaf (coverage a₂, reflectance ρ₂)
/// is met by a₂ of the rays and lit whole; the lower (a₁, ρ₁) by
/// (1 − a₂)·a₁ of them and lit by the sun through the upper, (1 − a₂); the
/// floor (ρ_f) by (1 − a₂)(1 − a₁) and lit through both. With direct light
/// only (`single`, `volpath` of one event) every pixel's expectation is
///
/// `L = [a₂ρ₂ + (1 − a₂)²a₁ρ₁ + (1 − a₂)²(1 − a₁)²ρ_f]/π`,
///
/// which needs the leaves chosen independently along a ray (one number
/// for both would give other powers) and shadow rays that pass a leaf as
/// camera rays do. The image mean must be within 4 standard errors of it
/// (from the pixels' scatter, all of one expectation). Planted, each
/// fault failed it, by 11 standard errors or more: shadow rays blocked by
/// the leaves (70), one number for both leaves along a ray (11), camera
/// rays that ignore the coverage (the upper leaf everywhere). A BLEND
/// surface of coverage 0 is left out, and shadow maps are refused.
#[test]
fn blend_covers_a_fraction_of_every_ray() {
    let dir = test_dir("blend");
    let no_specular = json!({"KHR_materials_specular": {"specularFactor": 0.0}});
    let (a1, rho1, a2, rho2, rho_f) = (0.5f32, 0.6f32, 0.3f32, 0.9f32, 0.8f32);
    let leaf = |a: f32, rho: f32| {
        json!({"pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, a], "metallicFactor": 0.0},
               "alphaMode": "BLEND", "extensions": no_specular})
    };
    let mut doc = sunlit(
        4,
        json!({
            "materials": [
                leaf(a1, rho1),
                leaf(a2, rho2),
                {"pbrMetallicRoughness": {"baseColorFactor": [rho_f, rho_f, rho_f, 1.0], "metallicFactor": 0.0},
                 "extensions": no_specular},
                leaf(0.0, 0.5)
            ],
        }),
    );
    camera_looking_down(&mut doc, 4.0, 0.3);
    let meshes = [
        square(1.0, 3.0, 0, None),
        square(2.0, 3.0, 1, None),
        square(0.0, 6.0, 2, None),
        // Coverage 0 everywhere: left out (it would cover the camera).
        square(3.0, 3.0, 3, None),
    ];
    let desc = common::load_gltf(&write_gltf(&dir, "leaves", &meshes, doc)).expect("loads");
    assert!(desc.scene.has_coverage());
    assert_eq!(
        desc.scene.geometry().primitives().len(),
        6,
        "the leaf of coverage 0 is left out"
    );
    let (t1, t2) = (1.0 - a1, 1.0 - a2);
    let expected = f64::from((a2 * rho2 + t2 * t2 * a1 * rho1 + t2 * t2 * t1 * t1 * rho_f) / PI);
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        let image = render(&desc, |s| {
            s.integrator = kind;
            s.max_depth = 1;
            s.width = 32;
            s.height = 32;
            s.spp = 16;
        });
        let values: Vec<f64> = image.pixels().iter().map(|p| f64::from(p.y)).collect();
        let (mean, stderr) = mean_and_stderr(&values);
        assert!(
            (mean - expected).abs() < 4.0 * stderr,
            "{kind:?}: mean {mean:.5} ± {stderr:.1e}, expected {expected:.5}"
        );
        // Power: the one-number fault moves the mean by 0.011.
        assert!(stderr < 1.5e-3, "the test has no power: {stderr:.1e}");
    }
    shadow_maps_are_refused(&desc);
}

/// Shadow maps, which do not see coverage, are refused for `desc`.
fn shadow_maps_are_refused(desc: &common::Loaded) {
    let maps = tyndall::RenderSettings {
        visibility: tyndall::settings::VisibilityMode::Maps { resolution: 64 },
        ..desc.settings
    };
    assert_eq!(
        maps.validate(&desc.scene),
        Err(tyndall::render::RenderError::CoverageNeedsShadowRays)
    );
}
