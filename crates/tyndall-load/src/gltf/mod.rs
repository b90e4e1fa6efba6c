//! glTF 2.0 scenes (`.gltf` with its buffers, `.glb`), read with the
//! `gltf` crate, as documented in docs/scene-format.md ("glTF input").
//!
//! The default scene's node hierarchy is walked with each node's world
//! matrix `M_world = M_parent · M_local` (glTF §3.5.2, `M_local = T·R·S` or
//! the node's matrix). Triangle primitives become triangles, the first
//! camera met in the walk becomes the camera, KHR_lights_punctual lights
//! become point, spot and directional lights (photometric units converted
//! by [`crate::photometry`]) and materials map to Tyndall's closed set
//! (`materials.rs`). Errors name the file and the
//! element (`meshes[2].primitives[0]`, `nodes[3]`, `materials[1]`).
//!
//! No file may crash, hang or exhaust memory: a `.glb` container is
//! parsed with its lengths checked (`glb.rs`), the JSON is checked before
//! the `gltf` crate indexes it (`validate.rs`: every index, every buffer
//! view and accessor inside what it refers to), buffers and images are
//! read with bounds (`sources.rs`: regular files only, no more than
//! `byteLength`), the node walk is iterative with a cycle check, and what
//! the hierarchy expands to is bounded ([`MAX_NODE_INSTANCES`],
//! [`MAX_TRIANGLES`], [`MAX_VERTICES`]) before any triangle is made.
//! [`load_bytes`] and [`add_bytes_to_scene`] read a document from memory
//! (for fuzzers).

mod glb;
mod materials;
mod mesh;
mod sources;
mod tangents;
mod textures;
mod validate;

pub use glb::glb_bytes;

use materials::MaterialTextures;

use crate::files::ReadOnce;
use crate::ies::IesFile;
use crate::photometry::{candela_to_watts_per_sr, lux_to_watts_per_m2};
use crate::source::SceneError;
use ::gltf::khr_lights_punctual::Kind;
use glam::{Mat4, Vec3};
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use tyndall::camera::{Aperture, CameraSpec, FieldOfView};
use tyndall::color::Rgb;
use tyndall::description::{LightDesc, Origin, SceneDesc, Sourced};
use tyndall::lights::{DirectionalLight, Luminaire, PointLight, SpotLight, SpotProfile};
use tyndall::materials::MaterialId;
use tyndall::settings::{IntegratorKind, MAX_IMAGE_SIDE};
use tyndall::shapes::Bounds;
use tyndall::texture::{Encoding, TextureId};

/// Extensions this loader interprets; any other listed in
/// `extensionsUsed` is ignored with a warning (and, if required, refused
/// by the `gltf` crate's validation).
pub const HANDLED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_ior",
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    "KHR_materials_clearcoat",
    "KHR_texture_transform",
];

/// Most node instances the default scene's hierarchy may expand to: a
/// node reached along several paths (a node listed as the child of two
/// parents, which glTF 2.0 §3.5.2 forbids but files contain) is an
/// instance per path. A 26-level hierarchy of two children each is 2²⁶
/// instances from 2.5 KB; it is refused before the walk starts.
pub const MAX_NODE_INSTANCES: u64 = 1 << 20;

/// Most triangles the node walk may make, over all mesh instances
/// (each primitive's index count, or vertex count, over 3, times the
/// mesh's instances), checked before any is made: the meshes' limit.
pub use crate::mesh::MAX_TRIANGLES;

/// Most vertices the node walk may read, over all mesh instances (each
/// primitive's `POSITION` count times the mesh's instances).
pub const MAX_VERTICES: u64 = 1 << 25;

/// Largest `.gltf` or `.glb` file read, and largest buffer `byteLength`.
pub const MAX_FILE_BYTES: u64 = 1 << 30;

/// Largest image file (`images[i].uri`) read.
pub use crate::files::MAX_IMAGE_FILE_BYTES;

/// Index of refraction glTF assumes without KHR_materials_ior.
const DEFAULT_IOR: f32 = 1.5;

/// Vertical field of view of the default view when the file has no camera.
const DEFAULT_FOV_Y_DEG: f32 = 40.0;

/// `cos θ` where a glTF spot's smooth falloff reaches full intensity, as in
/// Blender and Cycles: Blender imports the cone as a blend `b = 1 − inner/outer`
/// and Cycles' smoothstep runs over `(cos θ − cos θo)/((1 − cos θo)·b)`
/// (`spot_smooth`, intern/cycles/scene/light.cpp); `≤ cos θo` is a hard edge.
fn smooth_cos_inner(inner: f32, outer: f32) -> f32 {
    outer.cos() + (1.0 - outer.cos()) * (1.0 - inner / outer)
}

/// The camera a glTF file names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GltfCamera {
    pub spec: CameraSpec,
    /// Width over height, when the camera gives one.
    pub aspect: Option<f32>,
    /// Its index in `cameras`.
    pub index: usize,
    /// The node that placed it.
    pub node: usize,
}

/// What a glTF file added to a [`SceneDesc`].
pub struct GltfContent {
    /// The first camera of the scene's node walk (depth first, in node
    /// order), if any.
    pub camera: Option<GltfCamera>,
    /// Bounds of the triangles added (empty if none).
    pub bounds: Bounds,
    pub warnings: Vec<String>,
}

/// Loads a glTF file as a whole scene: its camera (or a view of its
/// bounds), geometry, materials and lights, with default render settings
/// (the image height follows the camera's aspect ratio) but for the
/// integrator, and no fog. The integrator is `volpath`: an asset is lit
/// as the tool that wrote it lights it, light reflected between its
/// surfaces included (Cycles' F12 follows 12 bounces); the default
/// `single` lights surfaces directly only, 8 % darker on a Khronos
/// sample asset over a floor (docs/benchmarks.md, "A glTF asset beside
/// Cycles").
pub fn load(path: &Path) -> Result<SceneDesc, SceneError> {
    let bytes = read_document(path)?;
    load_bytes(path, &bytes, Some(&base_dir(path)))
}

/// [`load`] of a document held in memory: `bytes` are the `.gltf` JSON or
/// the `.glb` container (told apart by the GLB magic `glTF`, glTF 2.0
/// §4.4.2), `name` the file name errors give, and `base_dir` the
/// directory relative `uri`s resolve in (§2.8); with `None` only
/// `data:` URIs and the GLB BIN chunk can be read, and a file `uri` is an
/// error. For fuzzers: nothing but the document's own references is read
/// from disk.
pub fn load_bytes(
    name: &Path,
    bytes: &[u8],
    base_dir: Option<&Path>,
) -> Result<SceneDesc, SceneError> {
    let path = name;
    let placeholder = CameraSpec {
        position: Vec3::Z,
        look_at: Vec3::ZERO,
        up: Vec3::Y,
        fov: FieldOfView::Vertical(DEFAULT_FOV_Y_DEG),
        aperture: Aperture::Pinhole,
    };
    let mut desc = SceneDesc::new(Sourced::code(placeholder));
    let mut content = add_bytes_to_scene(path, bytes, base_dir, Mat4::IDENTITY, &mut desc)?;
    let settings = &mut desc.settings;
    settings.integrator = IntegratorKind::Volpath;
    let (camera, camera_element) = match content.camera {
        Some(camera) => {
            if let Some(aspect) = camera.aspect {
                let height = (settings.width as f32 / aspect).round();
                settings.height = height.clamp(1.0, MAX_IMAGE_SIDE as f32) as u32;
            }
            (
                camera.spec,
                format!("cameras[{}] (at nodes[{}])", camera.index, camera.node),
            )
        }
        None => {
            content.warnings.push(
                "the file has no camera: using a view of the whole scene from +z".to_string(),
            );
            let view = view_of(content.bounds).ok_or_else(|| {
                error(
                    path,
                    "the file has no camera and no triangles: there is nothing to look at",
                )
            })?;
            (view, "the default view (the file has no camera)".into())
        }
    };
    desc.camera = Sourced::new(
        camera,
        Origin::Element {
            file: Arc::from(path),
            path: camera_element,
        },
    );
    if desc.lights.is_empty() {
        content.warnings.push(
            "the scene has no KHR_lights_punctual lights: only emissive surfaces light it".into(),
        );
    }
    if let Some(e) =
        crate::source::located_together(desc.errors().into_iter().map(SceneError::from))
    {
        return Err(e);
    }
    content.warnings.extend(desc.lighting_warnings());
    desc.warnings = content.warnings;
    Ok(desc)
}

/// Adds the geometry, materials and lights of the glTF file at `path`,
/// placed by `placement` (applied after the file's own transforms), to
/// `scene`. The camera is returned, not set.
pub fn add_to_scene(
    path: &Path,
    placement: Mat4,
    scene: &mut SceneDesc,
) -> Result<GltfContent, SceneError> {
    let bytes = read_document(path)?;
    add_bytes_to_scene(path, &bytes, Some(&base_dir(path)), placement, scene)
}

/// The directory a file's relative `uri`s resolve in.
fn base_dir(path: &Path) -> PathBuf {
    path.parent().map(Path::to_owned).unwrap_or_default()
}

/// The bytes of a `.gltf` or `.glb` file, at most [`MAX_FILE_BYTES`].
fn read_document(path: &Path) -> Result<Vec<u8>, SceneError> {
    crate::files::read_capped(path, MAX_FILE_BYTES)
        .map_err(|m| error(path, format!("cannot read the file: {m}")))
}

/// A document checked and its buffers read.
struct Imported {
    document: ::gltf::Document,
    buffers: Vec<::gltf::buffer::Data>,
    outline: validate::Outline,
}

/// Parses and checks a document and reads its buffers: the GLB container
/// (`glb::parse`), our checks of the JSON (`validate::check`), the `gltf`
/// crate's own validation, then each buffer (§3.6.1) — the BIN chunk or a
/// bounded read of its `uri`.
fn import(name: &Path, bytes: &[u8], base: Option<&Path>) -> Result<Imported, SceneError> {
    let (json, bin) = if bytes.starts_with(b"glTF") {
        let glb = glb::parse(bytes).map_err(|m| error(name, m))?;
        (glb.json, glb.bin)
    } else {
        (bytes, None)
    };
    let value: serde_json::Value = serde_json::from_slice(json)
        .map_err(|e| error(name, format!("the glTF JSON is malformed: {e}")))?;
    let outline = validate::check(&value, bin.map(|b| b.len() as u64))
        .map_err(|p| error(name, format!("{}: {}", p.element, p.message)))?;
    drop(value);
    let root = ::gltf::json::Root::from_slice(json)
        .map_err(|e| error(name, format!("invalid glTF: {e}")))?;
    let document =
        ::gltf::Document::from_json(root).map_err(|e| error(name, describe_import_error(&e)))?;
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let element = format!("buffers[{}]", buffer.index());
        let length = buffer.length() as u64;
        if length > MAX_FILE_BYTES {
            return Err(error(
                name,
                format!(
                    "{element}: byteLength {length} is more than the {MAX_FILE_BYTES} bytes a buffer may have"
                ),
            ));
        }
        let mut data = match buffer.source() {
            ::gltf::buffer::Source::Bin => bin
                .map(<[u8]>::to_vec)
                .ok_or_else(|| error(name, format!("{element}: the file has no GLB BIN chunk")))?,
            ::gltf::buffer::Source::Uri(uri) => sources::read_buffer(uri, base, length)
                .map_err(|m| error(name, format!("{element}: {m}")))?,
        };
        // As the gltf crate pads them (its readers assume it).
        data.resize(data.len().div_ceil(4) * 4, 0);
        buffers.push(::gltf::buffer::Data(data));
    }
    Ok(Imported {
        document,
        buffers,
        outline,
    })
}

/// Visits the nodes under `roots` depth first, in order (a node before
/// its children, children in `children` order), without recursion: an
/// explicit stack, so a chain of any depth takes no native stack. `visit`
/// gets a node and its parent's state and returns the node's, which its
/// children get. A node met again among its own ancestors is a cycle,
/// refused (glTF 2.0 §3.5.2: the hierarchy is a set of disjoint trees).
fn traverse<S: Copy>(
    name: &Path,
    roots: &[usize],
    children: &[Vec<usize>],
    root_state: S,
    mut visit: impl FnMut(usize, S) -> Result<S, SceneError>,
) -> Result<(), SceneError> {
    enum Step<S> {
        Enter(usize, S),
        Leave(usize),
    }
    let mut on_path = vec![false; children.len()];
    let mut stack: Vec<Step<S>> = roots
        .iter()
        .rev()
        .map(|&n| Step::Enter(n, root_state))
        .collect();
    while let Some(step) = stack.pop() {
        match step {
            Step::Enter(node, parent) => {
                if on_path.get(node).copied().unwrap_or(true) {
                    return Err(error(
                        name,
                        format!("nodes[{node}]: the node is its own ancestor (a cycle)"),
                    ));
                }
                let state = visit(node, parent)?;
                on_path[node] = true;
                stack.push(Step::Leave(node));
                stack.extend(children[node].iter().rev().map(|&c| Step::Enter(c, state)));
            }
            Step::Leave(node) => on_path[node] = false,
        }
    }
    Ok(())
}

/// Refuses a hierarchy that expands past [`MAX_NODE_INSTANCES`],
/// [`MAX_TRIANGLES`] or [`MAX_VERTICES`], before anything is made: the
/// walk is counted first, stopping at the first limit passed.
fn check_expansion(
    name: &Path,
    outline: &validate::Outline,
    roots: &[usize],
) -> Result<(), SceneError> {
    let (mut instances, mut vertices, mut triangles) = (0u64, 0u64, 0u64);
    traverse(name, roots, &outline.children, (), |node, ()| {
        instances += 1;
        if instances > MAX_NODE_INSTANCES {
            return Err(error(
                name,
                format!(
                    "nodes[{node}]: the scene's node hierarchy expands to more than {MAX_NODE_INSTANCES} node instances (nodes reached along many paths)"
                ),
            ));
        }
        if let Some(mesh) = outline.node_mesh[node] {
            let (v, t) = outline.mesh_cost[mesh];
            vertices = vertices.saturating_add(v);
            triangles = triangles.saturating_add(t);
            let over = if triangles > MAX_TRIANGLES {
                Some(format!("{MAX_TRIANGLES} triangles"))
            } else if vertices > MAX_VERTICES {
                Some(format!("{MAX_VERTICES} vertices"))
            } else {
                None
            };
            if let Some(over) = over {
                return Err(error(
                    name,
                    format!(
                        "nodes[{node}]: the scene's mesh instances (meshes[{mesh}] here) add up to more than {over}"
                    ),
                ));
            }
        }
        Ok(())
    })
}

/// [`add_to_scene`] of a document held in memory; `name`, `bytes` and
/// `base_dir` as for [`load_bytes`].
pub fn add_bytes_to_scene(
    name: &Path,
    bytes: &[u8],
    base_dir: Option<&Path>,
    placement: Mat4,
    scene: &mut SceneDesc,
) -> Result<GltfContent, SceneError> {
    let path = name;
    let Imported {
        document,
        buffers,
        outline,
    } = import(name, bytes, base_dir)?;
    let roots = outline
        .roots
        .clone()
        .ok_or_else(|| error(path, "the file has no scenes"))?;
    check_expansion(path, &outline, &roots)?;
    let mut loader = GltfLoader {
        path,
        base: base_dir,
        buffers,
        decoded_texels: 0,
        materials: HashMap::new(),
        hidden_materials: HashSet::new(),
        textures: HashMap::new(),
        warnings: Vec::new(),
        camera: None,
        bounds: Bounds::EMPTY,
        skipped_degenerate: 0,
        light_profiles: outline.light_profiles.clone(),
        ies_files: ReadOnce::new(),
    };
    for ext in document.extensions_used() {
        if !HANDLED_EXTENSIONS.contains(&ext) {
            loader.warnings.push(format!(
                "{}: extension {ext} is not supported and is ignored",
                path.display()
            ));
        }
    }
    let nodes: Vec<::gltf::Node> = document.nodes().collect();
    traverse(path, &roots, &outline.children, placement, |n, parent| {
        loader.node(&nodes[n], parent, scene)
    })?;
    if loader.skipped_degenerate > 0 {
        loader.warnings.push(format!(
            "{}: skipped {} degenerate triangles",
            path.display(),
            loader.skipped_degenerate
        ));
    }
    Ok(GltfContent {
        camera: loader.camera,
        bounds: loader.bounds,
        warnings: loader.warnings,
    })
}

fn error(path: &Path, message: impl Into<String>) -> SceneError {
    SceneError {
        path: path.to_owned(),
        line: 0,
        column: 0,
        message: message.into(),
    }
}

/// The `gltf` crate's error, in words; validation errors already carry
/// the element path (`meshes[0].primitives[0].attributes`).
fn describe_import_error(e: &::gltf::Error) -> String {
    match e {
        ::gltf::Error::Io(io) => format!("cannot read the file or one of its buffers: {io}"),
        ::gltf::Error::Validation(errors) => {
            let list: Vec<String> = errors
                .iter()
                .map(|(path, err)| format!("{path}: {err}"))
                .collect();
            format!("invalid glTF: {}", list.join("; "))
        }
        other => format!("cannot read glTF: {other}"),
    }
}

/// A view of `bounds` from +z, fitting its bounding sphere in the
/// default field of view; `None` for empty bounds.
fn view_of(bounds: Bounds) -> Option<CameraSpec> {
    if bounds.is_empty() {
        return None;
    }
    let center = bounds.center();
    let radius = (0.5 * bounds.extent().length()).max(1e-3);
    let distance = radius / (0.5 * DEFAULT_FOV_Y_DEG.to_radians()).sin();
    Some(CameraSpec {
        position: center + Vec3::Z * distance,
        look_at: center,
        up: Vec3::Y,
        fov: FieldOfView::Vertical(DEFAULT_FOV_Y_DEG),
        aperture: Aperture::Pinhole,
    })
}

struct GltfLoader<'a> {
    path: &'a Path,
    /// Where relative image `uri`s resolve.
    base: Option<&'a Path>,
    buffers: Vec<::gltf::buffer::Data>,
    /// Texels of the images decoded so far (bounded by
    /// `textures::MAX_DECODED_TEXELS`).
    decoded_texels: u64,
    /// Tyndall material of each glTF material (`None`: the default one),
    /// with the base colour texture that multiplies its diffuse
    /// reflectance, if any.
    materials: HashMap<Option<usize>, (MaterialId, MaterialTextures)>,
    /// glTF materials that are cut out everywhere (`MASK` below its
    /// cutoff without a texture's alpha): their primitives are left out.
    hidden_materials: HashSet<Option<usize>>,
    /// The scene's texture made of each (image, sampler) pair.
    textures: HashMap<(usize, Option<usize>, Encoding), TextureId>,
    warnings: Vec<String>,
    camera: Option<GltfCamera>,
    bounds: Bounds,
    skipped_degenerate: usize,
    /// Each light's measured profile named in its `extras`, if any.
    light_profiles: Vec<Option<validate::ProfileRef>>,
    /// The IES files those name, each read once.
    ies_files: ReadOnce<IesFile>,
}

impl GltfLoader<'_> {
    /// The origin of element `element` of this file.
    fn origin(&self, element: String) -> Origin {
        Origin::Element {
            file: Arc::from(self.path),
            path: element,
        }
    }

    fn err(&self, element: &str, message: impl std::fmt::Display) -> SceneError {
        error(self.path, format!("{element}: {message}"))
    }

    fn warn(&mut self, element: &str, message: impl std::fmt::Display) {
        self.warnings
            .push(format!("{}: {element}: {message}", self.path.display()));
    }

    /// One node of the walk ([`traverse`]): its mesh, camera and light,
    /// placed by `parent · local` (§3.5.2); returns its world matrix.
    fn node(
        &mut self,
        node: &::gltf::Node,
        parent: Mat4,
        scene: &mut SceneDesc,
    ) -> Result<Mat4, SceneError> {
        let element = format!("nodes[{}]", node.index());
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        if !local.is_finite() {
            return Err(self.err(&element, "the transform must be finite numbers"));
        }
        let world = parent * local;
        if let Some(mesh) = node.mesh() {
            self.mesh(&mesh, world, scene)?;
        }
        if let Some(camera) = node.camera()
            && self.camera.is_none()
        {
            self.camera = Some(self.camera(node.index(), &camera, world)?);
        }
        if let Some(light) = node.light() {
            let origin = self.origin(format!("{element}.light"));
            let light = self.light(&light, world)?;
            scene.add_light(light, origin);
        }
        Ok(world)
    }

    /// glTF cameras look along their node's −z with +y up (glTF §3.10).
    fn camera(
        &self,
        node_index: usize,
        camera: &::gltf::Camera,
        world: Mat4,
    ) -> Result<GltfCamera, SceneError> {
        let node = &format!("nodes[{node_index}]");
        let element = format!("cameras[{}]", camera.index());
        let perspective = match camera.projection() {
            ::gltf::camera::Projection::Perspective(p) => p,
            ::gltf::camera::Projection::Orthographic(_) => {
                return Err(self.err(
                    &element,
                    "orthographic cameras are not supported: use a perspective camera",
                ));
            }
        };
        let fov_deg = (perspective.yfov() as f64).to_degrees() as f32;
        if !(fov_deg > 0.0 && fov_deg < 180.0) {
            return Err(self.err(
                &element,
                format!("yfov must be in (0, π), got {} radians", perspective.yfov()),
            ));
        }
        let aspect = perspective.aspect_ratio();
        if let Some(a) = aspect
            && !(a > 0.0 && a.is_finite())
        {
            return Err(self.err(&element, format!("aspectRatio must be positive, got {a}")));
        }
        let position = world.transform_point3(Vec3::ZERO);
        let forward = world.transform_vector3(Vec3::NEG_Z);
        let up = world.transform_vector3(Vec3::Y);
        let usable = forward.length_squared() > 0.0
            && forward.is_finite()
            && forward.normalize().cross(up.normalize()).length_squared() > 1e-10;
        if !usable {
            return Err(self.err(
                node,
                "the camera's transform is degenerate (no view direction or up vector)",
            ));
        }
        Ok(GltfCamera {
            spec: CameraSpec {
                position,
                look_at: position + forward.normalize(),
                up: up.normalize(),
                fov: FieldOfView::Vertical(fov_deg),
                aperture: Aperture::Pinhole,
            },
            aspect,
            index: camera.index(),
            node: node_index,
        })
    }

    /// A KHR_lights_punctual light at its node: position `M·0`, direction
    /// `M·(0, 0, −1)` (the light's −z). A point or spot light whose
    /// `extras` name an `.ies` file ([`validate::ProfileRef`]) takes that
    /// measured profile with its nadir along the light's −z, as the native
    /// format's `ies` key does; the light's `intensity` (cd) is then the
    /// profile's peak.
    fn light(
        &mut self,
        light: &::gltf::khr_lights_punctual::Light,
        world: Mat4,
    ) -> Result<LightDesc, SceneError> {
        let element = format!("KHR_lights_punctual.lights[{}]", light.index());
        let color = Rgb::from_array(light.color());
        let intensity = light.intensity();
        if !(color.is_finite() && color.min_element() >= 0.0) {
            return Err(self.err(&element, "color must be non-negative"));
        }
        if !(intensity.is_finite() && intensity >= 0.0) {
            return Err(self.err(
                &element,
                format!("intensity must be non-negative, got {intensity}"),
            ));
        }
        if let Some(range) = light.range() {
            self.warn(
                &element,
                format!(
                    "range {range} is ignored: the light falls off with the inverse square of distance everywhere"
                ),
            );
        }
        let position = world.transform_point3(Vec3::ZERO);
        let direction = world.transform_vector3(Vec3::NEG_Z);
        let measured = self.light_profiles.get(light.index()).cloned().flatten();
        let needs_direction = !matches!(light.kind(), Kind::Point) || measured.is_some();
        if needs_direction && !(direction.length_squared() > 0.0 && direction.is_finite()) {
            return Err(self.err(&element, "the light's node transform has no direction"));
        }
        let luminaire = match (measured, light.kind()) {
            (Some(_), Kind::Directional) => {
                return Err(self.err(
                    &format!("{element}.extras.ies"),
                    "a measured profile needs a point or spot light",
                ));
            }
            (Some(profile), _) => {
                let path = match self.base {
                    Some(base) => base.join(&profile.file),
                    None => PathBuf::from(&profile.file),
                };
                let measured = self
                    .ies_files
                    .get_or_read(&path, crate::ies::load)
                    .map_err(|e| self.err(&format!("{element}.extras.ies"), e))?;
                Some(Luminaire::new(
                    measured.profile,
                    direction.normalize(),
                    profile.rotate_deg,
                ))
            }
            (None, _) => None,
        };
        Ok(match light.kind() {
            Kind::Point => LightDesc::Point(PointLight {
                luminaire,
                position,
                intensity: color * candela_to_watts_per_sr(intensity),
            }),
            Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => {
                let valid = inner_cone_angle >= 0.0
                    && inner_cone_angle <= outer_cone_angle
                    && outer_cone_angle > 0.0
                    && outer_cone_angle <= std::f32::consts::FRAC_PI_2;
                if !valid {
                    return Err(self.err(
                        &element,
                        format!(
                            "spot cone angles must satisfy 0 ≤ innerConeAngle ≤ outerConeAngle ≤ π/2 and outerConeAngle > 0, got {inner_cone_angle} and {outer_cone_angle}"
                        ),
                    ));
                }
                // Blender's spot blend 0 writes inner == outer: a hard edge.
                let cos_inner = smooth_cos_inner(inner_cone_angle, outer_cone_angle);
                let profile = if cos_inner <= outer_cone_angle.cos() {
                    SpotProfile::Hard
                } else {
                    SpotProfile::Smooth { cos_inner }
                };
                LightDesc::Spot(SpotLight {
                    gobo: None,
                    luminaire,
                    position,
                    direction: direction.normalize(),
                    cos_cutoff: outer_cone_angle.cos(),
                    profile,
                    intensity: color * candela_to_watts_per_sr(intensity),
                })
            }
            Kind::Directional => LightDesc::Directional(DirectionalLight {
                direction: direction.normalize(),
                irradiance: color * lux_to_watts_per_m2(intensity),
            }),
        })
    }
}
