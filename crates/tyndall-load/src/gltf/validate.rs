//! Checks of a glTF document's JSON made before the `gltf` crate sees it.
//!
//! The crate indexes its arrays with the indices a file gives and
//! unwraps properties the specification requires, so a small hostile file
//! makes it panic (a `POSITION` naming a missing accessor, an image with a
//! `bufferView` and no `mimeType`, a camera whose `type` has no matching
//! object, a texture-coordinate accessor of a type its reader does not
//! expect) or read past a buffer. Here the document is read as plain JSON
//! and every index is checked against the array it names, every buffer
//! view against its buffer and every accessor against its view, each
//! failure naming the element path (`meshes[0].primitives[0].attributes.POSITION`).
//! Section numbers are those of the glTF 2.0 specification.
//!
//! The check also returns the [`Outline`] the node walk needs: the node
//! graph and what each mesh costs, so that the walk's limits are applied
//! before any triangle is made.

use serde_json::{Map, Value};

/// A refusal: the element path and what is wrong with it.
#[derive(Debug)]
pub(super) struct Problem {
    pub element: String,
    pub message: String,
}

pub(super) fn problem(element: impl Into<String>, message: impl Into<String>) -> Problem {
    Problem {
        element: element.into(),
        message: message.into(),
    }
}

type Checked<T = ()> = Result<T, Problem>;

/// What the node walk needs to know before it starts, from a checked
/// document.
pub(super) struct Outline {
    /// Each node's children (§3.5.2).
    pub children: Vec<Vec<usize>>,
    /// Each node's mesh, if any.
    pub node_mesh: Vec<Option<usize>>,
    /// The root nodes of the scene to load: the default scene (`scene`),
    /// or else the first; `None` if the file has no scenes.
    pub roots: Option<Vec<usize>>,
    /// Each mesh's cost per instance: vertices read (the primitives'
    /// `POSITION` counts) and triangles made (index or vertex count / 3).
    pub mesh_cost: Vec<(u64, u64)>,
    /// Each KHR_lights_punctual light's measured profile, if its `extras`
    /// name one.
    pub light_profiles: Vec<Option<ProfileRef>>,
}

/// A measured (IES LM-63) profile a light's `extras` name, as the native
/// format's `ies` and `ies_rotate_deg` keys do: `"extras": {"ies":
/// "file.ies", "ies_rotate_deg": 30}` (the path relative to the glTF
/// file; the turn in degrees, in [−360, 360], 0 if absent).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct ProfileRef {
    pub file: String,
    pub rotate_deg: f32,
}

/// Bytes of one component of `componentType` (§3.6.2.2, table of
/// component types), `None` for an unknown type.
fn component_size(component_type: u64) -> Option<u64> {
    match component_type {
        5120 | 5121 => Some(1),
        5122 | 5123 => Some(2),
        5125 | 5126 => Some(4),
        _ => None,
    }
}

/// Components of an accessor `type` (§3.6.2.2).
fn multiplicity(kind: &str) -> Option<u64> {
    match kind {
        "SCALAR" => Some(1),
        "VEC2" => Some(2),
        "VEC3" => Some(3),
        "VEC4" | "MAT2" => Some(4),
        "MAT3" => Some(9),
        "MAT4" => Some(16),
        _ => None,
    }
}

/// The document being checked.
struct Doc<'a> {
    root: &'a Map<String, Value>,
    /// The GLB BIN chunk's length, when the document came in a `.glb`.
    bin_len: Option<u64>,
}

/// `value` as an object, or a problem naming `element`.
fn object<'a>(value: &'a Value, element: &str) -> Checked<&'a Map<String, Value>> {
    value
        .as_object()
        .ok_or_else(|| problem(element, "must be a JSON object"))
}

/// The array `key` of `object` (empty when absent).
fn array<'a>(object: &'a Map<String, Value>, key: &str, element: &str) -> Checked<&'a [Value]> {
    match object.get(key) {
        None => Ok(&[]),
        Some(Value::Array(items)) => Ok(items),
        Some(_) => Err(problem(element, "must be an array")),
    }
}

/// A non-negative integer property, if present.
fn integer(object: &Map<String, Value>, key: &str, element: &str) -> Checked<Option<u64>> {
    match object.get(key) {
        None => Ok(None),
        Some(v) => v.as_u64().map(Some).ok_or_else(|| {
            problem(
                format!("{element}.{key}"),
                format!("must be a non-negative integer, got {v}"),
            )
        }),
    }
}

/// An index into an array of `len` `what`s (§3.3: indices refer to the
/// top-level arrays), at `element`.
fn index(value: &Value, element: &str, what: &str, len: usize) -> Checked<usize> {
    let i = value.as_u64().ok_or_else(|| {
        problem(
            element,
            format!("must be the index of a {what}, got {value}"),
        )
    })?;
    if i >= len as u64 {
        return Err(problem(
            element,
            format!("{what} {i} does not exist (the file has {len})"),
        ));
    }
    Ok(i as usize)
}

/// The optional index property `key` of `object` at `element`.
fn index_of(
    object: &Map<String, Value>,
    key: &str,
    element: &str,
    what: &str,
    len: usize,
) -> Checked<Option<usize>> {
    object
        .get(key)
        .map(|v| index(v, &format!("{element}.{key}"), what, len))
        .transpose()
}

impl Doc<'_> {
    fn len(&self, key: &str) -> usize {
        self.root
            .get(key)
            .and_then(Value::as_array)
            .map_or(0, Vec::len)
    }

    fn items(&self, key: &str) -> Checked<&[Value]> {
        array(self.root, key, key)
    }

    /// Buffers (§3.6.1): a positive `byteLength`; without `uri` only
    /// buffer 0 of a `.glb`, which its BIN chunk must cover (§4.4.3.3).
    fn buffers(&self) -> Checked<Vec<u64>> {
        let mut lengths = Vec::new();
        for (i, buffer) in self.items("buffers")?.iter().enumerate() {
            let element = format!("buffers[{i}]");
            let buffer = object(buffer, &element)?;
            let length = integer(buffer, "byteLength", &element)?
                .ok_or_else(|| problem(&element, "byteLength is required"))?;
            if length == 0 {
                return Err(problem(
                    format!("{element}.byteLength"),
                    "must be at least 1",
                ));
            }
            match buffer.get("uri") {
                Some(Value::String(_)) => {}
                Some(other) => {
                    return Err(problem(
                        format!("{element}.uri"),
                        format!("must be a string, got {other}"),
                    ));
                }
                None => match self.bin_len {
                    Some(bin) if i == 0 => {
                        if bin < length {
                            return Err(problem(
                                format!("{element}.byteLength"),
                                format!(
                                    "is {length} bytes but the GLB BIN chunk holds {bin} (glTF §4.4.3.3)"
                                ),
                            ));
                        }
                    }
                    Some(_) => {
                        return Err(problem(
                            &element,
                            "only buffer 0 may refer to the GLB BIN chunk: the buffer needs a uri",
                        ));
                    }
                    None if i == 0 && self.bin_len.is_none() => {
                        return Err(problem(
                            &element,
                            "the buffer has no uri and the file has no GLB BIN chunk",
                        ));
                    }
                    None => return Err(problem(&element, "the buffer has no uri")),
                },
            }
            lengths.push(length);
        }
        Ok(lengths)
    }

    /// Buffer views (§3.6.2.4): inside their buffer, with a
    /// `byteStride` of 4 to 252 if any. Returns (length, stride) of each.
    fn views(&self, buffers: &[u64]) -> Checked<Vec<(u64, Option<u64>)>> {
        let mut views = Vec::new();
        for (i, view) in self.items("bufferViews")?.iter().enumerate() {
            let element = format!("bufferViews[{i}]");
            let view = object(view, &element)?;
            let buffer = index_of(view, "buffer", &element, "buffer", buffers.len())?
                .ok_or_else(|| problem(&element, "buffer is required"))?;
            let offset = integer(view, "byteOffset", &element)?.unwrap_or(0);
            let length = integer(view, "byteLength", &element)?
                .ok_or_else(|| problem(&element, "byteLength is required"))?;
            if length == 0 {
                return Err(problem(
                    format!("{element}.byteLength"),
                    "must be at least 1",
                ));
            }
            let end = offset.checked_add(length);
            if end.is_none_or(|end| end > buffers[buffer]) {
                return Err(problem(
                    &element,
                    format!(
                        "byteOffset {offset} + byteLength {length} runs past the end of buffers[{buffer}] ({} bytes)",
                        buffers[buffer]
                    ),
                ));
            }
            let stride = integer(view, "byteStride", &element)?;
            if let Some(s) = stride
                && !(4..=252).contains(&s)
            {
                return Err(problem(
                    format!("{element}.byteStride"),
                    format!("must be between 4 and 252, got {s}"),
                ));
            }
            views.push((length, stride));
        }
        Ok(views)
    }

    /// Accessors (§3.6.2): a known type, `count` ≥ 1, and every
    /// element inside its view: `byteOffset + stride·(count − 1) + size ≤
    /// byteLength` with the view's stride no shorter than an element;
    /// sparse indices and values likewise (§3.6.2.3). Returns each
    /// accessor's (componentType, type, normalized, count).
    fn accessors(&self, views: &[(u64, Option<u64>)]) -> Checked<Vec<AccessorInfo>> {
        let mut accessors = Vec::new();
        for (i, accessor) in self.items("accessors")?.iter().enumerate() {
            let element = format!("accessors[{i}]");
            let accessor = object(accessor, &element)?;
            let component_type = integer(accessor, "componentType", &element)?
                .ok_or_else(|| problem(&element, "componentType is required"))?;
            let component = component_size(component_type).ok_or_else(|| {
                problem(
                    format!("{element}.componentType"),
                    format!("{component_type} is not a glTF component type"),
                )
            })?;
            let kind = accessor
                .get("type")
                .and_then(Value::as_str)
                .ok_or_else(|| problem(&element, "type is required (\"SCALAR\", \"VEC3\", …)"))?;
            let n = multiplicity(kind).ok_or_else(|| {
                problem(
                    format!("{element}.type"),
                    format!("\"{kind}\" is not an accessor type"),
                )
            })?;
            let count = integer(accessor, "count", &element)?
                .ok_or_else(|| problem(&element, "count is required"))?;
            if count == 0 {
                return Err(problem(format!("{element}.count"), "must be at least 1"));
            }
            let size = component * n;
            let offset = integer(accessor, "byteOffset", &element)?.unwrap_or(0);
            let view = index_of(accessor, "bufferView", &element, "buffer view", views.len())?;
            if let Some(v) = view {
                fits(&element, "the accessor", views[v], v, offset, count, size)?;
            }
            if let Some(sparse) = accessor.get("sparse") {
                let element = format!("{element}.sparse");
                let sparse = object(sparse, &element)?;
                let sparse_count = integer(sparse, "count", &element)?
                    .ok_or_else(|| problem(&element, "count is required"))?;
                if sparse_count == 0 || sparse_count > count {
                    return Err(problem(
                        format!("{element}.count"),
                        format!(
                            "must be between 1 and the accessor's count {count}, got {sparse_count}"
                        ),
                    ));
                }
                for (part, element_size) in [("indices", None), ("values", Some(size))] {
                    let element = format!("{element}.{part}");
                    let part = object(
                        sparse
                            .get(part)
                            .ok_or_else(|| problem(&element, "is required"))?,
                        &element,
                    )?;
                    let size = match element_size {
                        Some(size) => size,
                        None => {
                            let t = integer(part, "componentType", &element)?
                                .ok_or_else(|| problem(&element, "componentType is required"))?;
                            match t {
                                5121 | 5123 | 5125 => component_size(t).unwrap_or(4),
                                _ => {
                                    return Err(problem(
                                        format!("{element}.componentType"),
                                        format!(
                                            "sparse indices must be unsigned byte, short or int (5121, 5123, 5125), got {t}"
                                        ),
                                    ));
                                }
                            }
                        }
                    };
                    let v = index_of(part, "bufferView", &element, "buffer view", views.len())?
                        .ok_or_else(|| problem(&element, "bufferView is required"))?;
                    let offset = integer(part, "byteOffset", &element)?.unwrap_or(0);
                    fits(
                        &element,
                        "the sparse data",
                        views[v],
                        v,
                        offset,
                        sparse_count,
                        size,
                    )?;
                }
            }
            accessors.push(AccessorInfo {
                component_type,
                kind: kind.to_string(),
                normalized: accessor.get("normalized") == Some(&Value::Bool(true)),
                count,
            });
        }
        Ok(accessors)
    }
}

/// One checked accessor.
pub(super) struct AccessorInfo {
    component_type: u64,
    kind: String,
    normalized: bool,
    count: u64,
}

/// Checks that `count` elements of `size` bytes from `offset` lie inside
/// view `v` (length, stride): the crate reads element k at
/// `offset + stride·k`.
fn fits(
    element: &str,
    what: &str,
    (length, stride): (u64, Option<u64>),
    v: usize,
    offset: u64,
    count: u64,
    size: u64,
) -> Checked {
    let stride = stride.unwrap_or(size);
    if stride < size {
        return Err(problem(
            element,
            format!(
                "bufferViews[{v}].byteStride {stride} is shorter than an element ({size} bytes)"
            ),
        ));
    }
    let end = (count - 1)
        .checked_mul(stride)
        .and_then(|s| s.checked_add(offset))
        .and_then(|s| s.checked_add(size));
    if end.is_none_or(|end| end > length) {
        return Err(problem(
            element,
            format!(
                "{what} ({count} elements of {size} bytes, {stride} apart, from byte {offset}) runs past the end of bufferViews[{v}] ({length} bytes)"
            ),
        ));
    }
    Ok(())
}

/// Checks the document `root` (the JSON of a `.gltf`, or a `.glb`'s JSON
/// chunk, whose BIN chunk holds `bin_len` bytes) and returns its
/// [`Outline`].
pub(super) fn check(root: &Value, bin_len: Option<u64>) -> Checked<Outline> {
    let root = object(root, "the document")?;
    let doc = Doc { root, bin_len };
    let buffers = doc.buffers()?;
    let views = doc.views(&buffers)?;
    let accessors = doc.accessors(&views)?;
    let n_nodes = doc.len("nodes");
    let n_meshes = doc.len("meshes");
    let n_textures = doc.len("textures");

    // Images (§3.8.3): a uri or a bufferView with a mimeType.
    for (i, image) in doc.items("images")?.iter().enumerate() {
        let element = format!("images[{i}]");
        let image = object(image, &element)?;
        let view = index_of(image, "bufferView", &element, "buffer view", views.len())?;
        match (image.get("uri"), view) {
            (Some(Value::String(_)), None) => {}
            (Some(_), None) => {
                return Err(problem(format!("{element}.uri"), "must be a string"));
            }
            (None, Some(_)) => {
                if !matches!(image.get("mimeType"), Some(Value::String(_))) {
                    return Err(problem(
                        &element,
                        "an image in a bufferView must have a mimeType (glTF §3.8.3)",
                    ));
                }
            }
            (Some(_), Some(_)) => {
                return Err(problem(
                    &element,
                    "an image has a uri or a bufferView, not both",
                ));
            }
            (None, None) => {
                return Err(problem(&element, "an image needs a uri or a bufferView"));
            }
        }
    }

    // Textures (§3.8.4) and samplers.
    let n_images = doc.len("images");
    let n_samplers = doc.len("samplers");
    for (i, texture) in doc.items("textures")?.iter().enumerate() {
        let element = format!("textures[{i}]");
        let texture = object(texture, &element)?;
        index_of(texture, "source", &element, "image", n_images)?
            .ok_or_else(|| problem(&element, "the texture has no source image"))?;
        index_of(texture, "sampler", &element, "sampler", n_samplers)?;
    }

    // Materials (§3.9): every textureInfo's index, in the core
    // properties and in extensions alike (any object under a key ending
    // in "Texture").
    for (i, material) in doc.items("materials")?.iter().enumerate() {
        texture_refs(material, &format!("materials[{i}]"), n_textures)?;
    }

    // Cameras (§3.10): the object its type names.
    for (i, camera) in doc.items("cameras")?.iter().enumerate() {
        let element = format!("cameras[{i}]");
        let camera = object(camera, &element)?;
        let kind = camera.get("type").and_then(Value::as_str).ok_or_else(|| {
            problem(
                &element,
                "type is required (\"perspective\" or \"orthographic\")",
            )
        })?;
        if kind != "perspective" && kind != "orthographic" {
            return Err(problem(
                format!("{element}.type"),
                format!("must be \"perspective\" or \"orthographic\", got \"{kind}\""),
            ));
        }
        if !matches!(camera.get(kind), Some(Value::Object(_))) {
            return Err(problem(
                &element,
                format!("the camera's type is \"{kind}\" but it has no \"{kind}\" object"),
            ));
        }
    }

    // KHR_lights_punctual lights: a spot has its "spot" object.
    let lights: &[Value] = match root
        .get("extensions")
        .and_then(|e| e.get("KHR_lights_punctual"))
    {
        Some(ext) => array(
            object(ext, "extensions.KHR_lights_punctual")?,
            "lights",
            "extensions.KHR_lights_punctual.lights",
        )?,
        None => &[],
    };
    let mut light_profiles = Vec::with_capacity(lights.len());
    for (i, light) in lights.iter().enumerate() {
        let element = format!("KHR_lights_punctual.lights[{i}]");
        let light = object(light, &element)?;
        if light.get("type").and_then(Value::as_str) == Some("spot")
            && !matches!(light.get("spot"), Some(Value::Object(_)))
        {
            return Err(problem(&element, "a spot light needs its \"spot\" object"));
        }
        light_profiles.push(profile_ref(light.get("extras"), &element)?);
    }

    // Meshes (§3.7.2).
    let n_materials = doc.len("materials");
    let mut mesh_cost = Vec::new();
    for (m, mesh) in doc.items("meshes")?.iter().enumerate() {
        let element = format!("meshes[{m}]");
        let mesh = object(mesh, &element)?;
        let (mut vertices, mut triangles) = (0u64, 0u64);
        for (p, primitive) in array(mesh, "primitives", &element)?.iter().enumerate() {
            let element = format!("{element}.primitives[{p}]");
            let primitive = object(primitive, &element)?;
            let attributes = object(
                primitive
                    .get("attributes")
                    .ok_or_else(|| problem(&element, "attributes is required"))?,
                &format!("{element}.attributes"),
            )?;
            let mut count = None;
            for (name, value) in attributes {
                let at = format!("{element}.attributes.{name}");
                let a = index(value, &at, "accessor", accessors.len())?;
                let info = &accessors[a];
                // All attributes of a primitive have the same count (§3.7.2.1).
                match count {
                    None => count = Some((name, info.count)),
                    Some((first, c)) if c != info.count => {
                        return Err(problem(
                            &at,
                            format!(
                                "accessor {a} has {} elements but {first} has {c}: a primitive's attributes must have the same count",
                                info.count
                            ),
                        ));
                    }
                    Some(_) => {}
                }
                // TEXCOORD_n: float, or normalized unsigned byte or short
                // (§3.7.2.1, table of attribute types).
                if name.starts_with("TEXCOORD_") {
                    let ok = info.kind == "VEC2"
                        && (info.component_type == 5126
                            || (info.normalized && matches!(info.component_type, 5121 | 5123)));
                    if !ok {
                        return Err(problem(
                            &at,
                            format!(
                                "accessor {a} must be VEC2 of floats or of normalized unsigned bytes or shorts, got {} of componentType {}{}",
                                info.kind,
                                info.component_type,
                                if info.normalized { " (normalized)" } else { "" }
                            ),
                        ));
                    }
                }
            }
            let positions = match attributes.get("POSITION") {
                Some(v) => v.as_u64().map_or(0, |a| accessors[a as usize].count),
                None => 0,
            };
            let indices = index_of(primitive, "indices", &element, "accessor", accessors.len())?;
            if let Some(a) = indices {
                let info = &accessors[a];
                if info.kind != "SCALAR" || !matches!(info.component_type, 5121 | 5123 | 5125) {
                    return Err(problem(
                        format!("{element}.indices"),
                        format!(
                            "accessor {a} must be SCALAR of unsigned bytes, shorts or ints, got {} of componentType {}",
                            info.kind, info.component_type
                        ),
                    ));
                }
            }
            index_of(primitive, "material", &element, "material", n_materials)?;
            for (t, target) in array(primitive, "targets", &element)?.iter().enumerate() {
                let at = format!("{element}.targets[{t}]");
                for (name, value) in object(target, &at)? {
                    index(value, &format!("{at}.{name}"), "accessor", accessors.len())?;
                }
            }
            vertices = vertices.saturating_add(positions);
            let corners = indices.map_or(positions, |a| accessors[a].count);
            triangles = triangles.saturating_add(corners / 3);
        }
        mesh_cost.push((vertices, triangles));
    }

    // Skins (§3.7.3) and animations (§3.11).
    for (i, skin) in doc.items("skins")?.iter().enumerate() {
        let element = format!("skins[{i}]");
        let skin = object(skin, &element)?;
        index_of(
            skin,
            "inverseBindMatrices",
            &element,
            "accessor",
            accessors.len(),
        )?;
        index_of(skin, "skeleton", &element, "node", n_nodes)?;
        for (j, joint) in array(skin, "joints", &element)?.iter().enumerate() {
            index(joint, &format!("{element}.joints[{j}]"), "node", n_nodes)?;
        }
    }
    for (i, animation) in doc.items("animations")?.iter().enumerate() {
        let element = format!("animations[{i}]");
        let animation = object(animation, &element)?;
        let samplers = array(animation, "samplers", &element)?;
        for (s, sampler) in samplers.iter().enumerate() {
            let at = format!("{element}.samplers[{s}]");
            let sampler = object(sampler, &at)?;
            index_of(sampler, "input", &at, "accessor", accessors.len())?;
            index_of(sampler, "output", &at, "accessor", accessors.len())?;
        }
        for (c, channel) in array(animation, "channels", &element)?.iter().enumerate() {
            let at = format!("{element}.channels[{c}]");
            let channel = object(channel, &at)?;
            index_of(channel, "sampler", &at, "animation sampler", samplers.len())?;
            if let Some(target) = channel.get("target") {
                let at = format!("{at}.target");
                index_of(object(target, &at)?, "node", &at, "node", n_nodes)?;
            }
        }
    }

    // Nodes (§3.5).
    let n_cameras = doc.len("cameras");
    let n_skins = doc.len("skins");
    let mut children = Vec::new();
    let mut node_mesh = Vec::new();
    for (i, node) in doc.items("nodes")?.iter().enumerate() {
        let element = format!("nodes[{i}]");
        let node = object(node, &element)?;
        let kids = array(node, "children", &element)?
            .iter()
            .enumerate()
            .map(|(c, child)| index(child, &format!("{element}.children[{c}]"), "node", n_nodes))
            .collect::<Checked<Vec<usize>>>()?;
        if kids.contains(&i) {
            return Err(problem(&element, "the node is its own child (a cycle)"));
        }
        children.push(kids);
        node_mesh.push(index_of(node, "mesh", &element, "mesh", n_meshes)?);
        index_of(node, "camera", &element, "camera", n_cameras)?;
        index_of(node, "skin", &element, "skin", n_skins)?;
        if let Some(ext) = node
            .get("extensions")
            .and_then(|e| e.get("KHR_lights_punctual"))
        {
            let at = format!("{element}.extensions.KHR_lights_punctual");
            index_of(
                object(ext, &at)?,
                "light",
                &at,
                "KHR_lights_punctual light",
                lights.len(),
            )?;
        }
    }

    // Scenes (§3.5.1).
    let scenes = doc.items("scenes")?;
    let mut scene_roots = Vec::new();
    for (i, scene) in scenes.iter().enumerate() {
        let element = format!("scenes[{i}]");
        let scene = object(scene, &element)?;
        let roots = array(scene, "nodes", &element)?
            .iter()
            .enumerate()
            .map(|(n, node)| index(node, &format!("{element}.nodes[{n}]"), "node", n_nodes))
            .collect::<Checked<Vec<usize>>>()?;
        scene_roots.push(roots);
    }
    let default = root
        .get("scene")
        .map(|v| index(v, "scene", "scene", scenes.len()))
        .transpose()?;
    let roots = match default {
        Some(s) => scene_roots.into_iter().nth(s),
        None => scene_roots.into_iter().next(),
    };
    Ok(Outline {
        children,
        node_mesh,
        roots,
        mesh_cost,
        light_profiles,
    })
}

/// The measured profile a light's `extras` name ([`ProfileRef`]); extras
/// that are not an object, or hold neither key, name none.
fn profile_ref(extras: Option<&Value>, element: &str) -> Checked<Option<ProfileRef>> {
    let Some(Value::Object(extras)) = extras else {
        return Ok(None);
    };
    let rotate_deg = match extras.get("ies_rotate_deg") {
        None => 0.0,
        Some(v) => match v.as_f64() {
            Some(r) if (-360.0..=360.0).contains(&r) => r as f32,
            _ => {
                return Err(problem(
                    format!("{element}.extras.ies_rotate_deg"),
                    "must be an angle in [−360°, 360°]",
                ));
            }
        },
    };
    match extras.get("ies") {
        None if extras.contains_key("ies_rotate_deg") => Err(problem(
            format!("{element}.extras.ies_rotate_deg"),
            "turns what `ies` names, and there is no `ies`",
        )),
        None => Ok(None),
        Some(Value::String(file)) => Ok(Some(ProfileRef {
            file: file.clone(),
            rotate_deg,
        })),
        Some(_) => Err(problem(
            format!("{element}.extras.ies"),
            "must be a string naming an .ies file",
        )),
    }
}

/// Checks every textureInfo under `value` (an object under a key ending
/// in `Texture`) names an existing texture; `extras` are skipped.
fn texture_refs(value: &Value, element: &str, n_textures: usize) -> Checked {
    match value {
        Value::Object(map) => {
            for (key, v) in map {
                let at = format!("{element}.{key}");
                if key == "extras" {
                    // Application-specific data, not read.
                    continue;
                }
                if key.ends_with("Texture") {
                    let info = object(v, &at)?;
                    index_of(info, "index", &at, "texture", n_textures)?
                        .ok_or_else(|| problem(&at, "index is required"))?;
                    integer(info, "texCoord", &at)?;
                } else {
                    texture_refs(v, &at, n_textures)?;
                }
            }
            Ok(())
        }
        Value::Array(items) => {
            for (i, v) in items.iter().enumerate() {
                texture_refs(v, &format!("{element}[{i}]"), n_textures)?;
            }
            Ok(())
        }
        _ => Ok(()),
    }
}
