//! Meshes and principled materials written into a native scene itself
//! (`type = "triangles"`, `type = "principled"`), as the Blender add-on
//! and `tyndall.Scene.from_dict` give them: each against the closed form
//! of a sunlit floor, and their bad input at its line and key.

mod common;

use glam::Vec3;
use std::f32::consts::PI;
use tyndall::IntegratorKind;
use tyndall::color::Rgb;
use tyndall::materials::{Material, MetallicRoughness};
use tyndall::ray::Ray;
use tyndall_load::SourceText;

/// The 2×2 colour checker, texel by texel, row by row.
const CHECKER: [Rgb; 4] = [
    Rgb::new(1.0, 0.0, 0.0),
    Rgb::new(0.0, 1.0, 0.0),
    Rgb::new(0.0, 0.0, 1.0),
    Rgb::new(1.0, 1.0, 1.0),
];

/// The text of a scene whose 4 × 4 floor at height 0 is a `triangles`
/// shape of material `floor` (its `uvs` spread an image over it, u along
/// x, v along z; with `normals` if `smooth`), the material table
/// `material`, and lights `lights`.
fn floor_scene(material: &str, smooth: bool, lights: &str) -> String {
    let normals = if smooth {
        "normals = [0, 1, 0,  0, 1, 0,  0, 1, 0,  0, 1, 0]\n"
    } else {
        ""
    };
    format!(
        r#"[camera]
position = [0, 5, 5]
look_at = [0, 0, 0]
fov_y_deg = 40

[materials.floor]
{material}

[[shapes]]
type = "triangles"
positions = [-2, 0, -2,  2, 0, -2,  2, 0, 2,  -2, 0, 2]
indices = [0, 2, 1,  0, 3, 2]
{normals}uvs = [0, 0,  1, 0,  1, 1,  0, 1]
material = "floor"
{lights}"#
    )
}

/// [`floor_scene`] in `dir`, smooth, under a sun straight down (E = 1 W/m²).
fn sunlit_floor(dir: &std::path::Path, material: &str) -> common::Loaded {
    let sun = "\n[[lights]]\ntype = \"directional\"\ndirection = [0, -1, 0]\nirradiance = 1\n";
    let text = floor_scene(material, true, sun);
    common::parse_native(&SourceText::new(dir.join("scene.toml"), text))
        .unwrap_or_else(|e| panic!("{e}"))
}

fn test_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("tyndall-inline-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// The radiance straight up from the floor under `(x, z)`, by `kind`.
fn looking_down(desc: &common::Loaded, kind: IntegratorKind, x: f32, z: f32) -> Rgb {
    let ray = Ray::new(Vec3::new(x, 1.0, z), Vec3::new(0.0, -1.0, 0.0));
    common::estimate_ray(desc, kind, 0.1, ray, 16).0
}

/// A principled floor with a base colour texture: at each texel's centre
/// the floor reflects `base·texel/π·E` (f0 = 0: Lambert), and halfway
/// between two texels their mean (bilinear), by `single` and `volpath`;
/// the material's constant surface is the glTF mix
/// ([`MetallicRoughness::surface`]) with F0 0.04 when `f0` is not given.
#[test]
fn a_textured_principled_triangles_floor_matches_its_closed_form() {
    let dir = test_dir("texture");
    tyndall_image::output::write_image(
        &tyndall::Image::from_pixels(2, 2, CHECKER.to_vec()),
        &dir.join("checker.png"),
        0.0,
    )
    .expect("png");
    let base = 0.8;
    let desc = sunlit_floor(
        &dir,
        &format!(
            "type = \"principled\"\nbase_color = {base}\nf0 = 0\nbase_color_texture = \"checker.png\""
        ),
    );
    let lit = |texel: Rgb| texel * (base / PI);
    let cases = [
        ([-1.0, -1.0], lit(CHECKER[0])),
        ([1.0, -1.0], lit(CHECKER[1])),
        ([-1.0, 1.0], lit(CHECKER[2])),
        ([1.0, 1.0], lit(CHECKER[3])),
        ([0.0, -1.0], lit((CHECKER[0] + CHECKER[1]) / 2.0)),
    ];
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        for ([x, z], expected) in cases {
            let got = looking_down(&desc, kind, x, z);
            assert!(
                (got - expected).abs().max_element() < 1e-5,
                "{kind:?} at ({x}, {z}): {got} vs {expected}"
            );
        }
    }
    let plain = sunlit_floor(
        &dir,
        "type = \"principled\"\nbase_color = [0.9, 0.6, 0.3]\nmetallic = 0.25\nroughness = 0.4",
    );
    let expected = MetallicRoughness {
        base: Rgb::new(0.9, 0.6, 0.3),
        metallic: 0.25,
        roughness: 0.4,
        f0: Rgb::splat(0.04),
        clearcoat: Default::default(),
    }
    .surface();
    assert_eq!(plain.scene.materials()[0], Material::Opaque(expected));
}

/// A principled floor that emits adds its emission to the light it
/// reflects: `emission + base/π·E` straight up (glTF adds emission to the
/// BRDF), by `single` and `volpath`.
#[test]
fn a_principled_emitter_adds_emission_to_reflection() {
    let dir = test_dir("emission");
    let (base, emission) = (0.8, Rgb::new(0.5, 0.25, 0.125));
    let desc = sunlit_floor(
        &dir,
        &format!(
            "type = \"principled\"\nbase_color = {base}\nf0 = 0\nemission = [{}, {}, {}]",
            emission.x, emission.y, emission.z
        ),
    );
    let expected = emission + Rgb::splat(base / PI);
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        let got = looking_down(&desc, kind, 0.3, -0.7);
        assert!(
            (got - expected).abs().max_element() < 1e-5,
            "{kind:?}: {got} vs {expected}"
        );
    }
}

/// Bad `triangles` and `principled` tables are errors at their line,
/// naming the key.
#[test]
fn bad_inline_meshes_are_errors_at_their_key() {
    let dir = test_dir("bad");
    let good = "type = \"principled\"\nbase_color = 0.5";
    let text = |material: &str| floor_scene(material, false, "");
    // The error's place is the line of `key` (its last occurrence: the
    // shape's own `material`, not the material's).
    let at = |text: String, key: &str, words: &str| {
        let line = 1 + text
            .lines()
            .enumerate()
            .filter(|(_, l)| l.starts_with(&format!("{key} =")))
            .map(|(i, _)| i)
            .last()
            .expect("the key is in the scene");
        let e = match common::parse_native(&SourceText::new(dir.join("scene.toml"), text.clone())) {
            Ok(_) => panic!("expected an error for:\n{text}"),
            Err(e) => e.to_string(),
        };
        assert!(
            e.contains(&format!("scene.toml:{line}:")),
            "wrong place: {e}"
        );
        assert!(e.contains(words), "`{words}` not in: {e}");
    };
    let base = text(good);
    at(
        base.replace("indices = [0, 2, 1,", "indices = [0, 2, 7,"),
        "indices",
        "index 2 is vertex 7, and there are 4 vertices",
    );
    at(
        base.replace("2, 0, 2]", "2, 0]"),
        "positions",
        "three numbers per vertex",
    );
    at(
        base.replace("uvs = [0, 0,  ", "uvs = ["),
        "uvs",
        "`uvs` holds 2 numbers per vertex (8 for 4 vertices), got 6",
    );
    at(
        base.replace("positions = [-2, 0, -2,", "positions = [-2, 0, nan,"),
        "positions",
        "vertex 0",
    );
    // Arrays given beside the text: none is given here.
    let beside = base
        .lines()
        .map(|l| match l.starts_with("positions =") {
            true => "positions = \"@array:0\"",
            false => l,
        })
        .collect::<Vec<_>>()
        .join("\n");
    at(
        beside.clone(),
        "positions",
        "names array 0, and 0 were given",
    );
    at(
        beside.replace("\"@array:0\"", "\"array 0\""),
        "positions",
        "give numbers, or \"@array:K\"",
    );
    at(
        text("type = \"principled\"\nbase_color = 0.5\nmetallic = 2"),
        "metallic",
        "`metallic` must be in [0, 1]",
    );
    at(
        text("type = \"principled\"\nbase_color = 0.5\nbase_color_texture = \"missing.png\""),
        "base_color_texture",
        "missing.png",
    );
    // Every triangle degenerate: nothing to draw.
    at(
        base.replace("indices = [0, 2, 1,  0, 3, 2]", "indices = [0, 0, 1]"),
        "indices",
        "zero area",
    );
    // A texture needs coordinates: on a sphere, or on triangles without `uvs`.
    tyndall_image::output::write_image(
        &tyndall::Image::from_pixels(1, 1, vec![Rgb::ONE]),
        &dir.join("white.png"),
        0.0,
    )
    .expect("png");
    let textured = "type = \"principled\"\nbase_color = 0.5\nbase_color_texture = \"white.png\"";
    at(
        text(textured).replace("uvs = [0, 0,  1, 0,  1, 1,  0, 1]\n", ""),
        "material",
        "give the shape `uvs`",
    );
    at(
        format!(
            "{}\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 1, 0]\nradius = 0.5\nmaterial = \"floor\"\n",
            text(textured)
        ),
        "material",
        "only a `triangles` shape with `uvs` can carry",
    );
}

/// Two principled materials naming one image share one texture: the
/// file is read and held once.
#[test]
fn materials_naming_one_image_share_its_texture() {
    let dir = test_dir("shared-texture");
    tyndall_image::output::write_image(
        &tyndall::Image::from_pixels(2, 2, CHECKER.to_vec()),
        &dir.join("checker.png"),
        0.0,
    )
    .expect("png");
    let material = |base: f32| {
        format!("type = \"principled\"\nbase_color = {base}\nbase_color_texture = \"checker.png\"")
    };
    let text = floor_scene(&material(0.8), false, "").replace(
        "[[shapes]]",
        &format!("[materials.wall]\n{}\n\n[[shapes]]", material(0.4)),
    ) + "\n[[shapes]]\ntype = \"triangles\"\npositions = [-2, 0, -3,  2, 0, -3,  2, 2, -3]\n\
         indices = [0, 1, 2]\nuvs = [0, 0,  1, 0,  1, 1]\nmaterial = \"wall\"\n";
    let desc = tyndall_load::native::parse(&SourceText::new(dir.join("scene.toml"), text))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(desc.materials.len(), 2);
    assert_eq!(desc.textures.len(), 1);
}
