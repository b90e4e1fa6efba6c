//! Bad input gives an error naming the file, line and column and what was
//! expected; never a panic.
mod common;

use tyndall_load::LegacyOptions;
use tyndall_load::SourceText;

const GOOD: &str = r#"[camera]
position = [0, 1, 5]
look_at = [0, 1, 0]
fov_y_deg = 40

[fog]
sigma_t = 0.1
albedo = 0.9

[materials.grey]
type = "diffuse"
reflectance = 0.5

[[shapes]]
type = "sphere"
center = [0, 1, 0]
radius = 0.5
material = "grey"

[[lights]]
type = "spot"
position = [0, 3, 0]
direction = [0, -1, 0]
cutoff_deg = 30
intensity = 10
"#;

fn native_error(text: &str) -> tyndall_load::SceneError {
    match common::parse_native(&SourceText::new("scene.toml", text)) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    }
}

/// Asserts the error is at `line` (1-based) and mentions `words`.
fn assert_error(e: &tyndall_load::SceneError, line: usize, words: &str) {
    let text = e.to_string();
    assert!(
        text.starts_with(&format!("scene.toml:{line}:")),
        "wrong place: {text}"
    );
    assert!(e.column >= 1, "{text}");
    assert!(text.contains(words), "`{words}` not in: {text}");
}

#[test]
fn good_scene_parses() {
    common::parse_native(&SourceText::new("scene.toml", GOOD)).expect("good scene");
}

#[test]
fn malformed_toml() {
    let e = native_error(&GOOD.replace("fov_y_deg = 40", "fov_y_deg = 40 40"));
    assert_error(&e, 4, "");
    let e = native_error(&GOOD.replace("radius = 0.5", "radius = \"big\""));
    assert_error(&e, 17, "");
    let e = native_error(&GOOD.replace("radius = 0.5", "radius = 0.5\ncolour = 1"));
    assert_error(&e, 18, "colour");
}

#[test]
fn bad_thin_lens() {
    for (lens, line, key) in [
        ("aperture_radius = -0.1", 5, "aperture_radius"),
        ("aperture_radius = nan", 5, "aperture_radius"),
        (
            "aperture_radius = 0.1\nfocus_distance = 0",
            6,
            "focus_distance",
        ),
        (
            "aperture_radius = 0.1\nfocus_distance = inf",
            6,
            "focus_distance",
        ),
        ("focus_distance = 3", 5, "needs `aperture_radius`"),
    ] {
        let e = native_error(&GOOD.replace("fov_y_deg = 40", &format!("fov_y_deg = 40\n{lens}")));
        assert_error(&e, line, key);
    }
    // A radius of 0 is a pinhole, whatever the focus.
    let pinhole = GOOD.replace(
        "fov_y_deg = 40",
        "fov_y_deg = 40\naperture_radius = 0\nfocus_distance = 2",
    );
    common::parse_native(&SourceText::new("scene.toml", &pinhole)).expect("a pinhole");
}

#[test]
fn negative_density() {
    let e = native_error(&GOOD.replace("sigma_t = 0.1", "sigma_t = -0.1"));
    assert_error(&e, 7, "sigma_t");
}

#[test]
fn cutoff_out_of_range() {
    for bad in ["0", "120"] {
        let e = native_error(&GOOD.replace("cutoff_deg = 30", &format!("cutoff_deg = {bad}")));
        assert_error(&e, 24, "cutoff_deg");
    }
}

#[test]
fn nan_values() {
    let e = native_error(&GOOD.replace("albedo = 0.9", "albedo = nan"));
    assert_error(&e, 8, "albedo");
    let e = native_error(&GOOD.replace("center = [0, 1, 0]", "center = [0, nan, 0]"));
    assert_error(&e, 16, "center");
}

#[test]
fn missing_mesh_file() {
    let text = GOOD.replace(
        "[[lights]]",
        "[[shapes]]\ntype = \"mesh\"\nfile = \"no-such-mesh.obj\"\nmaterial = \"grey\"\n\n[[lights]]",
    );
    let e = native_error(&text);
    assert_error(&e, 22, "no-such-mesh.obj");
}

#[test]
fn unknown_material_and_zero_size_image() {
    let e = native_error(&GOOD.replace("material = \"grey\"", "material = \"gray\""));
    assert_error(&e, 18, "unknown material `gray`");
    let e = native_error(&GOOD.replace("[fog]", "[render]\nwidth = 0\n\n[fog]"));
    assert_error(&e, 7, "width");
}

#[test]
fn zero_size_image_settings_are_rejected() {
    let desc = common::parse_native(&SourceText::new("scene.toml", GOOD)).expect("good");
    for (w, h) in [(0, 10), (10, 0)] {
        let settings = tyndall::RenderSettings {
            width: w,
            height: h,
            ..desc.settings
        };
        assert!(tyndall::render(&desc.scene, &settings, &|_| {}).is_err());
    }
}

fn legacy_error(text: &str) -> tyndall_load::SceneError {
    match common::parse_legacy(
        &SourceText::new("scene.obj", text),
        LegacyOptions::default(),
    ) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    }
}

#[test]
fn legacy_errors_name_line_and_column() {
    let base = "material\ndiffuse 1 1 1\nreflective 0 0 0\nemitted 5 5 5\n\nm 0\nv 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\nf 1 2 3 4\n";
    let cases = [
        (
            format!("{base}banana 3\n"),
            "scene.obj:12:1:",
            "unknown token `banana`",
        ),
        (
            base.replace("emitted 5 5 5", "emitted 5 5 5\nc 120"),
            "scene.obj:5:3:",
            "cutoff",
        ),
        (
            base.replace("emitted 5 5 5", "emitted 5 5 5\nc 0"),
            "scene.obj:5:3:",
            "cutoff",
        ),
        (
            base.replace("f 1 2 3 4", "f 1 2 3 9"),
            "scene.obj:11:9:",
            "vertex 9",
        ),
        (
            base.replace("v 1 1 0", "v 1 x 0"),
            "scene.obj:8:5:",
            "expected a number",
        ),
        (
            base.replace("v 1 1 0", "v 1 NaN 0"),
            "scene.obj:8:5:",
            "finite",
        ),
        (
            format!("{base}PerspectiveCamera {{ camera_position < 1, 2 > }}"),
            "scene.obj:12:",
            "three finite numbers",
        ),
        (
            format!("{base}r 0 0 0 1 1 2"),
            "scene.obj:12:1:",
            "not supported",
        ),
        (
            format!("{base}alpha 0.5"),
            "scene.obj:12:1:",
            "must follow a `material`",
        ),
    ];
    for (text, place, words) in cases {
        let e = legacy_error(&text).to_string();
        assert!(
            e.starts_with(place) && e.contains(words),
            "expected {place} … {words}, got: {e}"
        );
    }
}

/// Errors in a `[[media]]` table appended to the good scene, at the line
/// (counted from the table header, 1 = the header) of the offending key.
fn assert_media_error(table: &str, line_in_table: usize, words: &str) {
    let text = format!("{GOOD}\n[[media]]\n{table}");
    let e = native_error(&text);
    assert_error(&e, GOOD.lines().count() + 1 + line_in_table, words);
}

#[test]
fn media_errors_name_the_key() {
    let base = "sigma_t = 1.0\nalbedo = 0.9\nbox = { min = [-1, -1, -1], max = [1, 1, 1] }\n";
    assert_media_error(
        &format!("{base}density = \"fluffy\"\n"),
        5,
        "unknown density \"fluffy\"",
    );
    assert_media_error(&format!("{base}density = \"grid\"\n"), 5, "needs `file");
    assert_media_error(
        &format!("{base}density = \"grid\"\nfile = \"no-such-grid.tgrid\"\n"),
        6,
        "no-such-grid.tgrid",
    );
    assert_media_error(
        &format!("{base}density = \"noise\"\noctaves = 12\n"),
        6,
        "`octaves` must be between 1 and 8",
    );
    assert_media_error(&format!("{base}frequency = 2\n"), 5, "does not apply");
    assert_media_error(
        &format!("{base}mesh = \"m.obj\"\n"),
        5,
        "a `box` or a `mesh`, not both",
    );
    assert_media_error(
        "sigma_t = 1.0\nalbedo = 0.9\ndensity = \"noise\"\n",
        4,
        "needs a `box` or a `mesh`",
    );
    assert_media_error("sigma_t = 1.0\nalbedo = 1.2\n", 3, "between 0 and 1");
    assert_media_error("sigma_t = -1.0\nalbedo = 0.5\n", 2, "sigma_t");
    assert_media_error(
        "sigma_t = 1.0\nalbedo = 0.5\ntranslate = [1, 0, 0]\n",
        4,
        "places a `mesh`",
    );
}

/// A malformed grid file is named with what is wrong in it.
#[test]
fn bad_grid_file_is_reported() {
    let dir = std::env::temp_dir().join(format!("tyndall-bad-grid-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("short.tgrid"), b"tyndall-grid 1 2 2 2\n\0\0\0\0").unwrap();
    let text = format!(
        "{GOOD}\n[[media]]\nsigma_t = 1.0\nalbedo = 0.9\nbox = {{ min = [-1, -1, -1], max = [1, 1, 1] }}\ndensity = \"grid\"\nfile = \"short.tgrid\"\n"
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, &text).unwrap();
    let e = match common::load_native(&path) {
        Ok(_) => panic!("a short grid file must be an error"),
        Err(e) => e.to_string(),
    };
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        e.contains("short.tgrid") && e.contains("expected 8 f32 values"),
        "{e}"
    );
    assert!(
        e.contains(&format!(":{}:", GOOD.lines().count() + 7)),
        "{e}"
    );
}

/// Every value error of a file is reported at once, each at its key: the
/// first as the error's place, the others on their own lines.
#[test]
fn every_value_error_is_reported_at_its_key() {
    let text = GOOD
        .replace("reflectance = 0.5", "reflectance = 1.5")
        .replace("radius = 0.5", "radius = -1")
        .replace("intensity = 10", "intensity = -10");
    let e = native_error(&text);
    assert_error(&e, 12, "`reflectance` must be between 0 and 1");
    let text = e.to_string();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 3, "{text}");
    assert!(
        lines[1].starts_with("scene.toml:17:") && lines[1].contains("`radius`"),
        "{text}"
    );
    assert!(
        lines[2].starts_with("scene.toml:25:") && lines[2].contains("`intensity`"),
        "{text}"
    );
}

/// Light groups (docs/scene-format.md, "AOVs and denoising"): a name that
/// cannot name an EXR layer, the reserved `other`, a group on what does
/// not emit, and more groups than a render keeps are errors at the key.
#[test]
fn bad_light_groups_are_errors_at_their_key() {
    let spot = "intensity = 10\n";
    let on_spot = |value: &str| GOOD.replace(spot, &format!("{spot}light_group = {value}\n"));
    let e = native_error(&on_spot("\"key light\""));
    assert_error(&e, 26, "ASCII letters, digits");
    let e = native_error(&on_spot("\"other\""));
    assert_error(
        &e,
        26,
        "`other` is the group of the light in no named group",
    );
    let e = native_error(&on_spot("3"));
    assert_error(&e, 26, "expected a string");
    let sphere = "material = \"grey\"\n";
    let e = native_error(&GOOD.replace(sphere, &format!("{sphere}light_group = \"ball\"\n")));
    assert_error(&e, 19, "only lights and emissive shapes");
    // Sixteen named groups: one more than the per-sample split holds.
    let mut text = GOOD.to_owned();
    for k in 0..16 {
        text.push_str(&format!(
            "\n[[lights]]\ntype = \"point\"\nposition = [0, 2, {k}]\nintensity = 1\nlight_group = \"g{k}\"\n"
        ));
    }
    let e = native_error(&text);
    let line = text
        .lines()
        .position(|l| l == "light_group = \"g15\"")
        .expect("line")
        + 1;
    assert_error(&e, line, "at most 15 light groups");
}
