//! The runtime scene: geometry in its BVH, materials, lights, fog, volumes
//! and camera, built from a [`SceneDesc`] by [`Scene::build`].
//!
//! [`Scene`] is what the integrators read. Loaders (crate `tyndall-load`)
//! produce descriptions; none builds a `Scene` itself.

pub use crate::description::GlassSettings;

mod corner_values;
mod surface_textures;

use crate::accel::{Geometry, Hit, Primitive};
use crate::camera::CameraSpec;
use crate::color::Rgb;
use crate::description::{DescError, GroupMember, MediumDesc, RegionDesc, SceneDesc};
use crate::footprint::Footprint;
use crate::light_groups::{LightGroup, LightGroups};
use crate::lights::{
    EmissionTexture, EnvironmentLight, Light, LightSampler, LightSampling, MeshLight, QuadLight,
    SphereLight,
};
use crate::materials::Material;
use crate::materials::{MetallicRoughness, Surface};
use crate::media::Fog;
use crate::media::emitters::MediaEmitters;
use crate::media::volume::{MeshRegion, Volume, VolumeRegion};
use crate::ray::Ray;
use crate::shapes::Shape;
use corner_values::CornerValues;
use glam::Vec3;
use std::ops::ControlFlow;
use surface_textures::SurfaceTextures;

/// An emissive quad, sphere or triangle a path may hit, the light that
/// samples it (one light for all the triangles of a mesh), and which of
/// a mesh light's triangles it is (0 for quads and spheres).
#[derive(Clone, Copy, Debug)]
struct EmitterPrimitive {
    primitive: u32,
    light: u32,
    triangle: u32,
}

/// Everything the integrators need to know about the world.
pub struct Scene {
    pub(crate) camera: CameraSpec,
    pub(crate) geometry: Geometry,
    pub(crate) materials: Vec<Material>,
    pub(crate) lights: Vec<Light>,
    /// Which lights each estimate connects to.
    pub(crate) light_sampler: LightSampler,
    /// The light group of each light.
    pub(crate) light_groups: LightGroups,
    pub(crate) fog: Option<Fog>,
    /// General media (RGB, non-uniform, mesh-bounded); only `volpath`
    /// renders them.
    pub(crate) volumes: Vec<Volume>,
    /// The emitting volumes as light sources for NEE.
    pub(crate) media_emitters: MediaEmitters,
    /// Radiance of rays that leave the scene (linear RGB) where there is
    /// no environment light.
    pub(crate) background: Rgb,
    /// The light number of the environment, if there is one.
    environment: Option<usize>,
    pub(crate) glass: GlassSettings,
    /// The emissive primitives of area lights, by primitive.
    area_lights: Vec<EmitterPrimitive>,
    /// How many of the lights have a flat emitting surface.
    flat_emitters: usize,
    /// The lights that are not Dirac deltas (area lights, the
    /// environment), by index.
    extended_lights: Vec<usize>,
    /// The primitive of each light that is one primitive (quads and
    /// spheres), by light.
    light_primitives: Vec<Option<u32>>,
    /// Vertex normals of smooth meshes.
    shading_normals: CornerValues,
    /// Linear colours of meshes' vertices (glTF `COLOR_0`).
    vertex_colours: CornerValues,
    /// Colour textures and the triangles they cover.
    textures: SurfaceTextures,
}

impl Scene {
    /// Where the camera is and how it looks.
    pub fn camera(&self) -> &CameraSpec {
        &self.camera
    }

    /// Every primitive in its BVH.
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }

    /// The materials, indexed by a primitive's material id.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// The lights, emissive shapes first (see [`SceneDesc`]).
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// How estimates choose among the lights, instead of the
    /// description's [`crate::SceneDesc::light_sampling`].
    pub fn set_light_sampling(&mut self, sampling: LightSampling) {
        self.light_sampler = LightSampler::new(&self.lights, sampling);
    }

    /// Which lights each estimate connects to.
    pub fn light_sampler(&self) -> &LightSampler {
        &self.light_sampler
    }

    /// The light groups and each light's.
    pub fn light_groups(&self) -> &LightGroups {
        &self.light_groups
    }

    /// The light group of light number `light`.
    #[inline]
    pub fn light_group(&self, light: usize) -> LightGroup {
        self.light_groups.of(light)
    }

    /// The light group of the light whose geometry `primitive` is (an
    /// emissive surface that is no light's: [`LightGroup::OTHER`]).
    #[inline]
    pub fn light_group_at(&self, primitive: u32) -> LightGroup {
        self.area_light_at(primitive)
            .map_or(LightGroup::OTHER, |light| self.light_group(light))
    }

    /// The light group of rays that leave the scene: the environment
    /// light's, or [`LightGroup::OTHER`] for the background.
    #[inline]
    pub fn escaped_group(&self) -> LightGroup {
        self.environment
            .map_or(LightGroup::OTHER, |light| self.light_group(light))
    }

    /// The homogeneous fog, if any.
    pub fn fog(&self) -> Option<&Fog> {
        self.fog.as_ref()
    }

    /// Whether `x` lies in the fog (where it scatters) or within the
    /// bounds of a general medium: where a point light's in-scattered
    /// radiance may diverge along rays passing it
    /// ([`crate::render::LightImages`]).
    pub fn in_medium(&self, x: Vec3) -> bool {
        let in_fog = self.fog.as_ref().is_some_and(|fog| {
            fog.sigma_t > 0.0
                && fog.albedo.max_element() > 0.0
                && fog.bounds.is_none_or(|b| b.contains(x))
        });
        in_fog || self.volumes.iter().any(|v| v.bounds().contains(x))
    }

    /// The general media (`[[media]]`), with their majorant grids.
    pub fn volumes(&self) -> &[Volume] {
        &self.volumes
    }

    /// Radiance of rays that leave the scene (linear RGB) where there is
    /// no environment light.
    pub fn background(&self) -> Rgb {
        self.background
    }

    /// The environment light and its light number, if there is one.
    #[inline]
    pub fn environment(&self) -> Option<(usize, &EnvironmentLight)> {
        let index = self.environment?;
        match &self.lights[index] {
            Light::Environment(e) => Some((index, e)),
            _ => None,
        }
    }

    /// Radiance arriving along a ray that leaves the scene in the unit
    /// `direction`: the environment's, or else the background.
    #[inline]
    pub fn escaped_radiance(&self, direction: Vec3) -> Rgb {
        match self.environment() {
            Some((_, e)) => e.radiance(direction),
            None => self.background,
        }
    }

    /// How glass appears to camera rays and combines along shadow rays.
    pub fn glass(&self) -> GlassSettings {
        self.glass
    }

    /// The index of the area light whose geometry is `primitive`.
    pub fn area_light_at(&self, primitive: u32) -> Option<usize> {
        self.emitter_primitive(primitive).map(|e| e.light as usize)
    }

    #[inline]
    fn emitter_primitive(&self, primitive: u32) -> Option<EmitterPrimitive> {
        self.area_lights
            .binary_search_by_key(&primitive, |e| e.primitive)
            .ok()
            .map(|i| self.area_lights[i])
    }

    /// The radiance `emitted` by the emissive material of `primitive`
    /// (from [`Material::event`]) as it leaves the primitive's point `p`:
    /// scaled by its mesh light's emission texture there, if it has one
    /// ([`MeshLight::radiance_at`]), the same radiance that light sampling
    /// finds at `p`.
    ///
    /// Where a camera ray's cone meets it (`footprint`), the texture is
    /// filtered over it; light sampling, and paths that scattered before,
    /// read it at a point ([`Footprint::POINT`]).
    #[inline]
    pub fn emitted_at(&self, emitted: Rgb, primitive: u32, p: Vec3, footprint: Footprint) -> Rgb {
        match self.emitter_primitive(primitive) {
            Some(e) => match &self.lights[e.light as usize] {
                Light::Mesh(mesh) if mesh.emission_texture().is_some() => {
                    mesh.radiance_over(e.triangle as usize, p, footprint)
                }
                _ => emitted,
            },
            None => emitted,
        }
    }

    /// The primitive that is light number `light`'s geometry, if it is one
    /// primitive (quad and sphere lights; a mesh light's point lies on
    /// one of many).
    pub fn light_primitive(&self, light: usize) -> Option<u32> {
        self.light_primitives.get(light).copied().flatten()
    }

    /// How many lights have a flat emitting surface
    /// ([`Light::is_flat_emitter`]: quads, emissive or `[[lights]]`): the
    /// lights `volpath` starts light subpaths from.
    pub fn flat_emitter_count(&self) -> usize {
        self.flat_emitters
    }

    /// The indices of the lights that are not Dirac deltas in position
    /// or direction ([`Light::is_delta`]): area lights and the
    /// environment.
    pub fn extended_lights(&self) -> &[usize] {
        &self.extended_lights
    }

    pub fn material(&self, primitive: u32) -> &Material {
        &self.materials[self.geometry.primitive(primitive).material as usize]
    }

    /// The shading normal at the point `p` of `primitive`: its vertex
    /// normals interpolated, if it is a triangle of a smooth mesh
    /// ([`ShapeDesc::vertex_normals`](crate::description::ShapeDesc)),
    /// bent by its normal map if it has one
    /// ([`crate::description::NormalMap`]; filtered over `footprint`); not
    /// oriented to any side.
    #[inline]
    pub fn shading_normal(&self, primitive: u32, p: Vec3, footprint: Footprint) -> Option<Vec3> {
        match &self.geometry.primitive(primitive).shape {
            Shape::Triangle(triangle) => {
                let smooth = self.shading_normals.normal_at(primitive, triangle, p);
                self.textures
                    .normal_at(
                        primitive,
                        triangle,
                        p,
                        smooth.unwrap_or(triangle.normal),
                        footprint,
                    )
                    .or(smooth)
            }
            Shape::Sphere(_) | Shape::Quad(_) => None,
        }
    }

    /// Whether some mesh is smooth-shaded (has vertex normals).
    pub fn has_vertex_normals(&self) -> bool {
        self.shading_normals.is_used()
    }

    /// Whether some mesh carries a colour texture.
    pub fn has_textures(&self) -> bool {
        self.textures.is_used()
    }

    /// Whether some mesh carries vertex colours.
    pub fn has_vertex_colours(&self) -> bool {
        self.vertex_colours.is_used()
    }

    /// Whether some surface has alpha coverage (glTF `MASK` or `BLEND`,
    /// [`crate::coverage`]).
    pub fn has_coverage(&self) -> bool {
        self.textures.has_coverage()
    }

    /// Whether `ray` passes primitive `primitive` where it meets it at
    /// distance `t`: a hole of its alpha coverage there, or a part of a
    /// partially covering surface that this ray misses
    /// ([`crate::coverage::Coverage::passes`]).
    #[inline]
    pub fn passes(&self, primitive: u32, ray: &Ray, t: f32) -> bool {
        match &self.geometry.primitive(primitive).shape {
            Shape::Triangle(triangle) => self.textures.passes(primitive, triangle, ray, t),
            _ => false,
        }
    }

    /// The nearest surface along `ray` with `t ∈ (0, t_max)`, the
    /// surfaces it passes by their coverage passed: what every
    /// integrator's rays hit.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        if !self.has_coverage() {
            return self.geometry.intersect(ray, t_max);
        }
        self.geometry
            .intersect_where(ray, t_max, |t, index| !self.passes(index, ray, t))
    }

    /// Whether any surface that `ray` does not pass by its coverage meets
    /// it before `t_max`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let mut hit = false;
        self.geometry.for_each_hit(ray, t_max, |t, index| {
            if self.has_coverage() && self.passes(index, ray, t) {
                return ControlFlow::Continue(());
            }
            hit = true;
            ControlFlow::Break(())
        });
        hit
    }

    /// The surface `surface` (the material of `primitive`) at its point
    /// `p`: its diffuse reflectance multiplied by the colour of the
    /// primitive's texture there, if it is a textured triangle
    /// ([`ShapeDesc::texture`](crate::description::ShapeDesc)), and by its
    /// vertex colours interpolated there, if it has them
    /// ([`ShapeDesc::vertex_colours`](crate::description::ShapeDesc)).
    /// A triangle with a metallic-roughness surface
    /// ([`ShapeDesc::metallic_roughness`](crate::description::ShapeDesc))
    /// has that surface instead, evaluated at `p` with its base colour
    /// multiplied by the same colours. Textures are filtered over
    /// `footprint` ([`crate::footprint`]).
    #[inline]
    pub fn surface_at(
        &self,
        surface: Surface,
        primitive: u32,
        p: Vec3,
        footprint: Footprint,
    ) -> Surface {
        let Shape::Triangle(triangle) = &self.geometry.primitive(primitive).shape else {
            return surface;
        };
        let texture = self.textures.at(primitive, triangle, p, footprint);
        let vertex = self.vertex_colours.at(primitive, triangle, p);
        if let Some(parameters) = self
            .textures
            .metallic_roughness_at(primitive, triangle, p, footprint)
        {
            let colour = texture.unwrap_or(Rgb::ONE) * vertex.unwrap_or(Rgb::ONE);
            return MetallicRoughness {
                base: parameters.base * colour,
                ..parameters
            }
            .surface();
        }
        match (texture, vertex) {
            (None, None) => surface,
            (texture, vertex) => Surface {
                diffuse: surface.diffuse * texture.unwrap_or(Rgb::ONE) * vertex.unwrap_or(Rgb::ONE),
                ..surface
            },
        }
    }
}

impl Scene {
    /// Builds the runtime scene from a description: checks it
    /// ([`SceneDesc::validate`]), makes every emissive quad (a box's faces
    /// included), sphere and triangle mesh (the triangles of one item) an
    /// area light — sampled by every integrator's NEE and weighed by MIS
    /// where BSDF or phase sampling hits it, as in Mitsuba, Cycles and
    /// pbrt — builds the BVH, and the volumes with their majorant grids.
    /// Errors name the item's origin.
    ///
    /// Thin glass is always two-sided: a pane tints light the same
    /// whichever way it crosses, so one-sided culling (the course code's,
    /// for opaque back faces) never applies to it — for camera rays,
    /// shadow rays and shadow maps alike.
    pub fn build(desc: &SceneDesc) -> Result<Scene, DescError> {
        desc.validate()?;
        let volumes = desc
            .media
            .iter()
            .map(|m| build_volume(m.clone()))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self::assemble(desc, volumes))
    }

    /// [`Scene::build`] consuming the description, so that its media's
    /// density grids and meshes move into the scene instead of being
    /// copied (a large OpenVDB cloud is not held twice).
    pub fn from_desc(mut desc: SceneDesc) -> Result<Scene, DescError> {
        desc.validate()?;
        let volumes = std::mem::take(&mut desc.media)
            .into_iter()
            .map(build_volume)
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self::assemble(&desc, volumes))
    }

    /// The scene of a validated description, with its volumes built.
    fn assemble(desc: &SceneDesc, volumes: Vec<Volume>) -> Scene {
        let materials: Vec<Material> = desc.materials.iter().map(|m| m.value).collect();
        let mut primitives = Vec::new();
        let mut lights = Vec::new();
        let mut area_lights = Vec::new();
        let mut shading_normals = CornerValues::default();
        let mut vertex_colours = CornerValues::default();
        let mut textures =
            SurfaceTextures::new(desc.textures.iter().map(|t| t.value.clone()).collect());
        // The group named for each light, by light (emissive shapes first).
        let mut group_names: Vec<Option<&str>> = Vec::new();
        for (item_index, item) in desc.shapes.iter().enumerate() {
            let first = primitives.len() as u32;
            for (k, &corners) in item.vertex_normals.iter().enumerate() {
                shading_normals.insert(first + k as u32, corners);
            }
            for (k, &corners) in item.vertex_colours.iter().enumerate() {
                vertex_colours.insert(first + k as u32, corners);
            }
            if let Some(texture) = &item.texture {
                for k in 0..item.shapes.len() {
                    let uvs = texture.uvs.get(k).copied();
                    textures.bind(first + k as u32, texture.texture, uvs);
                }
            }
            if let Some(rule) = item.coverage {
                for k in 0..item.shapes.len() {
                    textures.bind_coverage(first + k as u32, rule);
                }
            }
            if let Some(map) = &item.metallic_roughness {
                for k in 0..item.shapes.len() {
                    let texture = map.texture.zip(map.uvs.get(k).copied());
                    textures.bind_metallic_roughness(first + k as u32, map.factors, texture);
                }
            }
            if let Some(map) = &item.normal_map {
                for (k, (shape, &uvs)) in item.shapes.iter().zip(&map.uvs).enumerate() {
                    if let Shape::Triangle(triangle) = shape {
                        textures.bind_normal_map(
                            first + k as u32,
                            triangle,
                            map.texture,
                            uvs,
                            map.scale,
                            map.tangents.get(k).copied(),
                        );
                    }
                }
            }
            let material = &materials[item.material as usize];
            // An emissive item's triangles: one mesh light.
            let mut mesh = Vec::new();
            let mut mesh_primitives = Vec::new();
            for &shape in &item.shapes {
                let shape = match material {
                    Material::Glass(_) => shape.two_sided(),
                    _ => shape,
                };
                if let Material::Emissive {
                    radiance,
                    two_sided,
                    ..
                } = *material
                {
                    let light = match shape {
                        Shape::Quad(quad) => {
                            Some(Light::Quad(QuadLight::new(quad, radiance, two_sided)))
                        }
                        Shape::Sphere(sphere) => Some(Light::Sphere(SphereLight {
                            sphere,
                            radiance,
                            two_sided,
                        })),
                        Shape::Triangle(triangle) => {
                            mesh.push(triangle);
                            mesh_primitives.push(primitives.len() as u32);
                            None
                        }
                    };
                    if let Some(light) = light {
                        area_lights.push(EmitterPrimitive {
                            primitive: primitives.len() as u32,
                            light: lights.len() as u32,
                            triangle: 0,
                        });
                        lights.push(light);
                    }
                }
                primitives.push(Primitive {
                    shape,
                    material: item.material,
                });
            }
            if let Material::Emissive {
                radiance,
                two_sided,
                ..
            } = *material
                && let Some(light) = MeshLight::new(mesh, radiance, two_sided)
            {
                // An emission map lies on a mesh (validated), so the
                // mesh's triangles are the item's shapes, in order.
                let light = match &item.emission_map {
                    Some(map) => light.with_texture(EmissionTexture {
                        texture: desc.textures[map.texture as usize].value.clone(),
                        uvs: map.uvs.clone(),
                    }),
                    None => light,
                };
                let index = lights.len() as u32;
                area_lights.extend(mesh_primitives.iter().enumerate().map(|(k, &p)| {
                    EmitterPrimitive {
                        primitive: p,
                        light: index,
                        triangle: k as u32,
                    }
                }));
                lights.push(Light::Mesh(light));
            }
            let group = desc.light_group_of(GroupMember::Shape(item_index));
            group_names.resize(lights.len(), group);
        }
        // By primitive, for `area_light_at`'s binary search (an item's
        // mesh light is numbered after its quads and spheres).
        area_lights.sort_unstable_by_key(|e| e.primitive);
        lights.extend(desc.lights.iter().map(|l| Light::from(l.value.clone())));
        group_names
            .extend((0..desc.lights.len()).map(|i| desc.light_group_of(GroupMember::Light(i))));
        let flat_emitters = lights.iter().filter(|l| l.is_flat_emitter()).count();
        let extended_lights = (0..lights.len())
            .filter(|&i| !lights[i].is_delta())
            .collect();
        let environment = lights
            .iter()
            .position(|l| matches!(l, Light::Environment(_)));
        let mut light_primitives = vec![None; lights.len()];
        for e in &area_lights {
            if !matches!(lights[e.light as usize], Light::Mesh(_)) {
                light_primitives[e.light as usize] = Some(e.primitive);
            }
        }
        Scene {
            light_sampler: LightSampler::new(&lights, desc.light_sampling),
            light_groups: LightGroups::new(group_names),
            light_primitives,
            camera: desc.camera.value,
            geometry: Geometry::new(primitives),
            materials,
            lights,
            fog: desc.fog.as_ref().map(|f| f.value),
            media_emitters: MediaEmitters::new(&volumes),
            volumes,
            background: desc.background,
            environment,
            glass: desc.glass,
            flat_emitters,
            extended_lights,
            area_lights,
            shading_normals,
            vertex_colours,
            textures,
        }
    }
}

/// A volume from its (validated) description.
fn build_volume(m: MediumDesc) -> Result<Volume, DescError> {
    let region = match m.region {
        RegionDesc::Everywhere => VolumeRegion::Everywhere,
        RegionDesc::Box(b) => VolumeRegion::Box(b),
        RegionDesc::Mesh(triangles) => VolumeRegion::Mesh(MeshRegion::new(triangles)),
    };
    let volume = Volume::new(m.sigma_t, m.albedo, m.phase, m.density, region)
        .map_err(|e| DescError::new(&m.origin, "density", e))?;
    match m.emission {
        Some(emission) => volume
            .with_emission(emission)
            .map_err(|e| DescError::new(&m.origin, "emission", e)),
        None => Ok(volume),
    }
}
