//! The native scene format: TOML, documented in docs/scene-format.md.
//!
//! Parsing is serde's ([`tables`]; unknown keys are errors). The loader
//! turns the tables into a [`SceneDesc`], reading the files they name
//! (meshes, grids, included glTF), and checks what it needs to convert
//! (directions, corners, boxes, angles); [`SceneDesc::validate`] checks
//! every value. Each item's origin is its table's span, so every error —
//! the loader's or the validation's — is reported at the offending key's
//! line and column.

use crate::files::ReadOnce;
use crate::ies::IesFile;
use crate::mesh::{MeshTransform, MeshTriangles, load_obj_mesh};
use crate::source::{SceneError, SourceText};
use glam::Vec3;
use serde_spanned::Spanned;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;
use tyndall::camera::{Aperture, CameraSpec, FieldOfView};
use tyndall::color::Rgb;
use tyndall::description::{
    GlassSettings, GroupMember, MeshAttributes, Origin, SceneDesc, Sourced,
};
use tyndall::glass::{Glass, GlassModel};
use tyndall::lights::LightSampling;
use tyndall::limits;
use tyndall::materials::{Material, MaterialId, Surface};
use tyndall::media::Fog;
use tyndall::phase::PhaseFunction;
use tyndall::settings::{
    DEFAULT_MAP_RESOLUTION, IntegratorKind, RenderSettings, VisibilityMode, check_map_resolution,
};
use tyndall::shapes::{Bounds, Quad, Shape, Sphere, box_faces};
use tyndall::texture::{Texture, TextureId};

mod lights;
mod medium;
mod principled;
mod tables;
mod triangles;

use tables::*;

/// Loads a native scene file.
pub fn load(path: &Path) -> Result<SceneDesc, SceneError> {
    load_frame(path, None)
}

/// Loads a native scene file whose file sequences (`####`,
/// [`crate::sequence`]) are read at `frame`.
pub fn load_frame(path: &Path, frame: Option<u32>) -> Result<SceneDesc, SceneError> {
    let source = SourceText::read(path)?;
    parse_frame(&source, frame)
}

/// Parses native scene text; relative paths resolve against the
/// directory of `source.path`. The description is validated
/// ([`SceneDesc::validate`]), its errors placed at the offending key.
pub fn parse(source: &SourceText) -> Result<SceneDesc, SceneError> {
    parse_frame(source, None)
}

/// [`parse`], with the scene's file sequences read at `frame`; a frame
/// that no file uses is reported in the warnings.
pub fn parse_frame(source: &SourceText, frame: Option<u32>) -> Result<SceneDesc, SceneError> {
    parse_with_arrays(source, frame, &[])
}

/// [`parse_frame`], with `arrays` given beside the text: where a flat
/// array of numbers is expected (a `triangles` shape's `positions`,
/// `indices`, `normals`, `uvs`, a medium's inline `mesh`), the string
/// `"@array:K"` stands for `arrays[K]`, little-endian 32-bit numbers
/// (floats; unsigned integers for `indices`). A program that builds
/// scenes in memory (`tyndall.Scene.from_dict`) hands over large meshes
/// this way instead of writing every number as text.
pub fn parse_with_arrays(
    source: &SourceText,
    frame: Option<u32>,
    arrays: &[Vec<u8>],
) -> Result<SceneDesc, SceneError> {
    let file: SceneFile = toml::from_str(&source.text).map_err(|e| {
        let offset = e.span().map_or(0, |s| s.start);
        locate_parse_error(source, offset, e.message().trim_end())
    })?;
    let mut desc = Loader {
        source,
        file: Arc::from(source.path.as_path()),
        warnings: Vec::new(),
        frame,
        frame_used: std::cell::Cell::new(false),
        base_textures: BTreeMap::new(),
        arrays,
        gobo_images: ReadOnce::new(),
        ies_files: ReadOnce::new(),
        base_color_images: ReadOnce::new(),
    }
    .build(file)?;
    if let Some(e) = source.locate_all(&desc.errors()) {
        return Err(e);
    }
    let lighting = desc.lighting_warnings();
    desc.warnings.extend(lighting);
    Ok(desc)
}

struct Loader<'a> {
    source: &'a SourceText,
    /// The file, shared by the origins of its items.
    file: Arc<Path>,
    warnings: Vec<String>,
    /// The frame file sequences are read at.
    frame: Option<u32>,
    /// Whether a file sequence took the frame.
    frame_used: std::cell::Cell<bool>,
    /// The base colour textures of principled materials, by material.
    base_textures: BTreeMap<MaterialId, principled::BaseColorTexture>,
    /// The arrays given beside the text ([`parse_with_arrays`]).
    arrays: &'a [Vec<u8>],
    /// Gobo images, IES profiles and base colour textures (the scene's
    /// texture made of each) by file, each read once.
    gobo_images: ReadOnce<Arc<Texture>>,
    ies_files: ReadOnce<IesFile>,
    base_color_images: ReadOnce<TextureId>,
}

impl Loader<'_> {
    /// The origin of a table spanning `span`.
    fn origin(&self, span: &Range<usize>) -> Origin {
        Origin::Span {
            file: self.file.clone(),
            span: span.clone(),
        }
    }

    fn err(&self, span: &Range<usize>, key: &str, message: impl Into<String>) -> SceneError {
        self.source.error_at_key(span.clone(), key, message)
    }

    /// A position (or placement) whose coordinates are finite and within
    /// [`limits::MAX_COORDINATE`].
    fn vec3(&self, span: &Range<usize>, key: &str, v: V3) -> Result<Vec3, SceneError> {
        let v = Vec3::from_array(v);
        limits::check_coordinates(&format!("`{key}`"), v).map_err(|m| self.err(span, key, m))?;
        Ok(v)
    }

    /// A unit direction from any finite non-zero vector (scaled before
    /// normalising, so `[0, -1, -1.5e38]` does not overflow to zero).
    fn direction(&self, span: &Range<usize>, key: &str, v: V3) -> Result<Vec3, SceneError> {
        let d = Vec3::from_array(v);
        if !d.is_finite() {
            return Err(self.err(
                span,
                key,
                format!("`{key}` must be finite numbers, got {v:?}"),
            ));
        }
        let scale = d.abs().max_element();
        let unit = if scale > 0.0 {
            (d / scale).normalize()
        } else {
            Vec3::ZERO
        };
        if unit.is_finite() && unit != Vec3::ZERO {
            Ok(unit)
        } else {
            Err(self.err(span, key, format!("`{key}` must be a non-zero direction")))
        }
    }

    /// An emitted quantity: non-negative, finite and at most
    /// [`limits::MAX_EMISSION`] per channel.
    fn emission(&self, span: &Range<usize>, key: &str, c: ColorValue) -> Result<Rgb, SceneError> {
        let c = self.color(span, key, c, false)?;
        limits::check_emission(&format!("`{key}`"), c).map_err(|m| self.err(span, key, m))?;
        Ok(c)
    }

    fn number(
        &self,
        span: &Range<usize>,
        key: &str,
        v: f32,
        range: (f32, f32),
        what: &str,
    ) -> Result<f32, SceneError> {
        if v.is_finite() && v >= range.0 && v <= range.1 {
            Ok(v)
        } else {
            Err(self.err(span, key, format!("`{key}` must be {what}, got {v}")))
        }
    }

    /// A non-negative finite colour, optionally at most 1 per channel.
    fn color(
        &self,
        span: &Range<usize>,
        key: &str,
        c: ColorValue,
        at_most_one: bool,
    ) -> Result<Rgb, SceneError> {
        let ok =
            c.0.iter()
                .all(|x| x.is_finite() && *x >= 0.0 && (!at_most_one || *x <= 1.0));
        if ok {
            Ok(Rgb::from_array(c.0))
        } else {
            let what = if at_most_one {
                "between 0 and 1"
            } else {
                "non-negative and finite"
            };
            Err(self.err(
                span,
                key,
                format!("`{key}` must be {what} in every channel, got {:?}", c.0),
            ))
        }
    }

    fn build(mut self, file: SceneFile) -> Result<SceneDesc, SceneError> {
        let camera = self.camera(&file.camera)?;
        let mut desc = SceneDesc::new(Sourced::new(camera, self.origin(&file.camera.span())));
        let (settings, output) = self.render(&file.render, &mut desc)?;
        if let Some(fog) = &file.fog {
            desc.fog = Some(Sourced::new(
                Self::fog(fog.get_ref()),
                self.origin(&fog.span()),
            ));
        }
        let mut material_ids: BTreeMap<&str, MaterialId> = BTreeMap::new();
        for (name, table) in &file.materials {
            let span = table.span();
            let (material, texture) = self.material(&span, table.get_ref(), &mut desc)?;
            let id = desc.add_material(material, self.origin(&span));
            material_ids.insert(name.as_str(), id);
            if let Some(texture) = texture {
                self.base_textures.insert(id, texture);
            }
        }
        for shape in &file.shapes {
            let before = Emitters::of(&desc);
            self.shape(shape, &material_ids, &mut desc)?;
            let group = shape.get_ref().light_group();
            self.light_group(&shape.span(), group, before, &mut desc);
        }
        for light in &file.lights {
            let before = Emitters::of(&desc);
            self.light(light, &mut desc)?;
            let group = light.get_ref().light_group();
            self.light_group(&light.span(), group, before, &mut desc);
        }
        for include in &file.include {
            self.include(include, &mut desc)?;
        }
        for medium in &file.media {
            let medium = self.medium(medium)?;
            desc.media.push(medium);
        }
        desc.settings = settings;
        desc.output = output;
        if let Some(frame) = self.frame
            && !self.frame_used.get()
        {
            self.warnings.push(format!(
                "frame {frame} is unused: {} names no file sequence (`####`)",
                self.source.path.display()
            ));
        }
        desc.warnings = self.warnings;
        Ok(desc)
    }

    /// Puts what one table added to `scene` since `before` (its shapes
    /// and lights) in the light group `group`, if it names one; the
    /// description's validation refuses a group on what does not emit.
    fn light_group(
        &self,
        span: &std::ops::Range<usize>,
        group: Option<&str>,
        before: Emitters,
        scene: &mut SceneDesc,
    ) {
        let Some(group) = group else {
            return;
        };
        let after = Emitters::of(scene);
        let members = (before.shapes..after.shapes)
            .map(GroupMember::Shape)
            .chain((before.lights..after.lights).map(GroupMember::Light));
        for member in members.collect::<Vec<_>>() {
            scene.add_to_light_group(member, group.to_owned(), self.origin(span));
        }
    }

    fn camera(&self, desc: &Spanned<CameraTable>) -> Result<CameraSpec, SceneError> {
        let span = desc.span();
        let c = desc.get_ref();
        let position = Vec3::from_array(c.position);
        let look_at = Vec3::from_array(c.look_at);
        // A lens radius of 0 is a pinhole; the focus defaults to the
        // look-at point's distance.
        let aperture = match (c.aperture_radius, c.focus_distance) {
            (None, Some(_)) => {
                return Err(self.err(
                    &span,
                    "focus_distance",
                    "`focus_distance` needs `aperture_radius` (a pinhole has no focus)",
                ));
            }
            (None, None) | (Some(0.0), _) => Aperture::Pinhole,
            (Some(radius), focus) => Aperture::ThinLens {
                radius,
                focus_distance: focus.unwrap_or_else(|| position.distance(look_at)),
            },
        };
        let spec = CameraSpec {
            position,
            look_at,
            up: self.direction(&span, "up", c.up)?,
            fov: FieldOfView::Vertical(c.fov_y_deg),
            aperture,
        };
        Ok(spec)
    }

    fn render(
        &self,
        desc: &Option<Spanned<RenderTable>>,
        scene: &mut SceneDesc,
    ) -> Result<(RenderSettings, Option<std::path::PathBuf>), SceneError> {
        let mut s = RenderSettings::default();
        let Some(desc) = desc else {
            return Ok((s, None));
        };
        let span = desc.span();
        let r = desc.get_ref();
        if let Some(w) = r.width {
            s.width = w;
        }
        if let Some(h) = r.height {
            s.height = h;
        }
        if let Some(spp) = r.spp {
            s.spp = spp;
        }
        if let Some(seed) = r.seed {
            s.seed = seed;
        }
        if let Some(name) = &r.integrator {
            s.integrator = IntegratorKind::from_name(name).ok_or_else(|| {
                self.err(
                    &span,
                    "integrator",
                    format!("unknown integrator `{name}`: expected `march`, `single` or `volpath`"),
                )
            })?;
        }
        if let Some(step) = r.step {
            s.step = step;
        }
        if let Some(n) = r.volume_samples {
            s.volume_samples = n;
        }
        if let Some(n) = r.max_depth {
            s.max_depth = n;
        }
        if let Some(n) = r.interleave {
            s.interleave = n;
        }
        let resolution = match r.shadow_map_resolution {
            // Checked even where visibility is "rays", which ignores it.
            Some(n) if let Err(e) = check_map_resolution(n) => {
                return Err(self.err(&span, e.setting, e.message));
            }
            Some(n) => n,
            None => DEFAULT_MAP_RESOLUTION,
        };
        s.visibility = match r.visibility.as_deref() {
            None | Some("rays") => VisibilityMode::ShadowRays,
            Some("maps") => VisibilityMode::Maps { resolution },
            Some(other) => {
                return Err(self.err(
                    &span,
                    "visibility",
                    format!("unknown visibility `{other}`: expected `rays` or `maps`"),
                ));
            }
        };
        if let Some(b) = r.max_bounces {
            s.max_bounces = b;
        }
        if let Some(e) = r.exposure {
            s.exposure = e;
        }
        if let Some(m) = &r.glass_model {
            scene.glass.model = match m.as_str() {
                "filter" => GlassModel::Filter,
                "blend" => GlassModel::Blend,
                other => {
                    return Err(self.err(
                        &span,
                        "glass_model",
                        format!("unknown glass model `{other}`: expected `filter` or `blend`"),
                    ));
                }
            };
        }
        if let Some(o) = r.glass_opaque {
            scene.glass = GlassSettings {
                opaque_to_camera: o,
                ..scene.glass
            };
        }
        if let Some(name) = &r.light_sampling {
            scene.light_sampling = LightSampling::from_name(name).ok_or_else(|| {
                self.err(
                    &span,
                    "light_sampling",
                    format!("unknown light sampling `{name}`: expected `auto`, `all` or `tree`"),
                )
            })?;
        }
        if let Some(bg) = r.background {
            scene.background = Rgb::from_array(bg.0);
        }
        scene.settings_origin = self.origin(&span);
        let output = r.output.as_ref().map(|o| self.relative(o));
        Ok((s, output))
    }

    fn relative(&self, p: &str) -> std::path::PathBuf {
        let dir = self.source.path.parent().unwrap_or(Path::new(""));
        dir.join(p)
    }

    /// The file a data `file` key names, relative to the scene: a frame
    /// sequence (`fluid_data_####.vdb`) at the chosen frame. The error
    /// names `key` in the table spanning `span`.
    fn data_file(
        &self,
        span: &Range<usize>,
        key: &str,
        pattern: &str,
    ) -> Result<std::path::PathBuf, SceneError> {
        let name =
            crate::sequence::frame_file(pattern, self.frame).map_err(|e| self.err(span, key, e))?;
        if crate::sequence::is_sequence(pattern) {
            self.frame_used.set(true);
        }
        Ok(self.relative(&name))
    }

    /// The fog of a `[fog]` table (its values checked by
    /// [`SceneDesc::validate`]).
    fn fog(f: &FogTable) -> Fog {
        Fog {
            sigma_t: f.sigma_t,
            albedo: Rgb::from_array(f.albedo.0),
            phase: PhaseFunction::from_asymmetry(f.g),
            bounds: f.bounds.as_ref().map(|b| Bounds {
                min: Vec3::from_array(b.min),
                max: Vec3::from_array(b.max),
            }),
        }
    }

    fn bounds(
        &self,
        span: &Range<usize>,
        key: &str,
        min: V3,
        max: V3,
    ) -> Result<Bounds, SceneError> {
        let (lo, hi) = (self.vec3(span, key, min)?, self.vec3(span, key, max)?);
        if lo.cmplt(hi).all() {
            Ok(Bounds { min: lo, max: hi })
        } else {
            Err(self.err(
                span,
                key,
                format!("box `min` {min:?} must be below `max` {max:?} on every axis"),
            ))
        }
    }

    /// The material of a `[materials.NAME]` table spanning `span` (its
    /// values checked by [`SceneDesc::validate`]), and a principled
    /// material's base colour texture ([`Loader::principled`]).
    fn material(
        &self,
        span: &Range<usize>,
        table: &MaterialTable,
        scene: &mut SceneDesc,
    ) -> Result<(Material, Option<principled::BaseColorTexture>), SceneError> {
        let material = match *table {
            MaterialTable::Diffuse(DiffuseTable { reflectance }) => {
                Material::Opaque(Surface::diffuse(Rgb::from_array(reflectance.0)))
            }
            MaterialTable::Mirror(MirrorTable { reflectance }) => Material::Opaque(
                Surface::layered(Rgb::ZERO, Rgb::from_array(reflectance.0), 0.0),
            ),
            MaterialTable::Glossy(GlossyTable {
                reflectance,
                roughness,
                diffuse,
            }) => Material::Opaque(Surface::layered(
                diffuse.map_or(Rgb::ZERO, |d| Rgb::from_array(d.0)),
                Rgb::from_array(reflectance.0),
                roughness,
            )),
            MaterialTable::Emissive(EmissiveTable {
                radiance,
                two_sided,
            }) => Material::emitter(Rgb::from_array(radiance.0), two_sided),
            MaterialTable::Glass(GlassTable { color, alpha }) => Material::Glass(Glass {
                color: Rgb::from_array(color.0),
                alpha,
            }),
            MaterialTable::Dielectric(DielectricTable { ior, absorption }) => {
                Material::Dielectric {
                    ior,
                    absorption: absorption.map_or(Rgb::ZERO, |a| Rgb::from_array(a.0)),
                }
            }
            MaterialTable::Principled(ref principled) => {
                return self.principled(span, principled, scene);
            }
        };
        Ok((material, None))
    }

    fn material_id(
        &self,
        span: &Range<usize>,
        name: &str,
        ids: &BTreeMap<&str, MaterialId>,
    ) -> Result<MaterialId, SceneError> {
        ids.get(name).copied().ok_or_else(|| {
            let known: Vec<&str> = ids.keys().copied().collect();
            self.err(
                span,
                "material",
                format!(
                    "unknown material `{name}`; defined materials: {}",
                    if known.is_empty() {
                        "none".into()
                    } else {
                        known.join(", ")
                    }
                ),
            )
        })
    }

    fn quad(
        &self,
        span: &Range<usize>,
        corners: &[V3; 4],
        one_sided: bool,
    ) -> Result<Quad, SceneError> {
        let mut c = [Vec3::ZERO; 4];
        for (slot, v) in c.iter_mut().zip(corners) {
            *slot = self.vec3(span, "corners", *v)?;
        }
        Quad::from_corners(c, one_sided).map_err(|m| self.err(span, "corners", m))
    }

    /// The material `name` of a shape that cannot carry a texture (it has
    /// no texture coordinates).
    fn untextured_material_id(
        &self,
        span: &Range<usize>,
        name: &str,
        ids: &BTreeMap<&str, MaterialId>,
    ) -> Result<MaterialId, SceneError> {
        let id = self.material_id(span, name, ids)?;
        if self.base_textures.contains_key(&id) {
            return Err(self.err(
                span,
                "material",
                format!(
                    "material `{name}` has a `base_color_texture`, which only a \
                     `triangles` shape with `uvs` can carry"
                ),
            ));
        }
        Ok(id)
    }

    fn shape(
        &mut self,
        desc: &Spanned<ShapeTable>,
        ids: &BTreeMap<&str, MaterialId>,
        scene: &mut SceneDesc,
    ) -> Result<(), SceneError> {
        let span = desc.span();
        let origin = self.origin(&span);
        match desc.get_ref() {
            ShapeTable::Sphere(SphereTable {
                center,
                radius,
                material,
                light_group: _,
            }) => {
                let m = self.untextured_material_id(&span, material, ids)?;
                let sphere = Sphere {
                    center: Vec3::from_array(*center),
                    radius: *radius,
                };
                scene.add_shapes(vec![Shape::Sphere(sphere)], m, origin);
            }
            ShapeTable::Quad(QuadTable {
                corners,
                material,
                one_sided,
                light_group: _,
            }) => {
                let m = self.untextured_material_id(&span, material, ids)?;
                let q = self.quad(&span, corners, *one_sided)?;
                scene.add_shapes(vec![Shape::Quad(q)], m, origin);
            }
            ShapeTable::Box(BoxShapeTable {
                min,
                max,
                material,
                light_group: _,
            }) => {
                let m = self.untextured_material_id(&span, material, ids)?;
                let b = self.bounds(&span, "min", *min, *max)?;
                let faces = box_faces(b).ok_or_else(|| {
                    self.err(&span, "min", "the box is too thin: its faces have no area")
                })?;
                scene.add_shapes(faces.map(Shape::Quad).to_vec(), m, origin);
            }
            ShapeTable::Mesh(MeshTable {
                file,
                material,
                translate,
                scale,
                rotate_deg,
                light_group: _,
            }) => {
                let m = self.untextured_material_id(&span, material, ids)?;
                let placement = (*translate, *scale, *rotate_deg);
                let mesh = self.mesh(&span, "file", file, placement)?;
                scene.add_mesh(
                    mesh.triangles,
                    MeshAttributes {
                        vertex_normals: mesh.vertex_normals,
                        ..MeshAttributes::default()
                    },
                    m,
                    origin,
                );
            }
            ShapeTable::Triangles(table) => {
                let m = self.material_id(&span, &table.material, ids)?;
                let texture = self.base_textures.get(&m).copied();
                let (triangles, attributes) = self.triangles(&span, table, texture)?;
                scene.add_mesh(triangles, attributes, m, origin);
            }
        }
        Ok(())
    }

    /// The triangles of mesh file `file` (named by key `key`), placed by
    /// (translate, scale, rotate_deg), with their vertex normals if the
    /// file gives them.
    fn mesh(
        &mut self,
        span: &Range<usize>,
        key: &str,
        file: &str,
        (translate, scale, rotate_deg): (Option<V3>, Option<ColorValue>, Option<V3>),
    ) -> Result<MeshTriangles, SceneError> {
        let transform = self.placement(span, (translate, scale, rotate_deg))?;
        let path = self.relative(file);
        let triangles = load_obj_mesh(&path, &transform).map_err(|m| self.err(span, key, m))?;
        if triangles.skipped_degenerate > 0 {
            self.warnings.push(format!(
                "{}: skipped {} degenerate triangles",
                path.display(),
                triangles.skipped_degenerate
            ));
        }
        Ok(triangles)
    }

    /// A placement from optional `translate`, `scale` and `rotate_deg`.
    fn placement(
        &self,
        span: &Range<usize>,
        (translate, scale, rotate_deg): (Option<V3>, Option<ColorValue>, Option<V3>),
    ) -> Result<MeshTransform, SceneError> {
        Ok(MeshTransform {
            translate: self.vec3(span, "translate", translate.unwrap_or([0.0; 3]))?,
            scale: match scale {
                Some(s) => {
                    let v = self.vec3(span, "scale", s.0)?;
                    if v.cmpeq(Vec3::ZERO).any() {
                        return Err(self.err(
                            span,
                            "scale",
                            "`scale` must be non-zero on every axis",
                        ));
                    }
                    v
                }
                None => Vec3::ONE,
            },
            rotate_deg: self.vec3(span, "rotate_deg", rotate_deg.unwrap_or([0.0; 3]))?,
        })
    }

    /// An `[[include]]`: the file's geometry, materials and lights.
    fn include(
        &mut self,
        desc: &Spanned<IncludeTable>,
        scene: &mut SceneDesc,
    ) -> Result<(), SceneError> {
        let span = desc.span();
        let d = desc.get_ref();
        let placement = self.placement(&span, (d.translate, d.scale, d.rotate_deg))?;
        let path = self.relative(&d.file);
        let warnings = crate::include(&path, placement.matrix(), scene)
            .map_err(|e| self.err(&span, "file", format!("cannot include: {e}")))?;
        self.warnings.extend(warnings);
        Ok(())
    }
}

/// How many shape items and lights a description holds: what a table
/// added is the difference.
#[derive(Clone, Copy)]
struct Emitters {
    shapes: usize,
    lights: usize,
}

impl Emitters {
    fn of(scene: &SceneDesc) -> Self {
        Emitters {
            shapes: scene.shapes.len(),
            lights: scene.lights.len(),
        }
    }
}
