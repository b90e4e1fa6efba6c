//! glTF 2.0 scenes (`.gltf` with its buffers, `.glb`), read with the
//! `gltf` crate, as documented in docs/scene-format.md ("glTF input").
//!
//! The default scene's node hierarchy is walked with each node's world
//! matrix `M_world = M_parent · M_local` (glTF §3.5.2, `M_local = T·R·S` or
//! the node's matrix). Triangle primitives become triangles, the first
//! camera met in the walk becomes the camera, KHR_lights_punctual lights
//! become point, spot and directional lights (photometric units converted
//! by [`crate::photometry`]) and materials map to Tyndall's closed set
//! (`GltfLoader::material`). Errors name the file and the
//! element (`meshes[2].primitives[0]`, `nodes[3]`, `materials[1]`).

use crate::photometry::{candela_to_watts_per_sr, lux_to_watts_per_m2};
use crate::source::SceneError;
use ::gltf::image::Format;
use ::gltf::khr_lights_punctual::Kind;
use ::gltf::mesh::Mode;
use ::gltf::{Accessor, Semantic};
use glam::{Mat4, Vec3};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;
use tyndall::camera::{CameraSpec, FieldOfView};
use tyndall::color::{Rgb, srgb_to_linear};
use tyndall::description::{LightDesc, Origin, SceneDesc, Sourced};
use tyndall::glass::Glass;
use tyndall::lights::{DirectionalLight, PointLight, SpotLight, SpotProfile};
use tyndall::materials::{Material, MaterialId, Surface};
use tyndall::settings::MAX_IMAGE_SIDE;
use tyndall::shapes::{Bounds, Shape, Triangle};

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
];

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
/// (the image height follows the camera's aspect ratio) and no fog.
pub fn load(path: &Path) -> Result<SceneDesc, SceneError> {
    let placeholder = CameraSpec {
        position: Vec3::Z,
        look_at: Vec3::ZERO,
        up: Vec3::Y,
        fov: FieldOfView::Vertical(DEFAULT_FOV_Y_DEG),
    };
    let mut desc = SceneDesc::new(Sourced::code(placeholder));
    let mut content = add_to_scene(path, Mat4::IDENTITY, &mut desc)?;
    let settings = &mut desc.settings;
    let camera = match content.camera {
        Some(camera) => {
            if let Some(aspect) = camera.aspect {
                let height = (settings.width as f32 / aspect).round();
                settings.height = height.clamp(1.0, MAX_IMAGE_SIDE as f32) as u32;
            }
            camera.spec
        }
        None => {
            content.warnings.push(
                "the file has no camera: using a view of the whole scene from +z".to_string(),
            );
            view_of(content.bounds).ok_or_else(|| {
                error(
                    path,
                    "the file has no camera and no triangles: there is nothing to look at",
                )
            })?
        }
    };
    desc.camera = Sourced::new(
        camera,
        Origin::Element {
            file: Arc::from(path),
            path: "cameras".into(),
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
    let (document, buffers, images) =
        ::gltf::import(path).map_err(|e| error(path, describe_import_error(&e)))?;
    let mut loader = GltfLoader {
        path,
        buffers,
        images,
        materials: HashMap::new(),
        texture_averages: HashMap::new(),
        warnings: Vec::new(),
        camera: None,
        bounds: Bounds::EMPTY,
        skipped_degenerate: 0,
    };
    for ext in document.extensions_used() {
        if !HANDLED_EXTENSIONS.contains(&ext) {
            loader.warnings.push(format!(
                "{}: extension {ext} is not supported and is ignored",
                path.display()
            ));
        }
    }
    let gltf_scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or_else(|| error(path, "the file has no scenes"))?;
    let mut ancestors = Vec::new();
    for node in gltf_scene.nodes() {
        loader.node(&node, placement, &mut ancestors, scene)?;
    }
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
    })
}

struct GltfLoader<'a> {
    path: &'a Path,
    buffers: Vec<::gltf::buffer::Data>,
    images: Vec<::gltf::image::Data>,
    /// Tyndall material of each glTF material (`None`: the default one).
    materials: HashMap<Option<usize>, MaterialId>,
    /// Mean linear colour of each image, by image index.
    texture_averages: HashMap<usize, Rgb>,
    warnings: Vec<String>,
    camera: Option<GltfCamera>,
    bounds: Bounds,
    skipped_degenerate: usize,
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

    fn node(
        &mut self,
        node: &::gltf::Node,
        parent: Mat4,
        ancestors: &mut Vec<usize>,
        scene: &mut SceneDesc,
    ) -> Result<(), SceneError> {
        let element = format!("nodes[{}]", node.index());
        if ancestors.contains(&node.index()) {
            return Err(self.err(&element, "the node is its own ancestor (a cycle)"));
        }
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
            self.camera = Some(self.camera(&element, &camera, world)?);
        }
        if let Some(light) = node.light() {
            let origin = self.origin(format!("{element}.light"));
            let light = self.light(&light, world)?;
            scene.add_light(light, origin);
        }
        ancestors.push(node.index());
        for child in node.children() {
            self.node(&child, world, ancestors, scene)?;
        }
        ancestors.pop();
        Ok(())
    }

    /// glTF cameras look along their node's −z with +y up (glTF §3.10).
    fn camera(
        &self,
        node: &str,
        camera: &::gltf::Camera,
        world: Mat4,
    ) -> Result<GltfCamera, SceneError> {
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
            },
            aspect,
        })
    }

    /// A KHR_lights_punctual light at its node: position `M·0`, direction
    /// `M·(0, 0, −1)` (the light's −z).
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
        let needs_direction = !matches!(light.kind(), Kind::Point);
        if needs_direction && !(direction.length_squared() > 0.0 && direction.is_finite()) {
            return Err(self.err(&element, "the light's node transform has no direction"));
        }
        Ok(match light.kind() {
            Kind::Point => LightDesc::Point(PointLight {
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

    /// Checks that an accessor holds `dimensions` × f32 or integer data
    /// as expected, naming `element` in the error.
    fn check_accessor(
        &self,
        element: &str,
        what: &str,
        accessor: &Accessor,
        dimensions: ::gltf::accessor::Dimensions,
        float: bool,
    ) -> Result<(), SceneError> {
        use ::gltf::accessor::DataType;
        let type_ok = if float {
            accessor.data_type() == DataType::F32
        } else {
            matches!(
                accessor.data_type(),
                DataType::U8 | DataType::U16 | DataType::U32
            )
        };
        if accessor.dimensions() != dimensions || !type_ok {
            return Err(self.err(
                element,
                format!(
                    "{what} must be {dimensions:?} of {}, got {:?} of {:?}",
                    if float { "floats" } else { "unsigned integers" },
                    accessor.dimensions(),
                    accessor.data_type()
                ),
            ));
        }
        if accessor.count() == 0 {
            return Err(self.err(element, format!("{what} is empty")));
        }
        Ok(())
    }

    fn mesh(
        &mut self,
        mesh: &::gltf::Mesh,
        world: Mat4,
        scene: &mut SceneDesc,
    ) -> Result<(), SceneError> {
        // A mirroring transform reverses the winding, and with it the
        // front face (glTF §3.7.4): swap two corners to keep it.
        let mirrored = world.determinant() < 0.0;
        for primitive in mesh.primitives() {
            let element = format!("meshes[{}].primitives[{}]", mesh.index(), primitive.index());
            if primitive.mode() != Mode::Triangles {
                return Err(self.err(
                    &element,
                    format!(
                        "primitive mode {:?} is not supported: only triangles (mode 4) are",
                        primitive.mode()
                    ),
                ));
            }
            let positions_accessor = primitive
                .get(&Semantic::Positions)
                .ok_or_else(|| self.err(&element, "the primitive has no POSITION attribute"))?;
            self.check_accessor(
                &element,
                "POSITION",
                &positions_accessor,
                ::gltf::accessor::Dimensions::Vec3,
                true,
            )?;
            if let Some(indices) = primitive.indices() {
                self.check_accessor(
                    &element,
                    "the indices",
                    &indices,
                    ::gltf::accessor::Dimensions::Scalar,
                    false,
                )?;
            }
            let material = self.material_id(&primitive.material(), scene)?;
            let mut triangles = Vec::new();
            let buffers = &self.buffers;
            let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
            let positions: Vec<Vec3> = reader
                .read_positions()
                .ok_or_else(|| {
                    self.err(
                        &element,
                        "cannot read POSITION: its accessor lies outside its buffer",
                    )
                })?
                .map(|p| world.transform_point3(Vec3::from_array(p)))
                .collect();
            let indices: Vec<u32> = match primitive.indices() {
                Some(_) => reader
                    .read_indices()
                    .ok_or_else(|| {
                        self.err(
                            &element,
                            "cannot read the indices: their accessor lies outside its buffer",
                        )
                    })?
                    .into_u32()
                    .collect(),
                None => (0..positions.len() as u32).collect(),
            };
            if indices.len() % 3 != 0 {
                return Err(self.err(
                    &element,
                    format!("{} vertices do not form whole triangles", indices.len()),
                ));
            }
            for (t, corners) in indices.chunks_exact(3).enumerate() {
                let vertex = |i: u32| {
                    positions.get(i as usize).copied().ok_or_else(|| {
                        self.err(
                            &element,
                            format!(
                                "triangle {t} refers to vertex {i}, but POSITION has {} vertices",
                                positions.len()
                            ),
                        )
                    })
                };
                let (a, mut b, mut c) = (
                    vertex(corners[0])?,
                    vertex(corners[1])?,
                    vertex(corners[2])?,
                );
                if !(a.is_finite() && b.is_finite() && c.is_finite()) {
                    return Err(self.err(&element, "vertex positions must be finite"));
                }
                if mirrored {
                    std::mem::swap(&mut b, &mut c);
                }
                match Triangle::new(a, b, c) {
                    Some(triangle) => {
                        self.bounds = self.bounds.union(triangle.bounds());
                        triangles.push(Shape::Triangle(triangle));
                    }
                    None => self.skipped_degenerate += 1,
                }
            }
            let origin = self.origin(element);
            scene.add_shapes(triangles, material, origin);
        }
        Ok(())
    }

    fn material_id(
        &mut self,
        material: &::gltf::Material,
        scene: &mut SceneDesc,
    ) -> Result<MaterialId, SceneError> {
        if let Some(&id) = self.materials.get(&material.index()) {
            return Ok(id);
        }
        let converted = self.material(material)?;
        let element = match material.index() {
            Some(i) => format!("materials[{i}]"),
            None => "the default material".into(),
        };
        let id = scene.add_material(converted, self.origin(element));
        self.materials.insert(material.index(), id);
        Ok(id)
    }

    /// Tyndall's material for a glTF material, first match wins:
    ///
    /// 1. `emissiveFactor × emissive_strength` non-zero → an emitter of
    ///    that radiance (W·sr⁻¹·m⁻², the number Blender's emission
    ///    strength gives Cycles), two-sided if `doubleSided`; emitters do
    ///    not reflect.
    /// 2. KHR_materials_transmission factor > 0: with KHR_materials_volume
    ///    thickness > 0 a refractive dielectric of KHR_materials_ior's
    ///    index (1.5 by default); without, thin coloured glass of the base
    ///    colour (the stained-glass case).
    /// 3. Otherwise an opaque surface: with metallic `m`, base colour `c`
    ///    and dielectric normal-incidence reflectance
    ///    `F0 = ((ior − 1)/(ior + 1))² · specularFactor · specularColorFactor`
    ///    (KHR_materials_specular; Blender writes factor 0 for a pure
    ///    Lambert surface), diffuse `c·(1 − m)·(1 − max F0)` and specular
    ///    `c·m + F0·(1 − m)`, the glTF BRDF's mix at normal incidence; the
    ///    roughness of the reflective lobe is glTF's `roughness²` (its α).
    ///
    /// A base-colour texture multiplies the factor by the texture's mean
    /// linear colour: Tyndall has no textures yet.
    fn material(&mut self, material: &::gltf::Material) -> Result<Material, SceneError> {
        let element = match material.index() {
            Some(i) => format!("materials[{i}]"),
            None => "the default material".to_string(),
        };
        let pbr = material.pbr_metallic_roughness();
        let factor = pbr.base_color_factor();
        let mut base = Rgb::new(factor[0], factor[1], factor[2]);
        if !(base.is_finite() && base.min_element() >= 0.0 && base.max_element() <= 1.0) {
            return Err(self.err(
                &element,
                format!("baseColorFactor must be in [0, 1], got {factor:?}"),
            ));
        }
        if let Some(info) = pbr.base_color_texture() {
            base *= self.texture_average(&element, &info.texture())?;
        }
        let emissive_strength = material.emissive_strength().unwrap_or(1.0);
        let emission = Rgb::from_array(material.emissive_factor()) * emissive_strength;
        if !(emission.is_finite() && emission.min_element() >= 0.0) {
            return Err(self.err(
                &element,
                "emissiveFactor × emissiveStrength must be non-negative and finite",
            ));
        }
        if emission.max_element() > 0.0 {
            if material.emissive_texture().is_some() {
                self.warn(
                    &element,
                    "emissiveTexture is ignored: the surface emits emissiveFactor",
                );
            }
            return Ok(Material::Emissive {
                radiance: emission,
                two_sided: material.double_sided(),
            });
        }
        let ior = material.ior().unwrap_or(DEFAULT_IOR);
        if !(ior.is_finite() && (1.0..=10.0).contains(&ior)) {
            return Err(self.err(
                &element,
                format!("KHR_materials_ior ior must be in [1, 10], got {ior}"),
            ));
        }
        if let Some(transmission) = material.transmission()
            && transmission.transmission_factor() > 0.0
        {
            let t = transmission.transmission_factor();
            if transmission.transmission_texture().is_some() {
                self.warn(&element, "transmissionTexture is ignored");
            }
            let thickness = material.volume().map_or(0.0, |v| v.thickness_factor());
            if thickness > 0.0 {
                if let Some(volume) = material.volume()
                    && volume.attenuation_distance().is_finite()
                {
                    self.warn(
                        &element,
                        "attenuationColor/attenuationDistance are ignored: the dielectric's inside is clear",
                    );
                }
                return Ok(Material::Dielectric { ior });
            }
            if t < 1.0 {
                self.warn(
                    &element,
                    format!(
                        "transmissionFactor {t} is rendered as 1: thin glass passes all light it does not filter"
                    ),
                );
            }
            return Ok(Material::Glass(Glass {
                color: base,
                alpha: 1.0,
            }));
        }
        let metallic = pbr.metallic_factor();
        let roughness = pbr.roughness_factor();
        for (name, v) in [("metallicFactor", metallic), ("roughnessFactor", roughness)] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Err(self.err(&element, format!("{name} must be in [0, 1], got {v}")));
            }
        }
        if pbr.metallic_roughness_texture().is_some() {
            self.warn(
                &element,
                "metallicRoughnessTexture is ignored: the factors apply everywhere",
            );
        }
        let (specular_factor, specular_color) = match material.specular() {
            Some(s) => {
                if s.specular_texture().is_some() || s.specular_color_texture().is_some() {
                    self.warn(&element, "KHR_materials_specular textures are ignored");
                }
                (
                    s.specular_factor(),
                    Rgb::from_array(s.specular_color_factor()),
                )
            }
            None => (1.0, Rgb::ONE),
        };
        let r0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let f0 = (Rgb::splat(r0) * specular_color * specular_factor).clamp(Rgb::ZERO, Rgb::ONE);
        if !f0.is_finite() {
            return Err(self.err(&element, "KHR_materials_specular factors must be finite"));
        }
        let diffuse = base * (1.0 - metallic) * (1.0 - f0.max_element());
        let specular = base * metallic + f0 * (1.0 - metallic);
        Ok(Material::Opaque(if specular == Rgb::ZERO {
            Surface::diffuse(diffuse)
        } else {
            Surface {
                diffuse,
                specular,
                roughness: roughness * roughness,
            }
        }))
    }

    /// The mean linear-RGB colour of a texture's image (sRGB-decoded,
    /// alpha ignored).
    fn texture_average(
        &mut self,
        element: &str,
        texture: &::gltf::Texture,
    ) -> Result<Rgb, SceneError> {
        let index = texture.source().index();
        if let Some(&mean) = self.texture_averages.get(&index) {
            return Ok(mean);
        }
        let image = self
            .images
            .get(index)
            .ok_or_else(|| self.err(element, format!("images[{index}] was not loaded")))?;
        let (channels, bytes) = match image.format {
            Format::R8 => (1, 1),
            Format::R8G8 => (2, 1),
            Format::R8G8B8 => (3, 1),
            Format::R8G8B8A8 => (4, 1),
            Format::R16 => (1, 2),
            Format::R16G16 => (2, 2),
            Format::R16G16B16 => (3, 2),
            Format::R16G16B16A16 => (4, 2),
            other => {
                return Err(self.err(
                    element,
                    format!(
                        "images[{index}]: pixel format {other:?} is not supported for a base colour"
                    ),
                ));
            }
        };
        let stride = channels * bytes;
        let mut sum = [0.0f64; 3];
        let mut count = 0usize;
        for pixel in image.pixels.chunks_exact(stride) {
            let channel = |c: usize| -> f32 {
                let c = c.min(channels - 1);
                let v = if bytes == 1 {
                    pixel[c] as f32 / 255.0
                } else {
                    u16::from_ne_bytes([pixel[2 * c], pixel[2 * c + 1]]) as f32 / 65535.0
                };
                srgb_to_linear(v)
            };
            // One and two channels are grey (+ alpha).
            let rgb = if channels <= 2 {
                [channel(0); 3]
            } else {
                [channel(0), channel(1), channel(2)]
            };
            for (s, v) in sum.iter_mut().zip(rgb) {
                *s += v as f64;
            }
            count += 1;
        }
        if count == 0 {
            return Err(self.err(element, format!("images[{index}] has no pixels")));
        }
        let mean = Rgb::new(
            (sum[0] / count as f64) as f32,
            (sum[1] / count as f64) as f32,
            (sum[2] / count as f64) as f32,
        );
        self.warn(
            element,
            format!(
                "baseColorTexture (images[{index}]) is averaged to one colour {:?}: Tyndall has no textures",
                mean.to_array()
            ),
        );
        self.texture_averages.insert(index, mean);
        Ok(mean)
    }
}
