//! glTF input: a file written here loads into the expected scene
//! description, renders as the same scene written in TOML does, and bad
//! files give errors naming the file and the element.
mod common;
mod gltf_files;

use glam::Vec3;
use gltf_files::{MeshData, test_dir, to_glb, write_gltf};
use serde_json::json;
use std::f32::consts::FRAC_1_SQRT_2;
use tyndall::Scene;
use tyndall::camera::FieldOfView;
use tyndall::color::Rgb;
use tyndall::lights::{Light, SpotProfile};
use tyndall::materials::{Material, Surface};
use tyndall::shapes::Shape;

fn triangle(material: usize) -> MeshData {
    MeshData {
        positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        indices: Some(vec![0, 1, 2]),
        mode: None,
        material: Some(material),
        normals: None,
        uvs: None,
        colors: None,
        tangents: None,
    }
}

fn corners(scene: &Scene, primitive: u32) -> [Vec3; 3] {
    match scene.geometry().primitive(primitive).shape {
        Shape::Triangle(t) => [t.v0, t.v0 + t.e1, t.v0 + t.e2],
        ref other => panic!("primitive {primitive} is not a triangle: {other:?}"),
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

/// Node transforms compose parent·child (glTF §3.5.2), lights take their
/// node's position and −z, photometric units become radiometric by
/// 683 lm/W, cone angles map to the spot profiles, materials map to the
/// closed set. Expected values are worked out by hand in the comments.
#[test]
fn gltf_loads_into_the_expected_description() {
    let s = FRAC_1_SQRT_2;
    let doc = json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular",
            "KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior",
            "KHR_materials_emissive_strength", "EXT_made_up"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "spot", "intensity": 2049.0, "color": [1.0, 0.5, 0.25],
             "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
            {"type": "directional", "intensity": 1366.0},
            {"type": "point", "intensity": 1366.0, "range": 10.0},
            {"type": "spot", "intensity": 683.0, "spot": {"innerConeAngle": 0.4, "outerConeAngle": 0.4}}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 2, 3, 4, 5, 6, 7, 8, 9, 10]}],
        "nodes": [
            // Parent: translate (1,0,0) · rotate 90° about +y · scale 2.
            {"translation": [1.0, 0.0, 0.0], "rotation": [0.0, s, 0.0, s],
             "scale": [2.0, 2.0, 2.0], "children": [1]},
            // Child: translate (0,0,−1); carries the triangle and spot 0.
            {"translation": [0.0, 0.0, -1.0], "mesh": 0,
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            // −90° about +x turns −z into −y.
            {"rotation": [-s, 0.0, 0.0, s], "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"matrix": [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 5.0, 0.0, 1.0],
             "extensions": {"KHR_lights_punctual": {"light": 2}}},
            {"extensions": {"KHR_lights_punctual": {"light": 3}}},
            {"translation": [0.0, 1.0, 10.0], "camera": 0},
            {"mesh": 1}, {"mesh": 2}, {"mesh": 3}, {"mesh": 4}, {"mesh": 5}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "aspectRatio": 2.0, "znear": 0.1}}],
        "materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.6, 0.7, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.5},
             "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.2, 0.1, 1.0], "metallicFactor": 0.0},
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}},
            {"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                            "KHR_materials_volume": {"thicknessFactor": 0.1,
                                "attenuationColor": [0.5, 0.25, 1.0], "attenuationDistance": 2.0},
                            "KHR_materials_ior": {"ior": 1.33}}},
            {"emissiveFactor": [1.0, 0.5, 0.0],
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.3}},
            {"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 1.0}}
        ]
    });
    let meshes: Vec<MeshData> = (0..6).map(triangle).collect();
    let path = write_gltf(&test_dir("describe"), "describe", &meshes, doc);
    let desc = common::load_gltf(&path).expect("loads");
    let scene = &desc.scene;

    // World(v) = (1,0,0) + R_y(90°)·2·(v + (0,0,−1)), R_y(90°)(x,y,z) = (z, y, −x):
    // (0,0,0) → (−1,0,0); (1,0,0) → (−1,0,−2); (0,1,0) → (−1,2,0).
    let [a, b, c] = corners(scene, 0);
    assert!(close(a, Vec3::new(-1.0, 0.0, 0.0)), "{a}");
    assert!(close(b, Vec3::new(-1.0, 0.0, -2.0)), "{b}");
    assert!(close(c, Vec3::new(-1.0, 2.0, 0.0)), "{c}");

    // The emissive mesh (mesh 3) is an area light, numbered first; then
    // the punctual lights in node order.
    assert_eq!(scene.lights().len(), 5);
    let Light::Mesh(lamp) = &scene.lights()[0] else {
        panic!("{:?}", scene.lights()[0])
    };
    assert_eq!(lamp.radiance, Rgb::new(4.0, 2.0, 0.0));
    assert_eq!(lamp.triangles().len(), 1);
    // Spot 0 at the child's origin, pointing along R_y(90°)(0,0,−1) = (−1,0,0);
    // 2049 cd / 683 = 3 W/sr times its colour; smooth from 0.2 to 0.5 rad.
    let Light::Spot(spot) = &scene.lights()[1] else {
        panic!("{:?}", scene.lights()[1])
    };
    assert!(close(spot.position, Vec3::new(-1.0, 0.0, 0.0)));
    assert!(close(spot.direction, Vec3::new(-1.0, 0.0, 0.0)));
    assert!((spot.cos_cutoff - 0.5f32.cos()).abs() < 1e-6);
    // Blender's blend 1 − 0.2/0.5 = 0.6: full intensity from
    // cos 0.5 + (1 − cos 0.5)·0.6, as Cycles renders the imported spot.
    let SpotProfile::Smooth { cos_inner } = spot.profile else {
        panic!("{:?}", spot.profile)
    };
    assert!((cos_inner - (0.5f32.cos() + (1.0 - 0.5f32.cos()) * 0.6)).abs() < 1e-6);
    assert!(close(spot.intensity, Vec3::new(3.0, 1.5, 0.75)));
    // Sun: 1366 lx / 683 = 2 W/m², travelling down.
    let Light::Directional(sun) = scene.lights()[2] else {
        panic!("{:?}", scene.lights()[2])
    };
    assert!(close(sun.direction, Vec3::NEG_Y), "{}", sun.direction);
    assert!(close(sun.irradiance, Vec3::splat(2.0)));
    // Point light placed by a matrix: 1366 cd → 2 W/sr; its range is warned about.
    let Light::Point(point) = &scene.lights()[3] else {
        panic!("{:?}", scene.lights()[3])
    };
    assert!(close(point.position, Vec3::new(0.0, 5.0, 0.0)));
    assert!(close(point.intensity, Vec3::splat(2.0)));
    assert!(desc.warnings.iter().any(|w| w.contains("range")));
    // Blender's blend 0 writes inner == outer: a hard spot, not an error.
    let Light::Spot(hard) = &scene.lights()[4] else {
        panic!("{:?}", scene.lights()[4])
    };
    assert_eq!(hard.profile, SpotProfile::Hard);
    assert!((hard.cos_cutoff - 0.4f32.cos()).abs() < 1e-6);

    // Camera at its node, looking down −z; yfov in radians; height from aspect.
    let camera = scene.camera();
    assert!(close(camera.position, Vec3::new(0.0, 1.0, 10.0)));
    assert!(close(camera.look_at, Vec3::new(0.0, 1.0, 9.0)));
    let FieldOfView::Vertical(fov) = camera.fov else {
        panic!("{:?}", camera.fov)
    };
    assert!((fov - 0.5f32.to_degrees()).abs() < 1e-4);
    assert_eq!(desc.settings.height * 2, desc.settings.width);

    // Materials, by primitive (mesh i is primitive i).
    assert_eq!(
        *scene.material(0),
        Material::Opaque(Surface::diffuse(Rgb::new(0.5, 0.6, 0.7))),
        "specularFactor 0 is pure Lambert"
    );
    let Material::Glass(glass) = *scene.material(1) else {
        panic!("{:?}", scene.material(1))
    };
    assert_eq!(glass.color, Rgb::new(0.9, 0.2, 0.1));
    // KHR_materials_volume: half the red and a quarter of the green is
    // left after 2 units, so σa = ln 2/2 and ln 4/2; blue is clear.
    let Material::Dielectric { ior, absorption } = *scene.material(2) else {
        panic!("{:?}", scene.material(2))
    };
    assert_eq!(ior, 1.33);
    let expected = Rgb::new(2f32.ln() / 2.0, 4f32.ln() / 2.0, 0.0);
    assert!(
        (absorption - expected).abs().max_element() < 1e-6,
        "{absorption}"
    );
    // Emission adds to the surface's reflection: here glTF's default
    // white metal (metallicFactor and roughnessFactor 1).
    assert_eq!(
        *scene.material(3),
        Material::Emissive {
            radiance: Rgb::new(4.0, 2.0, 0.0),
            two_sided: false,
            surface: Surface::layered(Rgb::ZERO, Rgb::ONE, 1.0),
        }
    );
    let Material::Opaque(metal) = *scene.material(4) else {
        panic!("{:?}", scene.material(4))
    };
    assert!(close(metal.specular, Vec3::splat(0.8)) && metal.diffuse == Rgb::ZERO);
    assert!((metal.roughness - 0.09).abs() < 1e-6, "α = roughness²");
    // Default dielectric: F0 = ((1.5 − 1)/(1.5 + 1))² = 0.04.
    let Material::Opaque(plastic) = *scene.material(5) else {
        panic!("{:?}", scene.material(5))
    };
    assert!(close(plastic.specular, Vec3::splat(0.04)));
    assert!(close(plastic.diffuse, Vec3::splat(0.96)));

    assert!(desc.warnings.iter().any(|w| w.contains("EXT_made_up")));
}

/// The same scene written as glTF (and .glb) (one mesh, a 683 cd point light, a
/// camera; fog from the command line's overrides) and as native TOML (an
/// .obj mesh, a 1 W/sr point light, `[fog]`) renders the same image with
/// the same seed: both loaders produce the same triangles, light, camera
/// and fog, so every sample is the same.
#[test]
fn gltf_and_toml_render_the_same_image() {
    let dir = test_dir("same-image");
    // A floor (two triangles) and a floating occluder triangle.
    let positions = vec![
        [-2.0, 0.0, -2.0],
        [2.0, 0.0, -2.0],
        [2.0, 0.0, 2.0],
        [-2.0, 0.0, 2.0],
        [-0.5, 1.0, -0.5],
        [0.5, 1.0, 0.5],
        [0.5, 1.0, -0.5],
    ];
    let indices = vec![0, 2, 1, 0, 3, 2, 4, 5, 6];
    let yfov = 0.7f32;
    let doc = json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 683.0}]}},
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0},
            {"translation": [0.0, 2.5, 0.0], "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"translation": [0.0, 1.5, 6.0], "camera": 0}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": yfov, "znear": 0.1}}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.7, 0.6, 1.0], "metallicFactor": 0.0},
                       "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
    });
    let mesh = MeshData {
        positions: positions.clone(),
        indices: Some(indices.clone()),
        mode: None,
        material: Some(0),
        normals: None,
        uvs: None,
        colors: None,
        tangents: None,
    };
    let gltf_path = write_gltf(&dir, "room", &[mesh], doc);
    let mut obj = String::new();
    for p in &positions {
        obj += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for t in indices.chunks(3) {
        obj += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(dir.join("room.obj"), obj).expect("write obj");
    // The glTF camera's field of view, in degrees as the loader computes it.
    let fov_deg = (yfov as f64).to_degrees() as f32;
    let toml = format!(
        r#"
[camera]
position = [0.0, 1.5, 6.0]
look_at = [0.0, 1.5, 5.0]
fov_y_deg = {fov_deg}

[fog]
sigma_t = 0.1
albedo = 0.9
g = 0.2

[materials.wall]
type = "diffuse"
reflectance = [0.8, 0.7, 0.6]

[[shapes]]
type = "mesh"
file = "room.obj"
material = "wall"

[[lights]]
type = "point"
position = [0.0, 2.5, 0.0]
intensity = 1.0
"#
    );
    let toml_path = dir.join("room.toml");
    std::fs::write(&toml_path, toml).expect("write toml");

    let mut from_gltf = common::load_any(&gltf_path, Default::default()).expect("glTF");
    // What `tyndall render room.gltf --density 0.1 --albedo 0.9 --g 0.2` does.
    from_gltf.override_fog(Some(0.1), Some(0.9)).expect("fog");
    from_gltf.override_fog_asymmetry(0.2).expect("g");
    let from_toml = common::load_native(&toml_path).expect("TOML");
    let render = |desc: &common::Loaded| {
        let mut settings = desc.settings;
        // One integrator for both: a glTF file's own default is volpath.
        settings.integrator = tyndall::IntegratorKind::Single;
        settings.width = 40;
        settings.height = 30;
        settings.spp = 4;
        settings.seed = 7;
        tyndall::render(&desc.scene, &settings, &|_| {})
            .expect("renders")
            .image
    };
    // The same file as binary glTF (.glb) loads into the same scene.
    let mut from_glb = common::load_any(&to_glb(&dir, "room"), Default::default()).expect("glb");
    from_glb.override_fog(Some(0.1), Some(0.9)).expect("fog");
    from_glb.override_fog_asymmetry(0.2).expect("g");
    assert_eq!(
        render(&from_glb).pixels(),
        render(&from_gltf).pixels(),
        ".glb and .gltf differ"
    );
    let (a, b) = (render(&from_gltf), render(&from_toml));
    assert!(
        a.pixels().iter().any(|p| p.max_element() > 0.0),
        "the image is lit"
    );
    let differing: Vec<usize> = (0..a.pixels().len())
        .filter(|&i| a.pixels()[i] != b.pixels()[i])
        .collect();
    assert!(
        differing.is_empty(),
        "{} pixels differ, first {:?}",
        differing.len(),
        differing
            .first()
            .map(|&i| (i, a.pixels()[i], b.pixels()[i]))
    );
}

fn load_error(name: &str, meshes: &[MeshData], doc: serde_json::Value) -> String {
    let path = write_gltf(&test_dir(name), name, meshes, doc);
    match common::load_gltf(&path) {
        Ok(_) => panic!("{name}: a bad file loaded"),
        Err(e) => {
            let message = e.to_string();
            assert!(
                message.contains(&format!("{name}.gltf")),
                "names the file: {message}"
            );
            message
        }
    }
}

/// Each bad file's error names the file and the element.
#[test]
fn bad_gltf_files_name_file_and_element() {
    let scene = |nodes: serde_json::Value| json!({"scenes": [{"nodes": [0]}], "nodes": nodes});
    let lines = MeshData {
        mode: Some(1),
        ..triangle(0)
    };
    let m = load_error(
        "lines",
        &[triangle(0), lines],
        json!({"scenes": [{"nodes": [0, 1]}], "nodes": [{"mesh": 0}, {"mesh": 1}],
               "materials": [{}]}),
    );
    assert!(
        m.contains("meshes[1].primitives[0]") && m.contains("Lines"),
        "{m}"
    );

    let m = load_error(
        "ortho",
        &[triangle(0)],
        json!({"scenes": [{"nodes": [0, 1]}], "nodes": [{"mesh": 0}, {"camera": 0}], "materials": [{}],
               "cameras": [{"type": "orthographic",
                            "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 10.0}}]}),
    );
    assert!(
        m.contains("cameras[0]") && m.contains("orthographic"),
        "{m}"
    );

    let mut doc = scene(json!([{"mesh": 0}]));
    doc["materials"] = json!([{}]);
    doc["extensionsUsed"] = json!(["EXT_made_up"]);
    doc["extensionsRequired"] = json!(["EXT_made_up"]);
    let m = load_error("required", &[triangle(0)], doc);
    assert!(
        m.contains("extensionsRequired") && m.contains("EXT_made_up"),
        "{m}"
    );

    let mut doc = scene(json!([{"mesh": 0}]));
    doc["materials"] = json!([{}]);
    let bad_index = MeshData {
        indices: Some(vec![0, 1, 5]),
        ..triangle(0)
    };
    let m = load_error("index", &[bad_index], doc);
    assert!(
        m.contains("meshes[0].primitives[0]") && m.contains("vertex 5"),
        "{m}"
    );

    let mut doc = scene(json!([{"mesh": 0}]));
    doc["materials"] = json!([{"pbrMetallicRoughness": {"baseColorFactor": [2.0, 0.5, 0.5, 1.0]}}]);
    let m = load_error("color", &[triangle(0)], doc);
    assert!(
        m.contains("materials[0]") && m.contains("baseColorFactor"),
        "{m}"
    );

    for (volume, named) in [
        (json!({"attenuationDistance": 0.0}), "attenuationDistance"),
        (
            json!({"attenuationColor": [1.5, 0.5, 0.5]}),
            "attenuationColor",
        ),
    ] {
        let mut doc = scene(json!([{"mesh": 0}]));
        let mut volume = volume;
        volume["thicknessFactor"] = json!(0.1);
        doc["extensionsUsed"] = json!(["KHR_materials_transmission", "KHR_materials_volume"]);
        doc["materials"] = json!([{"extensions": {
            "KHR_materials_transmission": {"transmissionFactor": 1.0},
            "KHR_materials_volume": volume}}]);
        let m = load_error("volume", &[triangle(0)], doc);
        assert!(m.contains("materials[0]") && m.contains(named), "{m}");
    }
}

/// A native scene's `[[include]]` adds the glTF file's triangles (placed
/// by the include's scale, then translation, after the file's own
/// transforms) and lights beside the scene's own fog; a bad included file
/// is an error naming the TOML line, the glTF file and the element.
#[test]
fn toml_includes_gltf() {
    let dir = test_dir("include");
    let doc = json!({
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 683.0}]}},
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0, "translation": [0.0, 0.0, 1.0]},
                  {"extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "materials": [{}]
    });
    write_gltf(&dir, "part", &[triangle(0)], doc);
    let bad = MeshData {
        mode: Some(0),
        ..triangle(0)
    };
    write_gltf(
        &dir,
        "bad",
        &[bad],
        json!({"scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "materials": [{}]}),
    );
    let scene = |file: &str| {
        format!(
            "[camera]\nposition = [0, 0, 10]\nlook_at = [0, 0, 0]\nfov_y_deg = 30\n\n\
             [fog]\nsigma_t = 0.05\nalbedo = 1\n\n\
             [[include]]\nfile = \"{file}\"\nscale = 2\ntranslate = [1, 2, 3]\n"
        )
    };
    let path = dir.join("with-include.toml");
    std::fs::write(&path, scene("part.gltf")).expect("write");
    let desc = common::load_any(&path, Default::default()).expect("loads");
    // (v + (0,0,1))·2 + (1,2,3): (0,0,0) → (1,2,5), (1,0,0) → (3,2,5), (0,1,0) → (1,4,5).
    let [a, b, c] = corners(&desc.scene, 0);
    assert!(close(a, Vec3::new(1.0, 2.0, 5.0)), "{a}");
    assert!(close(b, Vec3::new(3.0, 2.0, 5.0)), "{b}");
    assert!(close(c, Vec3::new(1.0, 4.0, 5.0)), "{c}");
    let Light::Point(point) = &desc.scene.lights()[0] else {
        panic!("{:?}", desc.scene.lights()[0])
    };
    assert!(close(point.position, Vec3::new(1.0, 2.0, 3.0)));
    assert!(desc.scene.fog().is_some());

    let path = dir.join("bad-include.toml");
    std::fs::write(&path, scene("bad.gltf")).expect("write");
    let e = common::load_any(&path, Default::default())
        .err()
        .expect("bad include");
    let m = e.to_string();
    assert!(
        m.contains("bad-include.toml:")
            && m.contains("bad.gltf")
            && m.contains("meshes[0].primitives[0]"),
        "{m}"
    );
}

/// Vertex normals shade (issue 12): a floor of two triangles whose
/// corner normals lean by different amounts, under a sun straight overhead, is lit as
/// `ρ/π·E·(n·up)` with `n` the corner normals interpolated at the seen
/// point by its barycentric weights (computed here from areas), by
/// `single` and `volpath`; without the NORMAL attribute it is lit as a
/// flat floor, `ρ/π·E`. A zero NORMAL is an error naming the primitive.
#[test]
fn vertex_normals_shade_smoothly() {
    use tyndall::IntegratorKind;
    use tyndall::ray::Ray;
    let positions = vec![
        [-2.0, 0.0, -2.0],
        [2.0, 0.0, -2.0],
        [2.0, 0.0, 2.0],
        [-2.0, 0.0, 2.0],
    ];
    let lean = |p: [f32; 3]| Vec3::new(0.3 * (p[0] + 2.0), 1.0, 0.2 * (p[2] + 2.0)).normalize();
    let normals: Vec<[f32; 3]> = positions.iter().map(|&p| lean(p).to_array()).collect();
    let indices = vec![0, 2, 1, 0, 3, 2];
    let (rho, lux) = (0.6f32, 1366.0f32);
    // A sun along its node's −z turned −90° about x: straight down.
    let s = FRAC_1_SQRT_2;
    let doc = json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": lux}]}},
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0},
            {"rotation": [-s, 0.0, 0.0, s], "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1.0], "metallicFactor": 0.0},
                       "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
    });
    let floor = |normals: Option<Vec<[f32; 3]>>| MeshData {
        positions: positions.clone(),
        indices: Some(indices.clone()),
        mode: None,
        material: Some(0),
        normals,
        uvs: None,
        colors: None,
        tangents: None,
    };
    let dir = test_dir("vertex-normals");
    let smooth = common::load_gltf(&write_gltf(
        &dir,
        "smooth",
        &[floor(Some(normals.clone()))],
        doc.clone(),
    ))
    .expect("loads");
    let flat =
        common::load_gltf(&write_gltf(&dir, "flat", &[floor(None)], doc.clone())).expect("loads");

    let seen = [0.4f32, 0.3];
    // The triangle holding the point, and its barycentric weights as
    // ratios of areas in the floor's plane.
    let area = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
        0.5 * ((b[0] - a[0]) * (c[2] - a[2]) - (c[0] - a[0]) * (b[2] - a[2]))
    };
    let p = [seen[0], 0.0, seen[1]];
    let n = indices
        .chunks(3)
        .find_map(|t| {
            let [a, b, c] = [0, 1, 2].map(|k| positions[t[k] as usize]);
            let whole = area(a, b, c);
            let w = [area(p, b, c), area(a, p, c), area(a, b, p)].map(|x| x / whole);
            w.iter().all(|&x| x >= 0.0).then(|| {
                (0..3)
                    .map(|k| lean(positions[t[k] as usize]) * w[k])
                    .sum::<Vec3>()
                    .normalize()
            })
        })
        .expect("the point lies on the floor");
    let irradiance = lux / 683.0;
    let expected_smooth = rho / std::f32::consts::PI * irradiance * n.y;
    let expected_flat = rho / std::f32::consts::PI * irradiance;
    assert!(expected_flat - expected_smooth > 0.03 * expected_flat);
    let ray = Ray::new(Vec3::new(seen[0], 1.0, seen[1]), Vec3::new(0.0, -1.0, 0.0));
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        for (desc, expected, what) in [
            (&smooth, expected_smooth, "smooth"),
            (&flat, expected_flat, "flat"),
        ] {
            let (mean, stderr) = common::estimate_ray(desc, kind, 0.1, ray, 64);
            // A sun and a Lambert floor with nothing else to see: every
            // sample is the same value, up to f32 rounding.
            assert!(stderr.y <= 1e-6 * expected, "{kind:?} {what}: {stderr}");
            assert!(
                (mean.y - expected).abs() < 1e-5 * expected,
                "{kind:?} {what}: {} vs {expected}",
                mean.y
            );
        }
    }

    let mut zero = normals;
    zero[2] = [0.0, 0.0, 0.0];
    let m = load_error("zero-normal", &[floor(Some(zero))], doc);
    assert!(
        m.contains("meshes[0].primitives[0]") && m.contains("NORMAL"),
        "{m}"
    );
}
