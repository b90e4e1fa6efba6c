//! `tyndall render` on glTF files: a good file renders with fog from the
//! command line; a bad one exits non-zero naming the file and the
//! element, and writes no image.

mod common;

use common::{stderr, temp_dir, tyndall};
use std::path::{Path, PathBuf};

/// A floor of two triangles under a 683 cd point light, seen by a camera;
/// `mode` is the primitive mode (4 = triangles).
fn write_room(dir: &Path, name: &str, mode: u32) -> PathBuf {
    let positions: [[f32; 3]; 4] = [
        [-2.0, 0.0, -2.0],
        [2.0, 0.0, -2.0],
        [2.0, 0.0, 2.0],
        [-2.0, 0.0, 2.0],
    ];
    let indices: [u16; 6] = [0, 2, 1, 0, 3, 2];
    let mut bin = Vec::new();
    for c in positions.iter().flatten() {
        bin.extend_from_slice(&c.to_le_bytes());
    }
    for i in indices {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    std::fs::write(dir.join(format!("{name}.bin")), &bin).expect("write bin");
    let gltf = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {{"KHR_lights_punctual": {{"lights": [{{"type": "point", "intensity": 683}}]}}}},
  "scenes": [{{"nodes": [0, 1, 2]}}],
  "nodes": [
    {{"mesh": 0}},
    {{"translation": [0, 2, 0], "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}},
    {{"translation": [0, 1, 5], "camera": 0}}
  ],
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.8, "znear": 0.1}}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "mode": {mode}}}]}}],
  "buffers": [{{"uri": "{name}.bin", "byteLength": {len}}}],
  "bufferViews": [
    {{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
    {{"buffer": 0, "byteOffset": 48, "byteLength": 12}}
  ],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
      "min": [-2, 0, -2], "max": [2, 0, 2]}},
    {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}}
  ]
}}"#,
        len = bin.len()
    );
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, gltf).expect("write gltf");
    path
}

#[test]
fn renders_gltf_with_fog_from_the_command_line() {
    let dir = temp_dir();
    let scene = write_room(&dir, "room", 4);
    let out = dir.join("room.exr");
    let _ = std::fs::remove_file(&out);
    let o = tyndall(&[
        "render",
        scene.to_str().unwrap(),
        "--density",
        "0.1",
        "--albedo",
        "0.9",
        "--g",
        "0.2",
        "--width",
        "24",
        "--height",
        "16",
        "--spp",
        "1",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let image = tyndall_image::read_exr(&out).expect("readable EXR");
    assert!(image.pixels().iter().any(|p| p.max_element() > 0.0));
}

#[test]
fn bad_gltf_exits_non_zero_naming_file_and_element_without_image() {
    let dir = temp_dir();
    let scene = write_room(&dir, "strips", 5);
    let out = dir.join("strips.png");
    let _ = std::fs::remove_file(&out);
    let o = tyndall(&[
        "render",
        scene.to_str().unwrap(),
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]);
    let message = stderr(&o);
    assert!(!o.status.success());
    assert!(
        message.contains("strips.gltf") && message.contains("meshes[0].primitives[0]"),
        "{message}"
    );
    assert!(!out.exists(), "no image is written");
}

#[test]
fn g_needs_fog_and_a_valid_value() {
    let dir = temp_dir();
    let scene = write_room(&dir, "nofog", 4);
    let out = dir.join("nofog.png");
    let _ = std::fs::remove_file(&out);
    let args = |g: &'static str, density: Option<&'static str>| {
        let mut a = vec![
            "render",
            scene.to_str().unwrap(),
            "-q",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
            "-o",
            out.to_str().unwrap(),
            "--g",
            g,
        ];
        if let Some(d) = density {
            a.extend(["--density", d]);
        }
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let run = |a: Vec<String>| {
        let refs: Vec<&str> = a.iter().map(String::as_str).collect();
        tyndall(&refs)
    };
    let o = run(args("0.2", None));
    assert!(!o.status.success() && stderr(&o).contains("--g needs fog"));
    let o = run(args("1.5", Some("0.1")));
    assert!(!o.status.success() && stderr(&o).contains("--g must be"));
    assert!(!out.exists());
}

/// `--environment` lights a glTF from a sky: a colour is the radiance of
/// every camera ray that leaves the scene (the upper rows, exactly), a map
/// file the map's radiance there, and the floor is brighter than under the
/// file's lamp alone; a bad value or file is an error naming it, and no
/// image is written.
#[test]
fn environment_from_the_command_line() {
    let dir = temp_dir();
    let scene = write_room(&dir, "sky", 4);
    let render = |environment: Option<&str>, out: &Path| {
        let _ = std::fs::remove_file(out);
        let mut args = vec![
            "render",
            scene.to_str().unwrap(),
            "--width",
            "16",
            "--height",
            "12",
            "--spp",
            "4",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ];
        if let Some(e) = environment {
            args.extend(["--environment", e]);
        }
        tyndall(&args)
    };
    let read = |out: &Path| tyndall_image::read_exr(out).expect("readable EXR");
    let floor_mean = |image: &tyndall::Image| {
        let row = image.height() - 1;
        (0..image.width())
            .map(|x| image.pixel(x, row).x)
            .sum::<f32>()
    };
    let lamp = dir.join("lamp.exr");
    let o = render(None, &lamp);
    assert!(o.status.success(), "{}", stderr(&o));
    let lamp = read(&lamp);
    assert_eq!(lamp.pixel(3, 0), tyndall::color::Rgb::ZERO);

    let coloured = dir.join("coloured.exr");
    let o = render(Some("0.25,0.5,1"), &coloured);
    assert!(o.status.success(), "{}", stderr(&o));
    let coloured = read(&coloured);
    assert_eq!(
        coloured.pixel(3, 0),
        tyndall::color::Rgb::new(0.25, 0.5, 1.0)
    );
    assert!(floor_mean(&coloured) > floor_mean(&lamp) + 0.1);

    let map = dir.join("grey-sky.exr");
    let grey = tyndall::Image::from_pixels(8, 4, vec![tyndall::color::Rgb::splat(0.3); 32]);
    tyndall_image::write_image(&grey, &map, 0.0).expect("write map");
    let mapped = dir.join("mapped.exr");
    let o = render(Some(map.to_str().unwrap()), &mapped);
    assert!(o.status.success(), "{}", stderr(&o));
    let sky = read(&mapped).pixel(3, 0);
    assert!(
        (sky - tyndall::color::Rgb::splat(0.3)).abs().max_element() < 1e-6,
        "{sky}"
    );

    for (bad, words) in [
        ("1,2", "one number or three"),
        ("no-such-sky.hdr", "no-such-sky.hdr"),
        ("-1", "--environment"),
    ] {
        let out = dir.join("bad.exr");
        let o = render(Some(bad), &out);
        assert!(!o.status.success(), "{bad}");
        assert!(stderr(&o).contains(words), "{bad}: {}", stderr(&o));
        assert!(!out.exists(), "{bad}: no image is written");
    }
}
