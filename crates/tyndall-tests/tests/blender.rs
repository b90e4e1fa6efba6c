//! A scene exported by Blender's own glTF exporter (bpy 4.5.15,
//! scenes/blender/make_fog_room.py, default "Standard" lighting mode)
//! loads with the values set in Blender: light powers in W become W/sr by
//! P/(4π), the sun's W/m² is kept, spot blend 0 is a hard spot, a
//! Principled surface with IOR level 0 is pure Lambert, the emission
//! panel is an area light.

mod common;

use glam::Vec3;
use std::f32::consts::PI;
use std::path::Path;
use tyndall::camera::FieldOfView;
use tyndall::color::Rgb;
use tyndall::lights::{Light, SpotProfile};
use tyndall::materials::{Material, Surface};

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
    // The floor: Principled base 0.8, Specular IOR Level 0.
    assert_eq!(
        *scene.material(0),
        Material::Opaque(Surface::diffuse(Rgb::splat(0.8)))
    );
}
