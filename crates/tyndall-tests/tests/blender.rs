//! A scene exported by Blender's own glTF exporter (bpy 4.5.15,
//! scenes/blender/make_fog_room.py, default "Standard" lighting mode)
//! loads with the values set in Blender: light powers in W become W/sr by
//! P/(4π), the sun's W/m² is kept, spot blend 0 is a hard spot, a
//! Principled surface with IOR level 0 is pure Lambert, the emission
//! panel is an area light.

mod common;

use common::{average, mean_and_stderr, pool_inflation, render, repo};
use glam::Vec3;
use std::f32::consts::PI;
use std::path::Path;
use tyndall::IntegratorKind;
use tyndall::camera::FieldOfView;
use tyndall::color::Rgb;
use tyndall::lights::{Light, SpotProfile};
use tyndall::materials::{Material, Surface};
use tyndall_image::metrics::relative_mse;

#[test]
fn blender_export_loads_with_blender_values() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/blender/fog-room.gltf");
    let desc = common::load_gltf(&path).expect("loads");
    let scene = &desc.scene;
    let rel = |a: f32, b: f32| ((a - b) / b).abs() < 1e-5;
    // Values set in make_fog_room.py.
    // The emissive panel (a 0.5 m plane, emission colour (1, 0.9, 0.7) at
    // strength 4) is an area light, numbered first (emissive shapes come
    // before the other lights).
    let Light::Mesh(panel) = &scene.lights()[0] else {
        panic!("{:?}", scene.lights()[0])
    };
    assert_eq!(panel.triangles().len(), 2);
    assert!(rel(panel.area(), 0.25), "{}", panel.area());
    assert!(
        (panel.radiance - Rgb::new(4.0, 3.6, 2.8))
            .abs()
            .max_element()
            < 1e-5,
        "{}",
        panel.radiance
    );
    let Light::Spot(hard) = &scene.lights()[1] else {
        panic!("{:?}", scene.lights()[1])
    };
    assert!(
        rel(hard.intensity.x, 400.0 / (4.0 * PI)),
        "{}",
        hard.intensity
    );
    assert_eq!(hard.profile, SpotProfile::Hard, "spot blend 0");
    assert!((hard.cos_cutoff - 20f32.to_radians().cos()).abs() < 1e-6);
    assert!((hard.position - Vec3::new(0.0, 4.0, 0.0)).length() < 1e-5);
    assert!(
        (hard.direction - Vec3::NEG_Y).length() < 1e-5,
        "Blender's spot points down −Z (up is +Y in glTF)"
    );
    let Light::Spot(soft) = &scene.lights()[2] else {
        panic!("{:?}", scene.lights()[2])
    };
    assert!(rel(soft.intensity.x, 60.0 / (4.0 * PI)));
    // Blender: inner = (size/2)·(1 − blend) = 25°·0.5; Cycles' smoothstep
    // reaches full intensity at cos 25° + (1 − cos 25°)·blend.
    let SpotProfile::Smooth { cos_inner } = soft.profile else {
        panic!("{:?}", soft.profile)
    };
    let cos_outer = 25f32.to_radians().cos();
    assert!((cos_inner - (cos_outer + (1.0 - cos_outer) * 0.5)).abs() < 1e-6);
    let Light::Point(bulb) = &scene.lights()[3] else {
        panic!("{:?}", scene.lights()[3])
    };
    assert!(rel(bulb.intensity.x, 30.0 / (4.0 * PI)));
    let Light::Directional(sun) = scene.lights()[4] else {
        panic!("{:?}", scene.lights()[4])
    };
    assert!(rel(sun.irradiance.x, 2.0));
    let FieldOfView::Vertical(fov) = scene.camera().fov else {
        panic!()
    };
    assert!((fov - 45.0).abs() < 1e-3);
    assert_eq!(desc.settings.width * 3, desc.settings.height * 4);
    // Lit as Blender lights it: with interreflection.
    assert_eq!(desc.settings.integrator, IntegratorKind::Volpath);
    // The floor: Principled base 0.8, Specular IOR Level 0.
    assert_eq!(
        *scene.material(0),
        Material::Opaque(Surface::diffuse(Rgb::splat(0.8)))
    );
}

/// Khronos sample assets as a Blender user lights and renders them
/// (scenes/gltf-samples/box_floor.py: the asset imported by Blender's
/// glTF importer over a grey floor, one hard spot tilted 30° and turned
/// 50°, exported by Blender's exporter) render like Cycles' F12 of the
/// same Blender scene (default 12 bounces; its two halves of 1024 spp
/// committed) when Tyndall is given nothing but the file, as the issue's
/// check asks of each asset. The assets: BoxTextured, and BoxTextured
/// glowing with its own texture (`make_glowing_box.py`: the texture as
/// its `emissiveTexture` too, so the box emits point by point over what
/// it reflects, and lights the floor by its texture).
/// - the image mean within 2 % of Cycles', plus 4 standard errors of the
///   difference (Tyndall's from its two renders' pixel differences,
///   Cycles' from its halves'). The 2 % is the models' difference: on the
///   box, Principled's rough dielectric layer takes an angle-dependent
///   share of the diffuse light where Tyndall takes `1 − F0`; without the
///   asset, the floor alone agrees to relMSE 2·10⁻⁶ (docs/benchmarks.md,
///   "A glTF asset beside Cycles");
/// - relMSE within both renders' noise (a quarter of each pair's relMSE
///   between halves, for the means of two) plus 10⁻².
///
/// This was the "tilted spot 7 % dark" of issue 22: a glTF file rendered
/// with the default `single` (surfaces lit directly only) is 8 % darker
/// than Cycles here and fails the first check; the spot's tilt had no part
/// in it (relMSE ≤ 4·10⁻⁶ from 15° to 60° with direct light only in both).
/// An emitter that did not reflect, or ignored its texture, fails the
/// glowing box's.
#[test]
fn a_blender_scene_renders_like_cycles_f12() {
    let dir = repo().join("scenes/gltf-samples");
    for name in ["box-floor", "glowing-box-floor"] {
        renders_like_cycles(name, &dir.join(format!("{name}.glb")), |i| {
            dir.join(format!("{name}-cycles-half{i}.exr"))
        });
    }
}

/// Khronos sample assets as a Blender user lights them
/// (`scenes/gltf-samples/assets_vs_cycles.py`: each imported by Blender's
/// glTF importer, its textures at most 256 texels a side, scaled to a
/// metre over a grey floor, lit by a tilted hard spot and a point light,
/// exported by Blender's exporter) render like Cycles' F12 of the same
/// Blender scene (12 bounces, two halves of 512 spp committed), by the
/// checks of [`a_blender_scene_renders_like_cycles_f12`]. Each asset
/// exercises what the issue names: `alphaMode` `BLEND` and `MASK`
/// (AlphaBlendModeTest), normal maps in MikkTSpace frames on mirrored
/// UVs (NormalTangentMirrorTest), `KHR_texture_transform`
/// (TextureTransformTest), `COLOR_0` (VertexColorTest),
/// `KHR_materials_emissive_strength` (EmissiveStrengthTest), samplers'
/// wrap modes and filters (TextureSettingsTest), `KHR_materials_clearcoat`
/// over glossy GGX layers lit by delta lights (ClearCoatTest). Assets
/// that do not agree yet are in docs/benchmarks.md, "Khronos assets
/// beside Cycles".
#[test]
fn khronos_assets_render_like_cycles_f12() {
    let dir = repo().join("scenes/gltf-samples");
    for name in [
        "AlphaBlendModeTest",
        "NormalTangentMirrorTest",
        "TextureTransformTest",
        "VertexColorTest",
        "EmissiveStrengthTest",
        "TextureSettingsTest",
        "ClearCoatTest",
    ] {
        let asset = dir.join(name);
        renders_like_cycles(name, &asset.join("scene.glb"), |i| {
            asset.join(format!("cycles-half{i}.exr"))
        });
    }
}

/// The check of [`a_blender_scene_renders_like_cycles_f12`] on the glTF
/// file `file` against Cycles' halves `half(0)` and `half(1)`.
fn renders_like_cycles(name: &str, file: &Path, half: impl Fn(u32) -> std::path::PathBuf) {
    let desc = common::load_gltf(file).expect("loads");
    let half = |i: u32| tyndall_image::read_exr(&half(i)).expect("Cycles' half");
    let (h0, h1) = (half(0), half(1));
    let cycles = average(&[&h0, &h1]);
    let settings = |seed: u64| {
        let mut s = desc.settings;
        s.width = cycles.width();
        s.height = cycles.height();
        s.spp = 32;
        s.seed = seed;
        s
    };
    let (c1, c2) = (
        render(&desc, |s| *s = settings(1)),
        render(&desc, |s| *s = settings(2)),
    );
    let tyndall = average(&[&c1, &c2]);
    let grey = |p: &Rgb| (p.x + p.y + p.z) as f64 / 3.0;
    let mean =
        |im: &tyndall::Image| im.pixels().iter().map(grey).sum::<f64>() / im.pixels().len() as f64;
    // The standard error of a mean of two renders (or halves) is half
    // that of their difference's mean.
    let stderr_of_mean = |a: &tyndall::Image, b: &tyndall::Image| {
        let diffs: Vec<f64> = a
            .pixels()
            .iter()
            .zip(b.pixels())
            .map(|(p, q)| grey(p) - grey(q))
            .collect();
        mean_and_stderr(&diffs).1 / 2.0
    };
    let inflation = pool_inflation(&desc, &settings(1), c1.pixels().len());
    let se = (inflation * stderr_of_mean(&c1, &c2)).hypot(stderr_of_mean(&h0, &h1));
    let (m, m_ref) = (mean(&tyndall), mean(&cycles));
    let bound = 0.02 * m_ref + 4.0 * se;
    assert!(
        (m - m_ref).abs() <= bound,
        "{name}: mean {m:.5} vs Cycles {m_ref:.5} ({:+.2} %), bound {bound:.2e}",
        100.0 * (m / m_ref - 1.0)
    );
    let noise = relative_mse(&c1, &c2) / 4.0 + relative_mse(&h0, &h1) / 4.0;
    let error = relative_mse(&tyndall, &cycles);
    eprintln!(
        "{name}: mean {:+.2} % from Cycles' (bound {:.2} %), relMSE {error:.3e} (noise {noise:.3e})",
        100.0 * (m / m_ref - 1.0),
        100.0 * bound / m_ref
    );
    assert!(
        error <= noise + 1e-2,
        "{name}: relMSE {error:.3e} against Cycles, noise {noise:.3e}"
    );
}
