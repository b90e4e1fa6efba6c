//! The scene description: what a scene is, as plain data, before anything
//! is built from it.
//!
//! Every loader (native TOML, the paper's legacy .obj, glTF, Python
//! dictionaries) produces a [`SceneDesc`]; none builds runtime objects.
//! [`SceneDesc::validate`] checks it in one place and reports each error
//! at the [`Origin`] of the item it concerns, and
//! [`Scene::build`](crate::scene::Scene::build) makes the runtime scene
//! from it (BVH, area lights from emissive shapes, volumes with their
//! majorant grids).
//!
//! The description is in physical units (docs/physics.md): positions in
//! scene units, radiance in W/(m²·sr), intensity in W/sr, irradiance in
//! W/m², extinction per scene unit, linear RGB.

mod validate;

use crate::camera::CameraSpec;
use crate::color::Rgb;
use crate::coverage::Coverage;
use crate::glass::GlassModel;
use crate::lights::{
    DirectionalLight, EnvironmentLight, Light, LightSampling, PointLight, SpotLight,
};
use crate::limits;
use crate::materials::{Material, MaterialId, MetallicRoughness};
use crate::media::Fog;
use crate::media::emission::Emission;
use crate::media::volume::Density;
use crate::phase::PhaseFunction;
use crate::settings::RenderSettings;
use crate::shapes::{Bounds, Shape, Triangle};
use crate::texture::{Texture, TextureId};
use glam::{Vec2, Vec3, Vec4};
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where an item of a description came from, so that an error about it
/// can name the place.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Origin {
    /// Made in code (tests, the API): no place to name.
    #[default]
    Code,
    /// A place in a text file, 1-based line and column (in characters).
    Location {
        file: Arc<Path>,
        line: usize,
        column: usize,
    },
    /// A table of a text file, as a byte range: the loader that read the
    /// text turns it, with the key an error names, into a line and
    /// column (TOML tables).
    Span { file: Arc<Path>, span: Range<usize> },
    /// An element of a structured file or value, by its path:
    /// `nodes[3].mesh` in a glTF file, `shapes[2]` in a Python dictionary.
    Element { file: Arc<Path>, path: String },
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Origin::Code => Ok(()),
            Origin::Location { file, line, column } => {
                write!(f, "{}:{line}:{column}", file.display())
            }
            Origin::Span { file, span } => write!(f, "{} (byte {})", file.display(), span.start),
            Origin::Element { file, path } => write!(f, "{}: {path}", file.display()),
        }
    }
}

/// An item of a description with its origin.
#[derive(Clone, Debug, PartialEq)]
pub struct Sourced<T> {
    pub value: T,
    pub origin: Origin,
}

impl<T> Sourced<T> {
    pub fn new(value: T, origin: Origin) -> Self {
        Self { value, origin }
    }

    /// An item made in code.
    pub fn code(value: T) -> Self {
        Self::new(value, Origin::Code)
    }
}

/// One shape item of a file — a sphere, a quad, a box's six faces, a
/// mesh's triangles — with the material they share.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeDesc {
    pub shapes: Vec<Shape>,
    pub material: MaterialId,
    pub origin: Origin,
    /// A smooth mesh's vertex normals, for shading: one unit normal per
    /// corner of each triangle of `shapes` (in the order `v0`, `v0 + e1`,
    /// `v0 + e2`), interpolated across it (Phong 1975). Empty for flat
    /// shading, the only kind quads and spheres have.
    pub vertex_normals: Vec<[Vec3; 3]>,
    /// A colour texture over the mesh's triangles, if any.
    pub texture: Option<SurfaceTexture>,
    /// A mesh's vertex colours (linear RGB, each channel in `[0, 1]`),
    /// which multiply its diffuse reflectance: one per corner of each
    /// triangle, in the order of `vertex_normals`, interpolated across it.
    /// Empty for none.
    pub vertex_colours: Vec<[Rgb; 3]>,
    /// A tangent-space normal map over the mesh's triangles, if any.
    pub normal_map: Option<NormalMap>,
    /// A texture scaling an emissive mesh's radiance, if any.
    pub emission_map: Option<EmissionMap>,
    /// A glTF metallic-roughness surface evaluated point by point, if
    /// any.
    pub metallic_roughness: Option<MetallicRoughnessMap>,
    /// How much of the mesh is there (glTF's `alphaMode` `MASK` or
    /// `BLEND`), on its coverage: the rule's factor times the alpha of
    /// [`ShapeDesc::texture`] at each point (its mean coverage without
    /// coordinates; 1 without a texture or without an alpha channel).
    /// `None`: wholly there.
    pub coverage: Option<Coverage>,
}

/// What a mesh carries per corner or per point besides its positions,
/// for [`SceneDesc::add_mesh`]: see the fields of the same names of
/// [`ShapeDesc`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshAttributes {
    pub vertex_normals: Vec<[Vec3; 3]>,
    pub vertex_colours: Vec<[Rgb; 3]>,
    pub texture: Option<SurfaceTexture>,
    pub normal_map: Option<NormalMap>,
    pub emission_map: Option<EmissionMap>,
    pub metallic_roughness: Option<MetallicRoughnessMap>,
    pub coverage: Option<Coverage>,
}

impl ShapeDesc {
    /// Whether every shape is a triangle (a mesh, which may carry
    /// per-corner attributes).
    pub fn is_mesh(&self) -> bool {
        self.shapes.iter().all(|s| matches!(s, Shape::Triangle(_)))
    }
}

/// A colour texture over a mesh: the texture multiplies the diffuse
/// reflectance of the mesh's material (a glTF base colour texture), at
/// the texture coordinates interpolated across each triangle from one per
/// corner (in the order of [`ShapeDesc::vertex_normals`]). Without
/// coordinates (`uvs` empty) the texture's mean colour applies everywhere.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceTexture {
    pub texture: TextureId,
    pub uvs: Vec<[Vec2; 3]>,
}

/// A tangent-space normal map over a mesh (glTF's `normalTexture`): at
/// each point the texture's texel `c` (read as data, `code/255`) gives
/// the shading normal `normalize(x·T + y·B + z·N)` with
/// `(x, y, z) = (2c − 1)·(scale, scale, 1)`, where N is the mesh's
/// shading normal there and T, B its tangent frame:
///
/// - with `tangents` (glTF's `TANGENT`, or MikkTSpace's tangents computed
///   by the loader as glTF 2.0 §3.7.2.1 asks where a file has none), T
///   is the corners' tangents interpolated across the triangle and
///   `B = w·(N × T)`, as the MikkTSpace reference (mikktspace.h, "how to
///   use") and Cycles' Normal Map node use them: neither is normalised
///   nor made perpendicular before the sum is;
/// - without, T is the triangle's direction of increasing u and B that
///   of decreasing v, both made perpendicular to N.
///
/// Either way B points up the map's image (glTF's v runs down its
/// images, and +y of the map points up them, as Blender and Cycles read
/// it). The coordinates and tangents are one per corner of each triangle,
/// in the order of [`ShapeDesc::vertex_normals`].
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMap {
    pub texture: TextureId,
    pub uvs: Vec<[Vec2; 3]>,
    /// glTF's `normalTexture.scale`: the map's x and y are multiplied by it.
    pub scale: f32,
    /// Per corner, the tangent T (xyz, world space, non-zero) and the
    /// handedness `w = ±1` of the frame (glTF's `TANGENT`); empty for the
    /// triangles' own frames.
    pub tangents: Vec<[Vec4; 3]>,
}

/// A colour texture over an emissive mesh (glTF's `emissiveTexture`):
/// its colour (sRGB-decoded, bilinear) multiplies the radiance of the
/// mesh's [`Material::Emissive`] at each point, at the texture
/// coordinates interpolated across each triangle from one per corner (in
/// the order of [`ShapeDesc::vertex_normals`]). The mesh's light samples
/// its points uniformly by area and weighs them by the texture
/// ([`crate::lights::MeshLight`]).
#[derive(Clone, Debug, PartialEq)]
pub struct EmissionMap {
    pub texture: TextureId,
    pub uvs: Vec<[Vec2; 3]>,
}

/// A glTF metallic-roughness surface over a mesh, evaluated at each point
/// ([`MetallicRoughness::surface`]) instead of the mesh's material's
/// constant surface: its base colour is `factors.base` times the mesh's
/// colour texture and vertex colours there, and where `texture` is given
/// (glTF's `metallicRoughnessTexture`, read as data: `code/255`, bilinear)
/// its metalness is `factors.metallic` times the texture's blue channel
/// and its roughness `factors.roughness` times its green, at the
/// coordinates interpolated across each triangle from one per corner (in
/// the order of [`ShapeDesc::vertex_normals`]; empty without a texture).
/// So a metal's specular colour follows its base colour texture too.
#[derive(Clone, Debug, PartialEq)]
pub struct MetallicRoughnessMap {
    pub factors: MetallicRoughness,
    pub texture: Option<TextureId>,
    pub uvs: Vec<[Vec2; 3]>,
}

/// A light that is not a shape. Area lights are shapes with an emissive
/// material ([`Material::Emissive`]), as in Mitsuba, Cycles and pbrt.
#[derive(Clone, Debug, PartialEq)]
pub enum LightDesc {
    Point(PointLight),
    Spot(SpotLight),
    Directional(DirectionalLight),
    /// Light from infinitely far in every direction (one per scene).
    Environment(EnvironmentLight),
}

impl From<LightDesc> for Light {
    fn from(light: LightDesc) -> Self {
        match light {
            LightDesc::Point(l) => Light::Point(l),
            LightDesc::Spot(l) => Light::Spot(l),
            LightDesc::Directional(l) => Light::Directional(l),
            LightDesc::Environment(l) => Light::Environment(l),
        }
    }
}

/// An emitter of a description: a light of [`SceneDesc::lights`] or an
/// emissive shape item of [`SceneDesc::shapes`] (all its quads, spheres
/// and its mesh light), by index.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum GroupMember {
    Light(usize),
    Shape(usize),
}

/// An emitter's membership of a named light group.
#[derive(Clone, Debug, PartialEq)]
pub struct LightGroupMember {
    pub member: GroupMember,
    pub group: String,
    pub origin: Origin,
}

/// Where a medium is.
#[derive(Clone, Debug, PartialEq)]
pub enum RegionDesc {
    /// All of space (uniform density only).
    Everywhere,
    Box(Bounds),
    /// The inside of a closed triangle mesh.
    Mesh(Vec<Triangle>),
}

/// A general medium (`[[media]]`): RGB extinction `sigma_t` (per scene
/// unit) scaled by a dimensionless `density` field over its region,
/// single-scattering `albedo`, and a phase function.
#[derive(Clone, Debug, PartialEq)]
pub struct MediumDesc {
    pub sigma_t: Rgb,
    pub albedo: Rgb,
    pub phase: PhaseFunction,
    pub density: Density,
    pub region: RegionDesc,
    /// Light the medium emits (docs/physics.md §2.5), if any.
    pub emission: Option<Emission>,
    pub origin: Origin,
}

impl RegionDesc {
    /// The region's bounding box (infinite for all of space).
    pub fn bounds(&self) -> Bounds {
        match self {
            RegionDesc::Everywhere => Bounds {
                min: glam::Vec3::splat(f32::NEG_INFINITY),
                max: glam::Vec3::splat(f32::INFINITY),
            },
            RegionDesc::Box(b) => *b,
            RegionDesc::Mesh(triangles) => triangles
                .iter()
                .fold(Bounds::EMPTY, |b, t| b.union(t.bounds())),
        }
    }
}

/// How glass appears to camera rays and combines along shadow rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GlassSettings {
    pub model: GlassModel,
    /// Draw glass as an opaque diffuse surface of its colour to camera
    /// rays, as the paper did for its figures; shadow rays still pass.
    pub opaque_to_camera: bool,
}

/// A whole scene as plain data, with its render settings.
///
/// Lights are numbered, for sampling, in a fixed order: the emissive
/// shapes in the order of [`SceneDesc::shapes`] (a box's faces in its
/// order), then [`SceneDesc::lights`].
#[derive(Clone, Debug, PartialEq)]
pub struct SceneDesc {
    pub camera: Sourced<CameraSpec>,
    /// Materials, indexed by [`ShapeDesc::material`].
    pub materials: Vec<Sourced<Material>>,
    /// Colour textures, indexed by [`SurfaceTexture::texture`]; shared,
    /// not copied, by descriptions and scenes.
    pub textures: Vec<Sourced<Arc<Texture>>>,
    pub shapes: Vec<ShapeDesc>,
    pub lights: Vec<Sourced<LightDesc>>,
    /// Homogeneous grey fog (the paper's medium).
    pub fog: Option<Sourced<Fog>>,
    /// General media (RGB, non-uniform, mesh-bounded); only `volpath`
    /// renders them.
    pub media: Vec<MediumDesc>,
    /// Which emitters are in named light groups (the AOV
    /// `light_groups`, module [`crate::light_groups`]); the others are in
    /// [`crate::light_groups::OTHER_NAME`].
    pub light_groups: Vec<LightGroupMember>,
    /// Radiance of rays that leave the scene (linear RGB), seen but
    /// lighting nothing in the single-scattering integrators; an
    /// environment light ([`LightDesc::Environment`]) replaces it.
    pub background: Rgb,
    pub glass: GlassSettings,
    /// How estimates choose among the lights (the light tree or every
    /// light).
    pub light_sampling: LightSampling,
    pub settings: RenderSettings,
    /// Where the settings, [`SceneDesc::background`],
    /// [`SceneDesc::glass`] and [`SceneDesc::light_sampling`] were given
    /// (a `[render]` table).
    pub settings_origin: Origin,
    /// Output file named by the scene, if any.
    pub output: Option<PathBuf>,
    /// What the loader accepted but warns about (non-physical values,
    /// approximated features).
    pub warnings: Vec<String>,
}

/// An error in a description: the item's origin, the field (the key a
/// file gave it by, when the loader knows it) and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DescError {
    pub origin: Origin,
    /// The field of the item the error is about (`radius`, `material`).
    pub field: &'static str,
    pub message: String,
}

impl DescError {
    pub fn new(origin: &Origin, field: &'static str, message: impl Into<String>) -> Self {
        Self {
            origin: origin.clone(),
            field,
            message: message.into(),
        }
    }
}

impl fmt::Display for DescError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.origin {
            Origin::Code => write!(f, "{}", self.message),
            _ => write!(f, "{}: {}", self.origin, self.message),
        }
    }
}

impl std::error::Error for DescError {}

impl SceneDesc {
    /// An empty scene seen by `camera`, with default settings.
    pub fn new(camera: Sourced<CameraSpec>) -> Self {
        Self {
            camera,
            materials: Vec::new(),
            textures: Vec::new(),
            shapes: Vec::new(),
            lights: Vec::new(),
            fog: None,
            media: Vec::new(),
            light_groups: Vec::new(),
            background: Rgb::ZERO,
            glass: GlassSettings::default(),
            light_sampling: LightSampling::default(),
            settings: RenderSettings::default(),
            settings_origin: Origin::Code,
            output: None,
            warnings: Vec::new(),
        }
    }

    /// Adds a material; its index is what shapes name.
    pub fn add_material(&mut self, material: Material, origin: Origin) -> MaterialId {
        self.materials.push(Sourced::new(material, origin));
        (self.materials.len() - 1) as MaterialId
    }

    /// Adds a texture; its index is what [`SurfaceTexture`]s name.
    pub fn add_texture(&mut self, texture: Arc<Texture>, origin: Origin) -> TextureId {
        self.textures.push(Sourced::new(texture, origin));
        (self.textures.len() - 1) as TextureId
    }

    /// Adds shapes sharing one material.
    pub fn add_shapes(&mut self, shapes: Vec<Shape>, material: MaterialId, origin: Origin) {
        self.shapes.push(ShapeDesc {
            shapes,
            material,
            origin,
            vertex_normals: Vec::new(),
            texture: None,
            vertex_colours: Vec::new(),
            normal_map: None,
            emission_map: None,
            metallic_roughness: None,
            coverage: None,
        });
    }

    /// Adds a mesh with its per-corner attributes: unit normals for
    /// smooth shading ([`ShapeDesc::vertex_normals`]; empty for flat
    /// shading), vertex colours, a colour texture, a normal map, an
    /// emission texture and a metallic-roughness surface, if any.
    pub fn add_mesh(
        &mut self,
        triangles: Vec<Triangle>,
        attributes: MeshAttributes,
        material: MaterialId,
        origin: Origin,
    ) {
        let MeshAttributes {
            vertex_normals,
            vertex_colours,
            texture,
            normal_map,
            emission_map,
            metallic_roughness,
            coverage,
        } = attributes;
        self.shapes.push(ShapeDesc {
            shapes: triangles.into_iter().map(Shape::Triangle).collect(),
            material,
            origin,
            vertex_normals,
            texture,
            vertex_colours,
            normal_map,
            emission_map,
            metallic_roughness,
            coverage,
        });
    }

    /// Adds a quad area light: an emissive quad, seen, occluding and
    /// sampled (see [`Scene::build`](crate::scene::Scene::build)).
    pub fn add_quad_light(
        &mut self,
        quad: crate::shapes::Quad,
        radiance: Rgb,
        two_sided: bool,
        origin: Origin,
    ) {
        let material = self.add_material(Material::emitter(radiance, two_sided), origin.clone());
        self.add_shapes(vec![Shape::Quad(quad)], material, origin);
    }

    pub fn add_light(&mut self, light: LightDesc, origin: Origin) {
        self.lights.push(Sourced::new(light, origin));
    }

    /// Puts `member` in the light group named `group` (validated with
    /// the description: a name, not [`crate::light_groups::OTHER_NAME`],
    /// an emitter, in one group only).
    pub fn add_to_light_group(&mut self, member: GroupMember, group: String, origin: Origin) {
        self.light_groups.push(LightGroupMember {
            member,
            group,
            origin,
        });
    }

    /// The light group named for light `index` of [`SceneDesc::lights`]
    /// or for shape item `index` of [`SceneDesc::shapes`], if any.
    pub fn light_group_of(&self, member: GroupMember) -> Option<&str> {
        self.light_groups
            .iter()
            .find(|m| m.member == member)
            .map(|m| m.group.as_str())
    }

    pub(crate) fn is_emissive(&self, material: MaterialId) -> bool {
        matches!(
            self.materials.get(material as usize).map(|m| &m.value),
            Some(Material::Emissive { .. })
        )
    }

    /// Warnings about lighting that will silently produce nothing.
    pub fn lighting_warnings(&self) -> Vec<String> {
        let mut warnings = Vec::new();
        let emissive: Vec<&ShapeDesc> = self
            .shapes
            .iter()
            .filter(|s| self.is_emissive(s.material))
            .collect();
        let emitting_media = self.media.iter().any(|m| m.emission.is_some());
        if self.lights.is_empty() && emissive.iter().all(|s| s.shapes.is_empty()) && !emitting_media
        {
            warnings.push(
                "the scene has no lights: only emissive surfaces will be visible \
                 (`--environment` lights it from a sky)"
                    .into(),
            );
        }
        let unbounded_fog = self
            .fog
            .as_ref()
            .is_some_and(|fog| fog.value.bounds.is_none() && fog.value.sigma_t > 0.0);
        let unbounded_volume = self
            .media
            .iter()
            .any(|m| m.region == RegionDesc::Everywhere && m.sigma_t.max_element() > 0.0);
        if unbounded_fog || unbounded_volume {
            // Lights from infinitely far, each kind named once.
            let has = |kind: fn(&LightDesc) -> bool| self.lights.iter().any(|l| kind(&l.value));
            for (kind, present) in [
                (
                    "a directional light",
                    has(|l| matches!(l, LightDesc::Directional(_))),
                ),
                (
                    "an environment light",
                    has(|l| matches!(l, LightDesc::Environment(_))),
                ),
            ] {
                if present {
                    warnings.push(format!(
                        "{kind} shines into fog that fills all space: its light is fully extinguished before it arrives; bound the medium with a box"
                    ));
                }
            }
        }
        warnings
    }

    /// Makes `environment` the scene's environment light (the command
    /// line's `--environment`), in place of any it had and of its
    /// `background`: the environment is what rays leaving the scene see.
    pub fn set_environment(&mut self, environment: EnvironmentLight, origin: Origin) {
        let removed: Vec<usize> = (0..self.lights.len())
            .filter(|&i| matches!(self.lights[i].value, LightDesc::Environment(_)))
            .collect();
        self.lights
            .retain(|l| !matches!(l.value, LightDesc::Environment(_)));
        // The lights after a removed one move down: so do their groups.
        self.light_groups.retain_mut(|m| match &mut m.member {
            GroupMember::Light(i) if removed.contains(i) => false,
            GroupMember::Light(i) => {
                *i -= removed.iter().filter(|&&r| r < *i).count();
                true
            }
            GroupMember::Shape(_) => true,
        });
        self.background = Rgb::ZERO;
        self.add_light(LightDesc::Environment(environment), origin);
    }

    /// Applies command-line fog settings (the paper's `--density` and
    /// `--albedo`): they change the scene's fog, or add fog filling all
    /// space (albedo 1 unless given) if it has none.
    pub fn override_fog(
        &mut self,
        density: Option<f32>,
        albedo: Option<f32>,
    ) -> Result<(), String> {
        if let Some(d) = density {
            if !(d >= 0.0 && d.is_finite()) {
                return Err(format!("--density must be a non-negative number, got {d}"));
            }
            limits::check_fog_extinction(d).map_err(|e| format!("--density: {e}"))?;
        }
        if let Some(a) = albedo {
            if !(a >= 0.0 && a.is_finite()) {
                return Err(format!("--albedo must be a non-negative number, got {a}"));
            }
            limits::check_fog_albedo(Rgb::splat(a)).map_err(|e| format!("--albedo: {e}"))?;
        }
        match (&mut self.fog, density) {
            (Some(fog), _) => {
                if let Some(d) = density {
                    fog.value.sigma_t = d;
                }
                if let Some(a) = albedo {
                    fog.value.albedo = Rgb::splat(a);
                }
            }
            (None, Some(d)) => {
                self.fog = Some(Sourced::code(Fog {
                    sigma_t: d,
                    albedo: Rgb::splat(albedo.unwrap_or(1.0)),
                    phase: PhaseFunction::Isotropic,
                    bounds: None,
                }));
            }
            (None, None) if albedo.is_some() => {
                return Err(
                    "--albedo needs fog: this scene has none, so give --density too".into(),
                );
            }
            (None, None) => {}
        }
        Ok(())
    }

    /// Applies a command-line Henyey–Greenstein asymmetry `--g` to the
    /// scene's fog (after [`Self::override_fog`], so `--density` may have
    /// added the fog); `g` in (−1, 1), 0 is isotropic.
    pub fn override_fog_asymmetry(&mut self, g: f32) -> Result<(), String> {
        if !(g.is_finite() && g.abs() <= 0.999) {
            return Err(format!("--g must be in [−0.999, 0.999], got {g}"));
        }
        let fog = self
            .fog
            .as_mut()
            .ok_or("--g needs fog: this scene has none, so give --density too")?;
        fog.value.phase = PhaseFunction::from_asymmetry(g);
        Ok(())
    }
}
