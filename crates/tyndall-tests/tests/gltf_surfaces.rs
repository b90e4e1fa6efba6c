//! glTF surfaces point by point: base colour textures (with
//! `KHR_texture_transform`), vertex colours and alpha cut-outs, each
//! against the closed form of a sunlit floor.

mod common;
mod gltf_files;

use glam::Vec3;
use gltf_files::{MeshData, test_dir, write_gltf};
use serde_json::json;
use std::f32::consts::{FRAC_1_SQRT_2, PI};
use tyndall::color::Rgb;

/// A base colour texture colours the surface point by point (issue 12):
/// a floor whose texture coordinates map it onto a 2×2 image of red,
/// green, blue and white texels (written as PNG here), under a sun
/// straight overhead, is lit as `factor·texel/π·E` at each texel's
/// centre and as the mean of two texels halfway between them (bilinear
/// filtering), by `single` and `volpath`. Without TEXCOORD_0 the
/// texture's mean colour applies, with a warning.
#[test]
fn base_colour_texture_colours_points() {
    use tyndall::IntegratorKind;
    use tyndall::ray::Ray;
    let dir = test_dir("texture");
    let texels = [
        Rgb::new(1.0, 0.0, 0.0),
        Rgb::new(0.0, 1.0, 0.0),
        Rgb::new(0.0, 0.0, 1.0),
        Rgb::new(1.0, 1.0, 1.0),
    ];
    tyndall_image::output::write_image(
        &tyndall::Image::from_pixels(2, 2, texels.to_vec()),
        &dir.join("checker.png"),
        0.0,
    )
    .expect("png");
    let positions = vec![
        [-2.0, 0.0, -2.0],
        [2.0, 0.0, -2.0],
        [2.0, 0.0, 2.0],
        [-2.0, 0.0, 2.0],
    ];
    // u along x, v along z, the image over the whole floor.
    let uv = |p: [f32; 3]| [(p[0] + 2.0) / 4.0, (p[2] + 2.0) / 4.0];
    let factor = 0.8f32;
    let s = FRAC_1_SQRT_2;
    let doc = json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 683.0}]}},
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0},
            {"rotation": [-s, 0.0, 0.0, s], "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "images": [{"uri": "checker.png"}],
        "samplers": [{"wrapS": 33071, "wrapT": 33071}],
        "textures": [{"source": 0, "sampler": 0}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [factor, factor, factor, 1.0],
                                                "baseColorTexture": {"index": 0},
                                                "metallicFactor": 0.0},
                       "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
    });
    let floor = |uvs: Option<Vec<[f32; 2]>>| MeshData {
        positions: positions.clone(),
        indices: Some(vec![0, 2, 1, 0, 3, 2]),
        mode: None,
        material: Some(0),
        normals: None,
        uvs,
        colors: None,
    };
    let textured = common::load_gltf(&write_gltf(
        &dir,
        "textured",
        &[floor(Some(positions.iter().map(|&p| uv(p)).collect()))],
        doc.clone(),
    ))
    .expect("loads");
    let untextured =
        common::load_gltf(&write_gltf(&dir, "no-uvs", &[floor(None)], doc)).expect("loads");
    assert!(
        untextured.warnings.iter().any(|w| w.contains("TEXCOORD_0")),
        "{:?}",
        untextured.warnings
    );
    // E = 683 lx / 683 lm/W = 1 W/m².
    let lit = |colour: Rgb| colour * (factor / std::f32::consts::PI);
    let mean = (texels[0] + texels[1] + texels[2] + texels[3]) / 4.0;
    let cases = [
        (&textured, [-1.0, -1.0], lit(texels[0])),
        (&textured, [1.0, -1.0], lit(texels[1])),
        (&textured, [-1.0, 1.0], lit(texels[2])),
        (&textured, [1.0, 1.0], lit(texels[3])),
        (&textured, [0.0, -1.0], lit((texels[0] + texels[1]) / 2.0)),
        (&untextured, [0.7, -1.3], lit(mean)),
    ];
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        for (desc, [x, z], expected) in cases {
            let ray = Ray::new(Vec3::new(x, 1.0, z), Vec3::new(0.0, -1.0, 0.0));
            let (got, _) = common::estimate_ray(desc, kind, 0.1, ray, 16);
            assert!(
                (got - expected).abs().max_element() < 1e-5,
                "{kind:?} at ({x}, {z}): {got} vs {expected}"
            );
        }
    }
    // The albedo guide (AOV, issue 24) is the textured reflectance itself:
    // `factor·texel`, point by point.
    for (desc, [x, z], expected) in cases {
        let ray = Ray::new(Vec3::new(x, 1.0, z), Vec3::new(0.0, -1.0, 0.0));
        let guide = tyndall::guides::first_surface(&desc.scene, ray);
        let albedo = expected * std::f32::consts::PI;
        assert!(
            (guide.albedo - albedo).abs().max_element() < 1e-5,
            "albedo at ({x}, {z}): {} vs {albedo}",
            guide.albedo
        );
    }
}

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
/// refused; `BLEND` is rendered opaque, with a warning.
#[test]
fn alpha_cutouts_are_holes_for_every_ray() {
    use tyndall::IntegratorKind;
    use tyndall::ray::Ray;
    let dir = test_dir("cutout");
    let checker = image::RgbaImage::from_fn(2, 2, |x, y| {
        image::Rgba([255, 255, 255, if x == y { 255 } else { 0 }])
    });
    checker.save(dir.join("leaf.png")).expect("png");
    let quad = |h: f32, r: f32| vec![[-r, h, -r], [r, h, -r], [r, h, r], [-r, h, r]];
    let mesh = |positions: Vec<[f32; 3]>, material: usize, uvs: bool| MeshData {
        uvs: uvs.then(|| {
            positions
                .iter()
                .map(|p| [(p[0] + 1.0) / 2.0, (p[2] + 1.0) / 2.0])
                .collect()
        }),
        positions,
        indices: Some(vec![0, 2, 1, 0, 3, 2]),
        mode: None,
        material: Some(material),
        normals: None,
        colors: None,
    };
    let s = FRAC_1_SQRT_2;
    let no_specular = json!({"KHR_materials_specular": {"specularFactor": 0.0}});
    let doc = |leaf_mode: &str| {
        json!({
            "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
            "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 683.0}]}},
            "scenes": [{"nodes": [0, 1, 2, 3]}],
            "nodes": [
                {"mesh": 0}, {"mesh": 1}, {"mesh": 2},
                {"rotation": [-s, 0.0, 0.0, s], "extensions": {"KHR_lights_punctual": {"light": 0}}}
            ],
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
        })
    };
    let meshes = [
        mesh(quad(1.0, 1.0), 0, true),
        mesh(quad(0.0, 2.0), 1, false),
        mesh(quad(1.5, 3.0), 2, false),
    ];
    let desc = common::load_gltf(&write_gltf(&dir, "leaf", &meshes, doc("MASK"))).expect("loads");
    assert!(desc.scene.has_cutouts());
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
    );
    assert!((guide.albedo - Rgb::splat(0.8)).abs().max_element() < 1e-6);

    let maps = tyndall::RenderSettings {
        visibility: tyndall::settings::VisibilityMode::Maps { resolution: 64 },
        ..desc.settings
    };
    assert_eq!(
        maps.validate(&desc.scene),
        Err(tyndall::render::RenderError::CutoutsNeedShadowRays)
    );

    let blended =
        common::load_gltf(&write_gltf(&dir, "blend", &meshes, doc("BLEND"))).expect("loads");
    assert!(!blended.scene.has_cutouts());
    assert!(
        blended.warnings.iter().any(|w| w.contains("BLEND")),
        "{:?}",
        blended.warnings
    );
}

/// `KHR_texture_transform` on a base colour texture: a 2×2 checker
/// (clamped) over a floor, its coordinates rotated a quarter turn and
/// offset by (0, 1), so that a point of coordinates (u, v) shows the
/// texel at `(v, 1 − u)` — the extension's `T·R·S` with its rotation
/// matrix `[cos sin; −sin cos]`, written out here. Each quadrant's
/// centre, lit by a sun straight down, shows that texel's colour.
#[test]
fn texture_transform_moves_the_texture() {
    use tyndall::IntegratorKind;
    use tyndall::ray::Ray;
    let dir = test_dir("texture-transform");
    let texels = [
        Rgb::new(1.0, 0.0, 0.0),
        Rgb::new(0.0, 1.0, 0.0),
        Rgb::new(0.0, 0.0, 1.0),
        Rgb::new(1.0, 1.0, 1.0),
    ];
    tyndall_image::output::write_image(
        &tyndall::Image::from_pixels(2, 2, texels.to_vec()),
        &dir.join("checker.png"),
        0.0,
    )
    .expect("png");
    let positions = vec![
        [-2.0, 0.0, -2.0],
        [2.0, 0.0, -2.0],
        [2.0, 0.0, 2.0],
        [-2.0, 0.0, 2.0],
    ];
    let uv = |x: f32, z: f32| [(x + 2.0) / 4.0, (z + 2.0) / 4.0];
    let s = FRAC_1_SQRT_2;
    let doc = json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular", "KHR_texture_transform"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 683.0}]}},
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0},
            {"rotation": [-s, 0.0, 0.0, s], "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "images": [{"uri": "checker.png"}],
        "samplers": [{"wrapS": 33071, "wrapT": 33071}],
        "textures": [{"source": 0, "sampler": 0}],
        "materials": [{"pbrMetallicRoughness": {
                           "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
                               "offset": [0.0, 1.0], "rotation": std::f32::consts::FRAC_PI_2}}},
                           "metallicFactor": 0.0},
                       "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
    });
    let floor = MeshData {
        uvs: Some(positions.iter().map(|p| uv(p[0], p[2])).collect()),
        colors: None,
        positions,
        indices: Some(vec![0, 2, 1, 0, 3, 2]),
        mode: None,
        material: Some(0),
        normals: None,
    };
    let desc = common::load_gltf(&write_gltf(&dir, "turned", &[floor], doc)).expect("loads");
    assert!(
        desc.warnings
            .iter()
            .all(|w| !w.contains("KHR_texture_transform")),
        "{:?}",
        desc.warnings
    );
    for (x, z) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
        let [u, v] = uv(x, z);
        // (u, v) ↦ (v, 1 − u), then the texel whose quadrant holds it.
        let (tu, tv) = (v, 1.0 - u);
        let texel = texels[2 * usize::from(tv > 0.5) + usize::from(tu > 0.5)];
        let expected = texel / PI;
        let ray = Ray::new(Vec3::new(x, 1.0, z), Vec3::new(0.0, -1.0, 0.0));
        let (got, _) = common::estimate_ray(&desc, IntegratorKind::Single, 0.1, ray, 4);
        assert!(
            (got - expected).abs().max_element() < 1e-5,
            "at ({x}, {z}): {got} vs {expected}"
        );
    }
}

/// Vertex colours (`COLOR_0`) multiply an opaque surface's diffuse
/// reflectance, interpolated across each triangle by barycentric weights:
/// a floor whose corners are red, green, blue and white, lit by a sun
/// straight down (E = 1 W/m²), shows at a point of weights `w` on a
/// triangle `0.8/π · Σ wᵢ cᵢ`, by `single` and `volpath`; its albedo guide
/// is `0.8 · Σ wᵢ cᵢ`.
#[test]
fn vertex_colours_colour_the_diffuse_reflectance() {
    use tyndall::IntegratorKind;
    use tyndall::ray::Ray;
    let dir = test_dir("vertex-colours");
    let positions = [
        [-2.0f32, 0.0, -2.0],
        [2.0, 0.0, -2.0],
        [2.0, 0.0, 2.0],
        [-2.0, 0.0, 2.0],
    ];
    let colours = [
        [1.0f32, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
    ];
    let s = FRAC_1_SQRT_2;
    let doc = json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 683.0}]}},
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0},
            {"rotation": [-s, 0.0, 0.0, s], "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0},
                       "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
    });
    let floor = MeshData {
        positions: positions.to_vec(),
        indices: Some(vec![0, 2, 1, 0, 3, 2]),
        mode: None,
        material: Some(0),
        normals: None,
        uvs: None,
        colors: Some(colours.to_vec()),
    };
    let desc = common::load_gltf(&write_gltf(&dir, "coloured", &[floor], doc)).expect("loads");
    assert!(
        desc.warnings.iter().all(|w| !w.contains("COLOR_0")),
        "{:?}",
        desc.warnings
    );
    let at = |weights: [(usize, f32); 3]| {
        let mut p = Vec3::ZERO;
        let mut c = Rgb::ZERO;
        for (i, w) in weights {
            p += Vec3::from_array(positions[i]) * w;
            c += Rgb::from_array(colours[i]) * w;
        }
        (p, c * 0.8)
    };
    let points = [
        at([(0, 0.2), (1, 0.3), (2, 0.5)]),
        at([(0, 0.6), (2, 0.1), (3, 0.3)]),
        at([(0, 0.5), (2, 0.5), (3, 0.0)]),
        at([(0, 0.05), (2, 0.05), (3, 0.9)]),
    ];
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        for (p, albedo) in points {
            let ray = Ray::new(p + Vec3::Y, Vec3::new(0.0, -1.0, 0.0));
            let (got, _) = common::estimate_ray(&desc, kind, 0.1, ray, 4);
            let expected = albedo / PI;
            assert!(
                (got - expected).abs().max_element() < 1e-5,
                "{kind:?} at {p}: {got} vs {expected}"
            );
            let guide = tyndall::guides::first_surface(&desc.scene, ray);
            assert!((guide.albedo - albedo).abs().max_element() < 1e-5);
        }
    }
}
