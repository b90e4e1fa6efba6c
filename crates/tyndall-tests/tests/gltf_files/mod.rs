//! Writes small glTF files for the tests: the test gives the JSON of
//! nodes, cameras, materials and extensions; [`write_gltf`] adds the
//! meshes' buffers, views and accessors and writes `.gltf` + `.bin`.
#![allow(dead_code)]

use serde_json::{Value, json};
use std::f32::consts::FRAC_1_SQRT_2;
use std::path::{Path, PathBuf};

/// One triangle-list primitive (its own mesh).
pub struct MeshData {
    pub positions: Vec<[f32; 3]>,
    pub indices: Option<Vec<u32>>,
    /// glTF primitive mode; 4 (triangles) when `None`.
    pub mode: Option<u32>,
    pub material: Option<usize>,
    /// Vertex normals (the NORMAL attribute), one per position.
    pub normals: Option<Vec<[f32; 3]>>,
    /// Texture coordinates (the TEXCOORD_0 attribute), one per position.
    pub uvs: Option<Vec<[f32; 2]>>,
    /// Vertex colours (the COLOR_0 attribute, linear RGB floats), one
    /// per position.
    pub colors: Option<Vec<[f32; 3]>>,
    /// Tangents and their handedness (the TANGENT attribute), one per
    /// position.
    pub tangents: Option<Vec<[f32; 4]>>,
}

/// A fresh directory for one test's files.
pub fn test_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tyndall-load-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Writes `dir/name.gltf` and `dir/name.bin`: `doc` with `meshes`,
/// `buffers`, `bufferViews` and `accessors` filled from `meshes` (mesh i
/// is `meshes[i]`).
pub fn write_gltf(dir: &Path, name: &str, meshes: &[MeshData], mut doc: Value) -> PathBuf {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut gltf_meshes = Vec::new();
    for mesh in meshes {
        let (mut min, mut max) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in &mesh.positions {
            for k in 0..3 {
                min[k] = min[k].min(p[k]);
                max[k] = max[k].max(p[k]);
            }
        }
        let position = push_floats(
            &mut (&mut bin, &mut views, &mut accessors),
            &mesh.positions,
            "VEC3",
        );
        accessors[position]["min"] = json!(min);
        accessors[position]["max"] = json!(max);
        let mut attributes = json!({"attributes": {"POSITION": accessors.len() - 1}});
        if let Some(indices) = &mesh.indices {
            let offset = bin.len();
            for i in indices {
                bin.extend_from_slice(&i.to_le_bytes());
            }
            views
                .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": bin.len() - offset}));
            accessors.push(json!({
                "bufferView": views.len() - 1, "componentType": 5125,
                "count": indices.len(), "type": "SCALAR"
            }));
            attributes["indices"] = json!(accessors.len() - 1);
        }
        let mut buffers = (&mut bin, &mut views, &mut accessors);
        if let Some(normals) = &mesh.normals {
            attributes["attributes"]["NORMAL"] = json!(push_floats(&mut buffers, normals, "VEC3"));
        }
        if let Some(uvs) = &mesh.uvs {
            attributes["attributes"]["TEXCOORD_0"] = json!(push_floats(&mut buffers, uvs, "VEC2"));
        }
        if let Some(colors) = &mesh.colors {
            attributes["attributes"]["COLOR_0"] = json!(push_floats(&mut buffers, colors, "VEC3"));
        }
        if let Some(tangents) = &mesh.tangents {
            attributes["attributes"]["TANGENT"] =
                json!(push_floats(&mut buffers, tangents, "VEC4"));
        }
        if let Some(mode) = mesh.mode {
            attributes["mode"] = json!(mode);
        }
        if let Some(material) = mesh.material {
            attributes["material"] = json!(material);
        }
        gltf_meshes.push(json!({"primitives": [attributes]}));
    }
    let bin_name = format!("{name}.bin");
    std::fs::write(dir.join(&bin_name), &bin).expect("write .bin");
    doc["asset"] = json!({"version": "2.0"});
    doc["buffers"] = json!([{"uri": bin_name, "byteLength": bin.len()}]);
    doc["bufferViews"] = Value::Array(views);
    doc["accessors"] = Value::Array(accessors);
    doc["meshes"] = Value::Array(gltf_meshes);
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, serde_json::to_string_pretty(&doc).expect("json")).expect("write .gltf");
    path
}

/// The binary buffer, buffer views and accessors being written.
type Buffers<'a> = (&'a mut Vec<u8>, &'a mut Vec<Value>, &'a mut Vec<Value>);

/// Appends `values` (little-endian f32) to the buffer with a view and a
/// FLOAT accessor of type `kind` over them; returns the accessor's index.
fn push_floats<const N: usize>(
    (bin, views, accessors): &mut Buffers,
    values: &[[f32; N]],
    kind: &str,
) -> usize {
    let offset = bin.len();
    for value in values {
        for c in value {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": bin.len() - offset}));
    accessors.push(json!({
        "bufferView": views.len() - 1, "componentType": 5126,
        "count": values.len(), "type": kind
    }));
    accessors.len() - 1
}

/// Rewrites `dir/name.gltf` + `.bin` (from [`write_gltf`]) as one binary
/// `dir/name.glb`: header, JSON chunk, BIN chunk (glTF §4.4).
pub fn to_glb(dir: &Path, name: &str) -> PathBuf {
    let mut doc: Value =
        serde_json::from_slice(&std::fs::read(dir.join(format!("{name}.gltf"))).expect("gltf"))
            .expect("json");
    let bin = std::fs::read(dir.join(format!("{name}.bin"))).expect("bin");
    doc["buffers"][0]
        .as_object_mut()
        .expect("buffer")
        .remove("uri");
    let json = serde_json::to_vec(&doc).expect("json");
    let path = dir.join(format!("{name}.glb"));
    std::fs::write(&path, tyndall_load::gltf::glb_bytes(&json, &bin)).expect("write glb");
    path
}

/// A glTF document of meshes `0..meshes` (a node each) under a sun
/// straight down of 683 lx (E = 1 W/m² at 683 lm/W), with `more`'s
/// members (images, samplers, textures, materials) added.
pub fn sunlit(meshes: usize, more: Value) -> Value {
    let s = FRAC_1_SQRT_2;
    let mut nodes: Vec<Value> = (0..meshes).map(|m| json!({"mesh": m})).collect();
    nodes.push(json!({"rotation": [-s, 0.0, 0.0, s],
                      "extensions": {"KHR_lights_punctual": {"light": 0}}}));
    let mut doc = json!({
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular", "KHR_texture_transform"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 683.0}]}},
        "scenes": [{"nodes": (0..=meshes).collect::<Vec<_>>()}],
        "nodes": nodes,
    });
    for (key, value) in more.as_object().expect("members") {
        doc[key] = value.clone();
    }
    doc
}

/// A square of half-side `r` at height `h`, facing up, of `material`,
/// with texture coordinates `uv(corner)` if given.
pub fn square(h: f32, r: f32, material: usize, uv: Option<fn([f32; 3]) -> [f32; 2]>) -> MeshData {
    let positions = vec![[-r, h, -r], [r, h, -r], [r, h, r], [-r, h, r]];
    MeshData {
        uvs: uv.map(|uv| positions.iter().map(|&p| uv(p)).collect()),
        positions,
        indices: Some(vec![0, 2, 1, 0, 3, 2]),
        mode: None,
        material: Some(material),
        normals: None,
        colors: None,
        tangents: None,
    }
}

/// Texture coordinates spreading an image over the 4 × 4 floor: u along
/// x, v along z.
pub fn floor_uv(p: [f32; 3]) -> [f32; 2] {
    [(p[0] + 2.0) / 4.0, (p[2] + 2.0) / 4.0]
}

/// Adds to `doc` (as [`sunlit`] makes it) a camera `height` above the
/// origin looking straight down (its −z turned to −y), of vertical field
/// of view `yfov` radians and a square image.
pub fn camera_looking_down(doc: &mut Value, height: f32, yfov: f32) {
    let s = FRAC_1_SQRT_2;
    doc["cameras"] = json!([{"type": "perspective",
                             "perspective": {"yfov": yfov, "aspectRatio": 1.0, "znear": 0.01}}]);
    let nodes = doc["nodes"].as_array_mut().expect("nodes");
    nodes.push(
        json!({"camera": 0, "translation": [0.0, height, 0.0], "rotation": [-s, 0.0, 0.0, s]}),
    );
    let camera = nodes.len() - 1;
    doc["scenes"][0]["nodes"]
        .as_array_mut()
        .expect("scene")
        .push(json!(camera));
}
