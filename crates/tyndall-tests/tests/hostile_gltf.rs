//! Hostile glTF and glb files (issue 28): each case a fuzzing campaign
//! found — a panic in the `gltf` crate, an allocation abort, a stack
//! overflow, memory exhausted by a node DAG or by reading `/dev/zero` —
//! is built here as its minimal file and must be refused with an error
//! naming the file and the element, or load, within bounded time. A
//! mutation test then feeds thousands of deterministic corruptions of
//! valid files to the loader: each must give `Ok` or `Err`, never a
//! panic.
mod gltf_files;

use gltf_files::{MeshData, test_dir, write_gltf};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Generous bound for "not a hang": the cases take milliseconds.
const HANG_GUARD: Duration = Duration::from_secs(20);

/// Triangles the description holds.
fn triangles(desc: &tyndall::description::SceneDesc) -> usize {
    desc.shapes.iter().map(|s| s.shapes.len()).sum()
}

fn triangle() -> MeshData {
    MeshData {
        positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        indices: Some(vec![0, 1, 2]),
        mode: None,
        material: Some(0),
        normals: None,
        uvs: None,
        colors: None,
        tangents: None,
    }
}

fn textured_triangle() -> MeshData {
    MeshData {
        uvs: Some(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
        colors: None,
        tangents: None,
        ..triangle()
    }
}

/// A scene of one triangle seen by a camera, with `edit` applied to the
/// JSON written by [`write_gltf`] (its accessors: 0 positions, 1
/// indices, 2 texture coordinates when `textured`).
fn write_edited(name: &str, textured: bool, edit: impl FnOnce(&mut Value)) -> PathBuf {
    let dir = test_dir(&format!("hostile-{name}"));
    let mesh = if textured {
        textured_triangle()
    } else {
        triangle()
    };
    let doc = json!({
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"translation": [0.2, 0.2, 3.0], "camera": 0}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "materials": [{}]
    });
    let path = write_gltf(&dir, name, &[mesh], doc);
    let mut doc: Value =
        serde_json::from_slice(&std::fs::read(&path).expect("read")).expect("json");
    edit(&mut doc);
    std::fs::write(&path, serde_json::to_vec_pretty(&doc).expect("json")).expect("write");
    path
}

/// Loads `path`, which must fail; returns the message after checking it
/// names the file and contains each of `expected`, within the hang guard.
fn refused(path: &Path, expected: &[&str]) -> String {
    let start = Instant::now();
    let result = tyndall_load::gltf::load(path);
    let elapsed = start.elapsed();
    assert!(elapsed < HANG_GUARD, "{}: took {elapsed:?}", path.display());
    let message = match result {
        Ok(_) => panic!("{}: a hostile file loaded", path.display()),
        Err(e) => e.to_string(),
    };
    println!("{message}");
    let file = path.file_name().and_then(|f| f.to_str()).unwrap_or("?");
    assert!(message.contains(file), "names the file: {message}");
    for e in expected {
        assert!(message.contains(e), "expected {e:?} in: {message}");
    }
    message
}

/// Gives material 0 a base colour texture of image `image`.
fn textured_material(doc: &mut Value, image: Value) {
    doc["images"] = json!([image]);
    doc["textures"] = json!([{"source": 0}]);
    doc["materials"] = json!([{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]);
}

/// A 2×2 PNG (red, green, blue, white), encoded in memory: the tests
/// that embed it run in parallel, and writing it to one shared file
/// raced (the writer refuses an existing file).
fn png_bytes() -> Vec<u8> {
    let texels = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]];
    let image = image::RgbImage::from_fn(2, 2, |x, y| image::Rgb(texels[(y * 2 + x) as usize]));
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, image::ImageFormat::Png)
        .expect("png");
    bytes.into_inner()
}

#[test]
fn position_naming_a_missing_accessor_is_refused() {
    let path = write_edited("missing-accessor", false, |doc| {
        doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(7);
    });
    refused(
        &path,
        &[
            "meshes[0].primitives[0].attributes.POSITION: accessor 7 does not exist (the file has 2)",
        ],
    );
}

#[test]
fn image_in_a_buffer_view_without_mime_type_is_refused() {
    let path = write_edited("no-mime", false, |doc| {
        textured_material(doc, json!({"bufferView": 0}));
    });
    refused(&path, &["images[0]", "mimeType"]);
}

#[test]
fn image_without_uri_or_buffer_view_is_refused() {
    let path = write_edited("no-source", false, |doc| {
        textured_material(doc, json!({"name": "nothing"}));
    });
    refused(&path, &["images[0]: an image needs a uri or a bufferView"]);
}

#[test]
fn camera_type_without_its_object_is_refused() {
    let path = write_edited("ortho-no-object", false, |doc| {
        doc["cameras"][0]["type"] = json!("orthographic");
    });
    refused(
        &path,
        &[
            "cameras[0]: the camera's type is \"orthographic\" but it has no \"orthographic\" object",
        ],
    );
}

#[test]
fn integer_texture_coordinates_are_refused() {
    // TEXCOORD_0 as VEC2 of u32 (componentType 5125), inside view 0.
    let path = write_edited("u32-uv", true, |doc| {
        textured_material(doc, json!({"uri": "t.png", "mimeType": "image/png"}));
        doc["accessors"][2]["componentType"] = json!(5125);
        doc["accessors"][2]["bufferView"] = json!(0);
    });
    refused(
        &path,
        &["meshes[0].primitives[0].attributes.TEXCOORD_0: accessor 2 must be VEC2 of floats"],
    );
}

/// A normal-mapped triangle whose TANGENT is a zero vector, or whose
/// TANGENT accessor is not VEC4 of floats, is refused naming the
/// primitive.
#[test]
fn tangents_that_make_no_frame_are_refused() {
    let dir = test_dir("hostile-tangent");
    std::fs::write(dir.join("t.png"), png_bytes()).expect("png");
    let doc = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "images": [{"uri": "t.png"}],
        "textures": [{"source": 0}],
        "materials": [{"normalTexture": {"index": 0}}]
    });
    let mesh = |tangent: [f32; 4]| MeshData {
        tangents: Some(vec![tangent; 3]),
        ..textured_triangle()
    };
    let zero = write_gltf(&dir, "zero", &[mesh([0.0, 0.0, 0.0, 1.0])], doc.clone());
    refused(&zero, &["meshes[0].primitives[0]", "tangent", "non-zero"]);
    let path = write_gltf(&dir, "vec3", &[mesh([1.0, 0.0, 0.0, 1.0])], doc);
    let mut edited: Value =
        serde_json::from_slice(&std::fs::read(&path).expect("read")).expect("json");
    let tangent = edited["meshes"][0]["primitives"][0]["attributes"]["TANGENT"].clone();
    edited["accessors"][tangent.as_u64().expect("index") as usize]["type"] = json!("VEC3");
    std::fs::write(&path, serde_json::to_vec(&edited).expect("json")).expect("write");
    refused(&path, &["TANGENT must be Vec4 of floats"]);
}

/// A normal texture whose vectors point into the surface (an all-black
/// image: (−1, −1, −1)) is no tangent-space normal map: the file loads,
/// the map is left out with a warning naming the material and its image,
/// and the surface keeps its own normal.
#[test]
fn an_all_black_normal_texture_is_named_and_left_out() {
    let dir = test_dir("hostile-black-normals");
    image::RgbImage::from_pixel(4, 4, image::Rgb([0, 0, 0]))
        .save(dir.join("black.png"))
        .expect("png");
    let doc = json!({
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "images": [{"uri": "black.png"}],
        "textures": [{"source": 0}],
        "materials": [{"normalTexture": {"index": 0}}]
    });
    let path = write_gltf(&dir, "black", &[textured_triangle()], doc);
    let loaded = tyndall_load::gltf::load(&path).expect("loads");
    assert!(
        loaded.warnings.iter().any(|w| w.contains("materials[0]")
            && w.contains("normalTexture")
            && w.contains("images[0]")),
        "{:?}",
        loaded.warnings
    );
    assert!(loaded.shapes.iter().all(|s| s.normal_map.is_none()));
}

#[test]
fn glb_image_view_past_its_buffer_is_refused() {
    let dir = test_dir("hostile-glb-view");
    let json = json!({
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": []}],
        "buffers": [{"byteLength": 8}],
        "bufferViews": [{"buffer": 0, "byteOffset": 4, "byteLength": 100}],
        "images": [{"bufferView": 0, "mimeType": "image/png"}]
    });
    let path = dir.join("view.glb");
    let bytes = tyndall_load::gltf::glb_bytes(json.to_string().as_bytes(), &[0; 8]);
    std::fs::write(&path, bytes).expect("write");
    refused(
        &path,
        &[
            "bufferViews[0]: byteOffset 4 + byteLength 100 runs past the end of buffers[0] (8 bytes)",
        ],
    );
}

#[test]
fn glb_header_claiming_4_gib_is_refused() {
    let dir = test_dir("hostile-glb-4gib");
    let mut bytes = tyndall_load::gltf::glb_bytes(br#"{"asset":{"version":"2.0"}}"#, &[]);
    bytes[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
    let path = dir.join("huge.glb");
    std::fs::write(&path, &bytes).expect("write");
    refused(
        &path,
        &[&format!(
            "claims 4294967295 bytes, but the file has {}",
            bytes.len()
        )],
    );
    // A chunk claiming more than the file holds.
    let mut bytes = tyndall_load::gltf::glb_bytes(br#"{"asset":{"version":"2.0"}}"#, &[1, 2, 3, 4]);
    let bin_chunk = bytes.len() - 12;
    bytes[bin_chunk..bin_chunk + 4].copy_from_slice(&0xFFFF_FFF0u32.to_le_bytes());
    std::fs::write(&path, &bytes).expect("write");
    refused(&path, &["chunk 1 claims 4294967280 bytes"]);
    // BIN shorter than buffer 0's byteLength.
    let json = br#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":64}]}"#;
    std::fs::write(&path, tyndall_load::gltf::glb_bytes(json, &[0; 8])).expect("write");
    refused(
        &path,
        &["buffers[0].byteLength: is 64 bytes but the GLB BIN chunk holds 8"],
    );
}

/// Nodes 0 → 1 → … → n−1, the last carrying the triangle; `fanout`
/// copies of each child link (2 makes a DAG of 2^(n−1) paths).
fn chain(name: &str, n: usize, fanout: usize) -> PathBuf {
    let dir = test_dir(&format!("hostile-{name}"));
    let mut nodes: Vec<Value> = (0..n - 1)
        .map(|i| json!({"children": vec![i + 1; fanout]}))
        .collect();
    nodes.push(json!({"mesh": 0}));
    write_gltf(
        &dir,
        name,
        &[triangle()],
        json!({"scenes": [{"nodes": [0]}], "nodes": nodes, "materials": [{}]}),
    )
}

#[test]
fn node_chain_30000_deep_loads_without_recursion() {
    let path = chain("deep-chain", 30_000, 1);
    let start = Instant::now();
    let desc = tyndall_load::gltf::load(&path).expect("a deep chain is a valid file");
    assert!(start.elapsed() < HANG_GUARD, "took {:?}", start.elapsed());
    assert_eq!(triangles(&desc), 1);
}

#[test]
fn node_dag_of_2_pow_26_instances_is_refused() {
    let path = chain("dag", 27, 2);
    refused(
        &path,
        &["nodes[", "expands to more than 1048576 node instances"],
    );
}

#[test]
fn node_cycle_is_refused() {
    let path = write_edited("cycle", false, |doc| {
        doc["nodes"] = json!([{"children": [2]}, {"camera": 0}, {"mesh": 0, "children": [0]}]);
    });
    refused(&path, &["nodes[0]: the node is its own ancestor (a cycle)"]);
}

#[test]
fn mesh_instances_past_the_triangle_cap_are_refused_before_generation() {
    // 2¹⁴ instances of a mesh claiming 2¹² triangles (a sparse index
    // accessor without a bufferView: zeros but for three): 2²⁶
    // triangles, refused by the count alone.
    let path = write_edited("tri-cap", false, |doc| {
        doc["accessors"][1] = json!({"componentType": 5125, "count": 3 << 12, "type": "SCALAR",
            "sparse": {"count": 3, "indices": {"bufferView": 1, "componentType": 5125},
                       "values": {"bufferView": 1}}});
        let mut nodes = vec![json!({"camera": 0})];
        nodes.extend((0..1 << 14).map(|_| json!({"mesh": 0})));
        let roots: Vec<usize> = (0..nodes.len()).collect();
        doc["nodes"] = Value::Array(nodes);
        doc["scenes"] = json!([{"nodes": roots}]);
    });
    refused(&path, &["more than 16777216 triangles"]);
    // 64 instances of a mesh of three triangles over 2²⁰ vertices (a
    // sparse POSITION): 2²⁶ vertices to read.
    let path = write_edited("vertex-cap", false, |doc| {
        doc["accessors"][0] = json!({"componentType": 5126, "count": 1 << 20, "type": "VEC3",
            "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0],
            "sparse": {"count": 3, "indices": {"bufferView": 1, "componentType": 5125},
                       "values": {"bufferView": 0}}});
        let mut nodes = vec![json!({"camera": 0})];
        nodes.extend((0..64).map(|_| json!({"mesh": 0})));
        let roots: Vec<usize> = (0..nodes.len()).collect();
        doc["nodes"] = Value::Array(nodes);
        doc["scenes"] = json!([{"nodes": roots}]);
    });
    refused(&path, &["nodes[33]", "more than 33554432 vertices"]);
    // One instance is within the limits: the sparse accessor reads as
    // zeros but for its three vertices, one triangle.
    let path = write_edited("sparse-one", false, |doc| {
        doc["accessors"][0] = json!({"componentType": 5126, "count": 1 << 20, "type": "VEC3",
            "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0],
            "sparse": {"count": 3, "indices": {"bufferView": 1, "componentType": 5125},
                       "values": {"bufferView": 0}}});
    });
    let desc = tyndall_load::gltf::load(&path).expect("a sparse POSITION loads");
    assert_eq!(triangles(&desc), 1);
}

#[test]
fn buffer_uri_naming_a_device_or_a_short_file_is_refused() {
    if Path::new("/dev/zero").exists() {
        let path = write_edited("dev-zero", false, |doc| {
            doc["buffers"]
                .as_array_mut()
                .expect("buffers")
                .push(json!({"uri": "/dev/zero", "byteLength": 4}));
        });
        refused(&path, &["buffers[1]: /dev/zero is not a regular file"]);
    }
    let path = write_edited("dir-buffer", false, |doc| {
        doc["buffers"][0]["uri"] = json!(".");
    });
    refused(&path, &["buffers[0]:", "is not a regular file"]);
    let path = write_edited("short-buffer", false, |doc| {
        let length = doc["buffers"][0]["byteLength"].as_u64().expect("length");
        doc["buffers"][0]["byteLength"] = json!(length + 4);
    });
    refused(
        &path,
        &["buffers[0]:", "shorter than the buffer's byteLength"],
    );
}

#[test]
fn buffer_file_longer_than_byte_length_loads() {
    let path = write_edited("long-buffer", false, |_| {});
    let bin = path.with_extension("bin");
    let mut bytes = std::fs::read(&bin).expect("bin");
    bytes.extend_from_slice(&[0xAB; 4096]);
    std::fs::write(&bin, bytes).expect("bin");
    let desc = tyndall_load::gltf::load(&path).expect("a longer buffer file loads");
    assert_eq!(triangles(&desc), 1);
}

#[test]
fn image_uri_naming_a_device_is_refused() {
    if Path::new("/dev/zero").exists() {
        let path = write_edited("dev-zero-image", true, |doc| {
            textured_material(doc, json!({"uri": "/dev/zero", "mimeType": "image/png"}));
        });
        refused(
            &path,
            &["materials[0]: images[0]: /dev/zero is not a regular file"],
        );
    }
    // A PNG header claiming 2¹⁶ × 2¹⁶ texels is refused from its header.
    let path = write_edited("huge-png", true, |doc| {
        textured_material(doc, json!({"uri": "huge.png"}));
    });
    // (IHDR: width, height at bytes 16..24, its CRC over type and data
    // at 29..33.)
    let mut png = png_bytes();
    png[16..20].copy_from_slice(&65535u32.to_be_bytes());
    png[20..24].copy_from_slice(&65535u32.to_be_bytes());
    let crc = crc32(&png[12..29]);
    png[29..33].copy_from_slice(&crc.to_be_bytes());
    std::fs::write(path.with_file_name("huge.png"), png).expect("png");
    refused(
        &path,
        &[
            "materials[0]: images[0]: the image is 65535×65535: at most 268435456 texels are supported",
        ],
    );
}

#[test]
fn textured_glb_with_embedded_png_loads() {
    let path = write_edited("glb-png", true, |doc| {
        textured_material(doc, json!({"bufferView": 3, "mimeType": "image/png"}));
    });
    let bytes = embed_png_as_glb(&path, &png_bytes());
    let glb = path.with_extension("glb");
    std::fs::write(&glb, &bytes).expect("glb");
    let desc = tyndall_load::gltf::load(&glb).expect("textured glb");
    assert_eq!(desc.textures.len(), 1);
}

/// The `.glb` of `path` (from [`write_edited`]) with `png` appended to
/// its buffer as bufferViews[3].
fn embed_png_as_glb(path: &Path, png: &[u8]) -> Vec<u8> {
    let mut doc: Value = serde_json::from_slice(&std::fs::read(path).expect("gltf")).expect("json");
    let mut bin = std::fs::read(path.with_extension("bin")).expect("bin");
    bin.resize(bin.len().div_ceil(4) * 4, 0);
    let offset = bin.len();
    bin.extend_from_slice(png);
    let views = doc["bufferViews"].as_array_mut().expect("views");
    while views.len() < 3 {
        views.push(json!({"buffer": 0, "byteLength": 4}));
    }
    views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": png.len()}));
    doc["buffers"] = json!([{"byteLength": bin.len()}]);
    tyndall_load::gltf::glb_bytes(&serde_json::to_vec(&doc).expect("json"), &bin)
}

#[test]
fn camera_errors_name_the_camera_and_its_node() {
    // 3.13 rad passes the loader's (0, π) but not the description's
    // (0°, 179°]: the error is located where the camera came from.
    let path = write_edited("yfov", false, |doc| {
        doc["cameras"][0]["perspective"]["yfov"] = json!(3.13);
    });
    refused(&path, &["cameras[0] (at nodes[1])"]);
    let path = write_edited("yfov-pi", false, |doc| {
        doc["cameras"][0]["perspective"]["yfov"] = json!(4.0);
    });
    refused(&path, &["cameras[0]: yfov must be in (0, π)"]);
}

#[test]
fn bytes_in_memory_need_a_directory_for_file_uris() {
    let path = write_edited("bytes", false, |_| {});
    let bytes = std::fs::read(&path).expect("gltf");
    let e = match tyndall_load::gltf::load_bytes(Path::new("mem.gltf"), &bytes, None) {
        Ok(_) => panic!("no directory to read the .bin from, yet it loaded"),
        Err(e) => e.to_string(),
    };
    assert!(
        e.contains("mem.gltf") && e.contains("buffers[0]") && e.contains("given as bytes"),
        "{e}"
    );
    let desc = tyndall_load::gltf::load_bytes(Path::new("mem.gltf"), &bytes, path.parent())
        .expect("loads with its directory");
    assert_eq!(triangles(&desc), 1);
}

/// CRC-32 (ISO 3309, as PNG chunks use it).
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// splitmix64: the mutations are the same on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const HOSTILE_NUMBERS: [&str; 7] = [
    "-1",
    "4294967295",
    "1e30",
    "0",
    "18446744073709551616",
    "3",
    "-0.0",
];

const HOSTILE_STRINGS: [&str; 30] = [
    "orthographic",
    "perspective",
    "spot",
    "directional",
    "image/png",
    "image/jpeg",
    "",
    "data:;base64,AAAA",
    "data:application/octet-stream;base64,",
    "/dev/zero",
    "..",
    "%zz",
    "file:///dev/zero",
    "http://example.com/a.bin",
    "VEC2",
    "MAT4",
    "SCALAR",
    "uri",
    "bufferView",
    "sparse",
    "mimeType",
    "TEXCOORD_0",
    "TEXCOORD_1",
    "NORMAL",
    "POSITION",
    "indices",
    "children",
    "KHR_lights_punctual",
    "KHR_materials_transmission",
    "baseColorTexture",
];

/// Byte ranges, start to end.
type Spans = Vec<(usize, usize)>;

/// Byte ranges of the JSON numbers in `text` and of its strings
/// (without their quotes).
fn tokens(text: &[u8]) -> (Spans, Spans) {
    let mut spans = Vec::new();
    let mut strings = Vec::new();
    let mut string_start = 0;
    let (mut i, mut in_string) = (0, false);
    while i < text.len() {
        let c = text[i];
        if in_string {
            if c == b'\\' {
                i += 1;
            } else if c == b'"' {
                in_string = false;
                strings.push((string_start, i));
            }
            i += 1;
        } else if c == b'"' {
            in_string = true;
            i += 1;
            string_start = i;
        } else if c == b'-' || c.is_ascii_digit() {
            let start = i;
            while i < text.len()
                && matches!(text[i], b'0'..=b'9' | b'-' | b'+' | b'.' | b'e' | b'E')
            {
                i += 1;
            }
            spans.push((start, i));
        } else {
            i += 1;
        }
    }
    (spans, strings)
}

/// One deterministic corruption of `seed`: byte flips, a truncation, or
/// (in its JSON) a number or string replaced by a hostile one.
fn mutate(seed: &[u8], glb: bool, rng: &mut Rng) -> Vec<u8> {
    let mut bytes = seed.to_vec();
    match rng.below(4) {
        0 => {
            for _ in 0..1 + rng.below(4) {
                let at = rng.below(bytes.len());
                bytes[at] ^= 1 << rng.below(8);
            }
        }
        1 => {
            let at = rng.below(bytes.len());
            bytes[at] = rng.next() as u8;
        }
        2 => bytes.truncate(rng.below(bytes.len())),
        _ => {
            // A number of the JSON (inside the seed, which may be a glb
            // holding it) replaced.
            let (offset, text) = if glb {
                let len = seed
                    .get(12..16)
                    .map_or(0, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
                match seed.get(20..20usize.saturating_add(len)) {
                    Some(text) if seed.len() >= 16 => (20, text),
                    _ => return bytes,
                }
            } else {
                (0, seed)
            };
            let (numbers, strings) = tokens(text);
            // A number, or a string's contents (keys included).
            let (spans, hostile): (_, &[&str]) = if rng.below(3) > 0 {
                (numbers, &HOSTILE_NUMBERS)
            } else {
                (strings, &HOSTILE_STRINGS)
            };
            if spans.is_empty() {
                return bytes;
            }
            let (start, end) = spans[rng.below(spans.len())];
            let with = hostile[rng.below(hostile.len())].as_bytes();
            let mut out = seed[..offset + start].to_vec();
            out.extend_from_slice(with);
            out.extend_from_slice(&seed[offset + end..]);
            // Keep a glb's lengths (the header and JSON chunk) in step.
            if glb && out.len() != seed.len() {
                let pad = (seed.len() as i64 - out.len() as i64).rem_euclid(4) as usize;
                let insert = offset + start + with.len();
                for _ in 0..pad {
                    out.insert(insert, b' ');
                }
                let grow = out.len() as i64 - seed.len() as i64;
                let total = (u32::from_le_bytes([seed[8], seed[9], seed[10], seed[11]]) as i64
                    + grow) as u32;
                let chunk = (u32::from_le_bytes([seed[12], seed[13], seed[14], seed[15]]) as i64
                    + grow) as u32;
                out[8..12].copy_from_slice(&total.to_le_bytes());
                out[12..16].copy_from_slice(&chunk.to_le_bytes());
            }
            return out;
        }
    }
    bytes
}

/// Thousands of deterministic corruptions of valid files — the test
/// scenes written here (plain, textured with an embedded PNG, as .gltf
/// and .glb) and Blender's fog room — each give `Ok` or `Err`, never a
/// panic, quickly.
#[test]
fn mutated_files_never_panic() {
    let textured = write_edited("mutate-tex", true, |doc| {
        textured_material(doc, json!({"bufferView": 3, "mimeType": "image/png"}));
    });
    let glb = embed_png_as_glb(&textured, &png_bytes());
    let plain = write_edited("mutate-plain", false, |_| {});
    let blender = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/blender/fog-room.gltf");
    let plain_dir = plain.parent().expect("dir").to_owned();
    let blender_dir = blender.parent().expect("dir").to_owned();
    let plain_glb = {
        let dir = test_dir("hostile-mutate-plain-glb");
        write_gltf(
            &dir,
            "p",
            &[triangle()],
            json!({"scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "materials": [{}]}),
        );
        std::fs::read(gltf_files::to_glb(&dir, "p")).expect("glb")
    };
    let seeds: Vec<(&str, Vec<u8>, bool, PathBuf)> = vec![
        (
            "plain.gltf",
            std::fs::read(&plain).expect("plain"),
            false,
            plain_dir,
        ),
        ("plain.glb", plain_glb, true, PathBuf::from("/nonexistent")),
        ("textured.glb", glb, true, PathBuf::from("/nonexistent")),
        (
            "fog-room.gltf",
            std::fs::read(&blender).expect("fog room"),
            false,
            blender_dir,
        ),
    ];
    // More for a longer local campaign:
    // TYNDALL_GLTF_MUTATIONS=100000 cargo test --release --test hostile_gltf.
    let per_seed: usize = std::env::var("TYNDALL_GLTF_MUTATIONS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1500);
    let seed: u64 = std::env::var("TYNDALL_GLTF_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(28);
    let mut rng = Rng(seed);
    let start = Instant::now();
    let (mut ok, mut err) = (0, 0);
    for (name, seed, glb, dir) in &seeds {
        // Unmutated, each seed loads.
        tyndall_load::gltf::load_bytes(Path::new(name), seed, Some(dir))
            .unwrap_or_else(|e| panic!("{name}: the seed does not load: {e}"));
        for i in 0..per_seed {
            let mut bytes = mutate(seed, *glb, &mut rng);
            // A quarter get a second mutation on top.
            if rng.below(4) == 0 && !bytes.is_empty() {
                bytes = mutate(&bytes, *glb, &mut rng);
            }
            let result = std::panic::catch_unwind(|| {
                tyndall_load::gltf::load_bytes(Path::new(name), &bytes, Some(dir)).map(|_| ())
            });
            match result {
                Ok(Ok(())) => ok += 1,
                Ok(Err(_)) => err += 1,
                Err(_) => {
                    let dump = std::env::temp_dir().join(format!("tyndall-panic-{i}-{name}"));
                    let _ = std::fs::write(&dump, &bytes);
                    panic!(
                        "{name}: mutation {i} panicked; written to {}",
                        dump.display()
                    );
                }
            }
        }
    }
    assert!(
        start.elapsed() < HANG_GUARD * 3,
        "took {:?}",
        start.elapsed()
    );
    // Both outcomes occur: the mutations are neither all harmless nor
    // all fatal.
    println!("{ok} mutations loaded, {err} refused");
    assert!(ok > 0 && err > 0, "{ok} loaded, {err} refused");
}
