//! The paper's legacy .obj format (docs/scene-format.md, "The paper's legacy format").
mod common;

use common::repo;
use glam::Vec3;
use tyndall::camera::FieldOfView;
use tyndall::glass::GlassModel;
use tyndall::lights::{Light, SpotProfile};
use tyndall::materials::Material;
use tyndall::shapes::Shape;
use tyndall_load::LegacyOptions;
use tyndall_load::SourceText;

/// The short example of the course's description of the format, verbatim
/// (the format is documented in docs/scene-format.md).
const EXAMPLE: &str = "material
diffuse 0 0 0
reflective 0 0 0
emitted 64 64 64

material
diffuse 0.7 0.7 0.7
reflective 0 0 0
emitted 0 0 0

m 0
v -7 10 7
v -7 10 3
v -3 10 3
v -3 10 7
f 1 2 3 4

m 1
v -10 -1 -10
v -10 -1 10
v 10 -1 10
v 10 -1 -10
f 5 6 7 8
s 0.3 0 -1 1

background_color 0 0 0

PerspectiveCamera {
  camera_position    < 5.3, 2.0, 5.9 >
  point_of_interest  < 1.3, 0.4, 0.96 >
  up                 < 0, 1, 0 >
  angle              20
}
";

fn parse(text: &str) -> Result<common::Loaded, tyndall_load::SceneError> {
    common::parse_legacy(&SourceText::new("test.obj", text), LegacyOptions::default())
}

#[test]
fn example_parses_into_expected_scene() {
    let desc = parse(EXAMPLE).expect("example parses");
    let scene = &desc.scene;
    // A ceiling area light of radiance 64, facing down into the room.
    assert_eq!(scene.lights().len(), 1);
    let Light::Quad(light) = scene.lights()[0] else {
        panic!("expected a quad light, got {:?}", scene.lights()[0])
    };
    assert_eq!(light.radiance, Vec3::splat(64.0));
    assert!((light.quad.normal - Vec3::NEG_Y).length() < 1e-6);
    assert!((light.quad.area() - 16.0).abs() < 1e-5);
    assert!(!light.two_sided);
    // Light quad, floor quad (normal up, one-sided) and the sphere.
    let prims = scene.geometry().primitives();
    assert_eq!(prims.len(), 3);
    let quads: Vec<_> = prims
        .iter()
        .filter_map(|p| {
            if let Shape::Quad(q) = p.shape {
                Some(q)
            } else {
                None
            }
        })
        .collect();
    assert_eq!(quads.len(), 2);
    assert!(quads.iter().all(|q| q.one_sided));
    assert!(
        quads
            .iter()
            .any(|q| (q.normal - Vec3::Y).length() < 1e-6 && q.origin.y == -1.0)
    );
    let sphere = prims
        .iter()
        .find_map(|p| {
            if let Shape::Sphere(s) = p.shape {
                Some((s, p.material))
            } else {
                None
            }
        })
        .expect("sphere");
    assert_eq!(sphere.0.center, Vec3::new(0.3, 0.0, -1.0));
    assert_eq!(sphere.0.radius, 1.0);
    let Material::Opaque(surface) = scene.materials()[sphere.1 as usize] else {
        panic!("sphere material")
    };
    assert_eq!(surface.diffuse, Vec3::splat(0.7));
    assert_eq!(scene.camera().position, Vec3::new(5.3, 2.0, 5.9));
    assert_eq!(scene.camera().look_at, Vec3::new(1.3, 0.4, 0.96));
    assert_eq!(scene.camera().fov, FieldOfView::ShorterSide(20.0));
    assert_eq!(scene.background(), Vec3::ZERO);
    assert_eq!(scene.glass().model, GlassModel::Blend);
    assert!(scene.fog().is_none());
}

#[test]
fn two_sided_flag() {
    let desc = common::parse_legacy(
        &SourceText::new("t.obj", EXAMPLE),
        LegacyOptions { two_sided: true },
    )
    .expect("parses");
    assert!(
        desc.scene
            .geometry()
            .primitives()
            .iter()
            .all(|p| !matches!(p.shape, Shape::Quad(q) if q.one_sided))
    );
}

/// The paper's tokens: `c` inside a material block and as a statement
/// before faces; `alpha` makes glass.
#[test]
fn paper_tokens() {
    let spot_in_material = EXAMPLE.replace("emitted 64 64 64", "emitted 64 64 64\nc 30");
    let desc = parse(&spot_in_material).expect("parses");
    let Light::Spot(spot) = &desc.scene.lights()[0] else {
        panic!("expected a spot")
    };
    assert_eq!(spot.profile, SpotProfile::Linear);
    assert!((spot.cos_cutoff - 30f32.to_radians().cos()).abs() < 1e-6);
    assert_eq!(spot.position, Vec3::new(-5.0, 10.0, 5.0));
    assert!((spot.direction - Vec3::NEG_Y).length() < 1e-6);
    assert_eq!(spot.intensity, Vec3::splat(64.0 * 16.0));

    let spot_statement = EXAMPLE.replace("m 0\n", "m 0\nc 45\n");
    let desc = parse(&spot_statement).expect("parses");
    let Light::Spot(spot) = &desc.scene.lights()[0] else {
        panic!("expected a spot")
    };
    assert!((spot.cos_cutoff - 45f32.to_radians().cos()).abs() < 1e-6);

    let glass = EXAMPLE.replace("diffuse 0.7 0.7 0.7", "diffuse 0.9 0.1 0.1\nalpha 0.4");
    let desc = parse(&glass).expect("parses");
    assert!(desc.scene.materials().iter().any(
        |m| matches!(m, Material::Glass(g) if g.alpha == 0.4 && g.color == Vec3::new(0.9, 0.1, 0.1))
    ));
}

/// Public course scenes nobody here wrote.
#[test]
fn course_scenes_load() {
    let dir = repo().join("scenes/legacy");
    let cornell = common::load_legacy(&dir.join("cornell_box.obj"), LegacyOptions::default())
        .expect("cornell");
    assert_eq!(cornell.scene.lights().len(), 1);
    assert_eq!(cornell.scene.geometry().primitives().len(), 6);
    let spheres = common::load_legacy(
        &dir.join("reflective_spheres.obj"),
        LegacyOptions::default(),
    )
    .expect("spheres");
    assert!(
        spheres
            .scene
            .materials()
            .iter()
            .any(|m| matches!(m, Material::Opaque(s) if s.roughness == 0.06))
    );
    let fig7 = common::load_legacy(&dir.join("fig07-spot-sphere.obj"), LegacyOptions::default())
        .expect("fig7");
    assert!(matches!(fig7.scene.lights()[0], Light::Spot(_)));
}

/// The camera at z = 5 sees into the Cornell box through the back of its
/// emissive front wall (quads are one-sided): the centre pixel shows the
/// lit back wall, not the emitter's radiance 1.27.
#[test]
fn one_sided_emitter_is_seen_through_from_behind() {
    let dir = repo().join("scenes/legacy");
    let desc = common::load_legacy(&dir.join("cornell_box.obj"), LegacyOptions::default())
        .expect("cornell");
    let image = common::render(&desc, |s| {
        s.width = 9;
        s.height = 9;
        s.spp = 16;
    });
    let centre = image.pixel(4, 4);
    assert!(
        centre.max_element() > 0.01 && centre.max_element() < 1.0,
        "{centre}"
    );
}
