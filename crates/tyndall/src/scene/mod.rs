//! The scene: geometry, materials, lights, fog and camera; and its loaders.
//!
//! [`Scene`] is what the integrators read. It is built through
//! [`SceneBuilder`] by the native TOML loader ([`native`]), the paper's
//! legacy .obj loader ([`legacy`]) and the built-in demo ([`demo`]).

pub mod demo;
pub mod legacy;
pub mod limits;
pub mod mesh;
pub mod native;
mod source;

pub use source::{SceneError, SourceText};

use crate::accel::{Geometry, Primitive};
use crate::camera::CameraSpec;
use crate::color::Rgb;
use crate::glass::GlassModel;
use crate::lights::{Light, QuadLight, SphereLight};
use crate::materials::{Material, MaterialId};
use crate::media::Fog;
use crate::media::volume::Volume;
use crate::render::RenderSettings;
use crate::shapes::{Quad, Shape};
use std::path::PathBuf;

/// How glass appears to camera rays and combines along shadow rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GlassSettings {
    pub model: GlassModel,
    /// Draw glass as an opaque diffuse surface of its colour to camera
    /// rays, as the paper did for its figures; shadow rays still pass.
    pub opaque_to_camera: bool,
}

/// Everything the integrators need to know about the world.
pub struct Scene {
    pub camera: CameraSpec,
    pub geometry: Geometry,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    pub fog: Option<Fog>,
    /// General media (RGB, non-uniform, mesh-bounded); only `volpath`
    /// renders them.
    pub volumes: Vec<Volume>,
    /// Radiance of rays that leave the scene (linear RGB).
    pub background: Rgb,
    pub glass: GlassSettings,
    /// (primitive, light) pairs of area lights, by primitive: the
    /// emissive quad or sphere a path may hit and the light that samples
    /// it.
    area_lights: Vec<(u32, u32)>,
    /// How many of the lights are quads.
    quad_lights: usize,
    /// The primitive of each light that has geometry, by light.
    light_primitives: Vec<Option<u32>>,
}

impl Scene {
    /// The index of the area light whose geometry is `primitive`.
    pub fn area_light_at(&self, primitive: u32) -> Option<usize> {
        self.area_lights
            .binary_search_by_key(&primitive, |&(p, _)| p)
            .ok()
            .map(|i| self.area_lights[i].1 as usize)
    }

    /// The primitive that is light number `light`'s geometry, if it has
    /// any (area lights).
    pub fn light_primitive(&self, light: usize) -> Option<u32> {
        self.light_primitives.get(light).copied().flatten()
    }

    /// How many quad area lights the scene has (emissive quads included):
    /// the lights `volpath` starts light subpaths from.
    pub fn quad_light_count(&self) -> usize {
        self.quad_lights
    }

    pub fn material(&self, primitive: u32) -> &Material {
        &self.materials[self.geometry.primitive(primitive).material as usize]
    }
}

/// A loaded scene with its render settings and the warnings the loader
/// raised (non-physical values it accepted, features it approximated).
pub struct SceneDescription {
    pub scene: Scene,
    pub settings: RenderSettings,
    /// Output file named by the scene, if any.
    pub output: Option<PathBuf>,
    pub warnings: Vec<String>,
}

/// Collects primitives, materials and lights, then builds the BVH.
pub struct SceneBuilder {
    pub camera: CameraSpec,
    pub fog: Option<Fog>,
    pub volumes: Vec<Volume>,
    pub background: Rgb,
    pub glass: GlassSettings,
    materials: Vec<Material>,
    area_lights: Vec<(u32, u32)>,
    primitives: Vec<Primitive>,
    lights: Vec<Light>,
    unsampled_emitters: usize,
}

impl SceneBuilder {
    pub fn new(camera: CameraSpec) -> Self {
        Self {
            camera,
            fog: None,
            volumes: Vec::new(),
            background: Rgb::ZERO,
            glass: GlassSettings::default(),
            area_lights: Vec::new(),
            materials: Vec::new(),
            primitives: Vec::new(),
            lights: Vec::new(),
            unsampled_emitters: 0,
        }
    }

    pub fn add_material(&mut self, material: Material) -> MaterialId {
        self.materials.push(material);
        (self.materials.len() - 1) as MaterialId
    }

    /// Adds a shape with its material. Thin glass is always two-sided: a
    /// pane tints light the same whichever way it crosses, so one-sided
    /// culling (the course code's, for opaque back faces) never applies
    /// to it — for camera rays, shadow rays and shadow maps alike.
    ///
    /// An emissive quad (a box's faces included) or sphere is an area
    /// light, as in Mitsuba, Cycles and pbrt: sampled by every
    /// integrator's NEE and weighed by MIS where BSDF or phase sampling
    /// hits it; an emissive quad exactly like a `[[lights]]` quad.
    /// Emissive triangles (meshes) glow where seen but are not sampled yet
    /// ([`SceneBuilder::unsampled_emitters`]).
    pub fn add_shape(&mut self, shape: Shape, material: MaterialId) {
        let shape = match self.materials[material as usize] {
            Material::Glass(_) => shape.two_sided(),
            _ => shape,
        };
        if let Material::Emissive {
            radiance,
            two_sided,
        } = self.materials[material as usize]
        {
            let light = match shape {
                Shape::Quad(quad) => Some(Light::Quad(QuadLight {
                    quad,
                    radiance,
                    two_sided,
                })),
                Shape::Sphere(sphere) => Some(Light::Sphere(SphereLight {
                    sphere,
                    radiance,
                    two_sided,
                })),
                _ => None,
            };
            match light {
                Some(light) => {
                    self.area_lights
                        .push((self.primitives.len() as u32, self.lights.len() as u32));
                    self.lights.push(light);
                }
                None => self.unsampled_emitters += 1,
            }
        }
        self.primitives.push(Primitive { shape, material });
    }

    /// How many emissive shapes are not lights (triangles): they
    /// glow when seen, and `volpath` finds their light only when a path
    /// hits them by chance; `march` and `single` not at all.
    pub fn unsampled_emitters(&self) -> usize {
        self.unsampled_emitters
    }

    pub fn add_light(&mut self, light: Light) {
        self.lights.push(light);
    }

    /// A quad area light: an emissive quad, seen, occluding and sampled
    /// (see [`SceneBuilder::add_shape`]).
    pub fn add_quad_light(&mut self, quad: Quad, radiance: Rgb, two_sided: bool) {
        let material = self.add_material(Material::Emissive {
            radiance,
            two_sided,
        });
        self.add_shape(Shape::Quad(quad), material);
    }

    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    pub fn build(self) -> Scene {
        let quad_lights = self
            .lights
            .iter()
            .filter(|l| matches!(l, Light::Quad(_)))
            .count();
        let mut light_primitives = vec![None; self.lights.len()];
        for &(primitive, light) in &self.area_lights {
            light_primitives[light as usize] = Some(primitive);
        }
        Scene {
            light_primitives,
            camera: self.camera,
            geometry: Geometry::new(self.primitives),
            materials: self.materials,
            lights: self.lights,
            fog: self.fog,
            volumes: self.volumes,
            background: self.background,
            glass: self.glass,
            quad_lights,
            // Pushed in primitive order, so already sorted.
            area_lights: self.area_lights,
        }
    }
}

/// Checks that a camera can be built: distinct position and target, an
/// up vector not parallel to the view direction.
pub(crate) fn check_camera(spec: &CameraSpec) -> Result<(), String> {
    let forward = spec.look_at - spec.position;
    let has_direction = forward.length_squared() > 0.0; // false for NaN too
    if !has_direction {
        return Err("the camera's look-at point must differ from its position".into());
    }
    let up_length = spec.up.length_squared(); // 0 when it underflows
    if !(up_length > 0.0 && up_length.is_finite()) {
        return Err(
            "the camera's up vector must be a non-zero direction (of length between 1e-19 and 1e19)"
                .into(),
        );
    }
    let up_across_view = forward
        .normalize()
        .cross(spec.up.normalize())
        .length_squared()
        > 1e-10;
    if !up_across_view {
        return Err("the camera's up vector must not be parallel to its view direction".into());
    }
    Ok(())
}

/// Relative tolerance for four corners to form a parallelogram.
const PARALLELOGRAM_TOLERANCE: f32 = 1e-4;

/// A quad from four corners listed around a parallelogram.
pub(crate) fn parallelogram(c: [glam::Vec3; 4], one_sided: bool) -> Result<Quad, String> {
    let scale = c
        .iter()
        .map(|p| p.abs().max_element())
        .fold(1.0f32, f32::max);
    let expected = c[1] + c[3] - c[0];
    if (expected - c[2]).length() > PARALLELOGRAM_TOLERANCE * scale {
        return Err(format!(
            "the corners must form a parallelogram listed in order around it (the third corner should be {:?})",
            expected.to_array()
        ));
    }
    Quad::new(c[0], c[1] - c[0], c[3] - c[0], one_sided)
        .ok_or_else(|| "the corners must span a parallelogram of non-zero area".to_string())
}

/// Warnings about lighting that will silently produce nothing.
pub(crate) fn check_lighting(builder: &SceneBuilder, warnings: &mut Vec<String>) {
    if builder.lights().is_empty() {
        warnings.push("the scene has no lights: only emissive surfaces will be visible".into());
    }
    if builder.unsampled_emitters() > 0 {
        warnings.push(format!(
            "{} emissive triangle(s) (meshes) glow where seen but are not sampled as lights: \
             `march` and `single` get no light from them, `volpath` only by chance; \
             emissive quads, boxes and spheres are area lights",
            builder.unsampled_emitters()
        ));
    }
    let unbounded_fog = builder
        .fog
        .is_some_and(|fog| fog.bounds.is_none() && fog.sigma_t > 0.0);
    let unbounded_volume = builder
        .volumes
        .iter()
        .any(|v| v.is_unbounded() && v.max_extinction() > 0.0);
    if (unbounded_fog || unbounded_volume)
        && builder
            .lights()
            .iter()
            .any(|l| matches!(l, Light::Directional(_)))
    {
        warnings.push(
            "a directional light shines into fog that fills all space: its light is fully extinguished before it arrives; bound the medium with a box"
                .into(),
        );
    }
}

impl SceneDescription {
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
        match (&mut self.scene.fog, density) {
            (Some(fog), _) => {
                if let Some(d) = density {
                    fog.sigma_t = d;
                }
                if let Some(a) = albedo {
                    fog.albedo = Rgb::splat(a);
                }
            }
            (None, Some(d)) => {
                self.scene.fog = Some(Fog {
                    sigma_t: d,
                    albedo: Rgb::splat(albedo.unwrap_or(1.0)),
                    phase: crate::phase::PhaseFunction::Isotropic,
                    bounds: None,
                });
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
            .scene
            .fog
            .as_mut()
            .ok_or("--g needs fog: this scene has none, so give --density too")?;
        fog.phase = crate::phase::PhaseFunction::from_asymmetry(g);
        Ok(())
    }
}
