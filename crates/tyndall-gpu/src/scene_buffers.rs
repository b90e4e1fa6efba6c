//! The scene as flat GPU buffers: primitives, materials and lights as
//! arrays of 16-byte-aligned plain structs (WGSL `std430` layout), read by
//! `shaders/scene.wgsl`, whose struct declarations mirror these.
//!
//! Built from the core's runtime [`tyndall::Scene`]; anything the GPU
//! march does not implement is refused here with a message naming it, so
//! no scene renders silently wrong.

use crate::bvh::{FlatBvh, GpuBvhNode};
use crate::device::GpuError;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use tyndall::Scene;
use tyndall::color::Rgb;
use tyndall::lights::{Light, SpotProfile};
use tyndall::materials::Material;
use tyndall::materials::{ALBEDO_COSINES, Ggx};
use tyndall::shapes::Shape;

/// Shape kinds in [`GpuPrimitive::kind`].
const SHAPE_SPHERE: u32 = 0;
const SHAPE_QUAD: u32 = 1;
const SHAPE_TRIANGLE: u32 = 2;

/// Material kinds in [`GpuMaterial::kind`].
const MATERIAL_OPAQUE: u32 = 0;
const MATERIAL_EMISSIVE: u32 = 1;
const MATERIAL_LAMP_FACE: u32 = 2;
const MATERIAL_GLASS: u32 = 3;

/// Light kinds in [`GpuLight::kind`].
const LIGHT_POINT: u32 = 0;
const LIGHT_SPOT: u32 = 1;
const LIGHT_DIRECTIONAL: u32 = 2;
const LIGHT_QUAD: u32 = 3;
const LIGHT_SPHERE: u32 = 4;
const LIGHT_MESH: u32 = 5;

/// One shape. Sphere: `a = (centre, radius)`. Quad: `a` origin, `b`
/// edge u, `c` edge v, `d` unit normal, `e` = n/|n|² for the unnormalised
/// normal n (the hit's (u, v)). Triangle: `a` v0, `b` e1, `c` e2, `d` unit
/// normal.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuPrimitive {
    pub kind: u32,
    pub material: u32,
    pub one_sided: u32,
    pub pad: u32,
    pub a: [f32; 4],
    pub b: [f32; 4],
    pub c: [f32; 4],
    pub d: [f32; 4],
    pub e: [f32; 4],
}

/// One material: `color` is the diffuse reflectance (opaque), radiance
/// (emitters, W·sr⁻¹·m⁻²) or pane colour (glass); `specular` the
/// reflective layer's reflectance; `albedo` its GGX lobe's
/// single-scattering albedo at the tabulated cosines
/// (`tyndall::materials::Ggx::albedo_row`, 1 for a mirror), for its
/// multiple-scattering compensation.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuMaterial {
    pub kind: u32,
    pub two_sided: u32,
    pub roughness: f32,
    pub alpha: f32,
    pub color: [f32; 4],
    pub specular: [f32; 4],
    pub albedo: [[f32; 4]; ALBEDO_COSINES / 4],
}

/// One light (`tyndall::lights::Light`), by kind:
/// - point, spot: `position`; a spot's unit axis in `direction`, its
///   profile and cone in `profile`, `cos_cutoff`, `cos_inner`;
///   `intensity` in W/sr;
/// - directional (a sun): the unit `direction` its light travels in,
///   its irradiance (W/m²) in `intensity`;
/// - area lights (quad, sphere, mesh): radiance (W·sr⁻¹·m⁻²) in
///   `intensity.xyz` and the emitting area (m², one side) in
///   `intensity.w`; `two_sided` 1 if both sides emit. A quad: corner
///   `position`, edges `direction` (u) and `edge_v`, unit `normal`,
///   `rectangle` 1 if its edges are orthogonal (then sampled in solid
///   angle). A sphere: centre and radius in `position`. A mesh: its
///   triangles `first_triangle..first_triangle + triangle_count` of
///   [`SceneBuffers::light_triangles`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuLight {
    pub kind: u32,
    pub profile: u32,
    pub cos_cutoff: f32,
    pub cos_inner: f32,
    pub position: [f32; 4],
    pub direction: [f32; 4],
    pub intensity: [f32; 4],
    pub edge_v: [f32; 4],
    pub normal: [f32; 4],
    pub two_sided: u32,
    pub rectangle: u32,
    pub first_triangle: u32,
    pub triangle_count: u32,
}

/// One triangle of an emissive mesh (`tyndall::lights::MeshLight`):
/// corner `v0` and edges `e1`, `e2` as in `tyndall::shapes::Triangle`,
/// unit `normal`; `v0.w` is the mesh's cumulative selection table at
/// this triangle (`MeshLight::selection_cdf`, rounded to f32) and `e1.w`
/// the triangle's area (m²).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuLightTriangle {
    pub v0: [f32; 4],
    pub e1: [f32; 4],
    pub e2: [f32; 4],
    pub normal: [f32; 4],
}

/// The scene's arrays, ready to upload.
pub struct SceneBuffers {
    /// In the order of the BVH's leaves.
    pub primitives: Vec<GpuPrimitive>,
    pub(crate) bvh_nodes: Vec<GpuBvhNode>,
    /// `order[j]`: the scene's index of `primitives[j]`.
    pub(crate) order: Vec<u32>,
    pub materials: Vec<GpuMaterial>,
    pub lights: Vec<GpuLight>,
    /// The triangles of every emissive mesh, mesh after mesh.
    pub light_triangles: Vec<GpuLightTriangle>,
}

fn v4(v: Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}

impl SceneBuffers {
    /// Flattens `scene`, or says what in it the GPU march cannot render.
    pub fn new(scene: &Scene) -> Result<Self, GpuError> {
        Self::after(scene, None)
    }

    /// As [`SceneBuffers::new`], keeping `previous`'s BVH when `scene`'s
    /// geometry is the same (a live view's change of camera, fog or
    /// lights): the tree is then not built again on the host.
    pub(crate) fn after(scene: &Scene, previous: Option<&Self>) -> Result<Self, GpuError> {
        if let Some(index) = scene.volumes().iter().position(|v| v.is_emissive()) {
            return Err(GpuError::Unsupported(format!(
                "emitting medium #{index} ([[media]] in order, from 0: `emission` or `temperature_grid`; only the CPU `volpath` renders emission)"
            )));
        }
        if !scene.volumes().is_empty() {
            return Err(GpuError::Unsupported(
                "heterogeneous volumes (only the box fog is rendered on the GPU)".into(),
            ));
        }
        if scene.has_vertex_normals() {
            return Err(GpuError::Unsupported(
                "smooth-shaded meshes (vertex normals; the GPU shades with the geometric normal)"
                    .into(),
            ));
        }
        if scene.has_coverage() {
            return Err(GpuError::Unsupported(
                "alpha coverage (glTF alphaMode MASK or BLEND)".into(),
            ));
        }
        if scene.has_textures() {
            return Err(GpuError::Unsupported("textured surfaces".into()));
        }
        if scene.environment().is_some() {
            return Err(GpuError::Unsupported(
                "environment light (only the CPU renders it)".into(),
            ));
        }
        if scene.has_vertex_colours() {
            return Err(GpuError::Unsupported(
                "vertex colours (glTF COLOR_0)".into(),
            ));
        }
        if let Some((index, pattern)) = scene
            .lights()
            .iter()
            .enumerate()
            .find_map(|(i, l)| Some((i, l.emission_pattern()?)))
        {
            return Err(GpuError::Unsupported(format!(
                "light #{index} with {pattern} (only the CPU renders them)"
            )));
        }
        check_panes(scene)?;
        let scene_primitives = scene.geometry().primitives();
        let in_scene_order: Vec<GpuPrimitive> = scene_primitives
            .iter()
            .map(|p| primitive(&p.shape, p.material))
            .collect();
        let in_order = |order: &[u32]| -> Vec<GpuPrimitive> {
            order.iter().map(|&i| in_scene_order[i as usize]).collect()
        };
        let same_geometry = |previous: &Self| {
            previous.order.len() == in_scene_order.len()
                && bytemuck::cast_slice::<_, u8>(&in_order(&previous.order))
                    == bytemuck::cast_slice::<_, u8>(&previous.primitives)
        };
        let (bvh, primitives) = match previous.filter(|p| same_geometry(p)) {
            Some(previous) => (
                FlatBvh {
                    nodes: previous.bvh_nodes.clone(),
                    order: previous.order.clone(),
                },
                previous.primitives.clone(),
            ),
            None => {
                let bvh = FlatBvh::new(scene_primitives);
                let primitives = in_order(&bvh.order);
                (bvh, primitives)
            }
        };
        let materials = scene
            .materials()
            .iter()
            .map(material)
            .collect::<Result<_, _>>()?;
        let mut light_triangles = Vec::new();
        let lights = scene
            .lights()
            .iter()
            .map(|l| light(l, &mut light_triangles))
            .collect();
        Ok(Self {
            primitives,
            bvh_nodes: bvh.nodes,
            order: bvh.order,
            materials,
            lights,
            light_triangles,
        })
    }
}

/// `lights` as the GPU holds them, with the triangles of their emissive
/// meshes (what [`SceneBuffers::new`] uploads of a scene's lights).
pub fn gpu_lights(lights: &[Light]) -> (Vec<GpuLight>, Vec<GpuLightTriangle>) {
    let mut triangles = Vec::new();
    let lights = lights.iter().map(|l| light(l, &mut triangles)).collect();
    (lights, triangles)
}

/// Most panes a ray keeps on the GPU: a blend-model shadow ray, to apply
/// them in order, and a shadow-map texel, as its layers
/// (`MAX_BLEND_PANES` in `march.wgsl`, `MAX_MAP_LAYERS` in `maps.wgsl`).
pub(crate) const MAX_PANES: usize = 16;

/// A ray crosses a quad or triangle at most once and a sphere twice;
/// scenes whose glass a ray could cross more than [`MAX_PANES`] times are
/// refused rather than tinted wrongly.
fn check_panes(scene: &Scene) -> Result<(), GpuError> {
    let crossings: usize = scene
        .geometry()
        .primitives()
        .iter()
        .filter(|p| matches!(scene.materials()[p.material as usize], Material::Glass(_)))
        .map(|p| {
            if matches!(p.shape, Shape::Sphere(_)) {
                2
            } else {
                1
            }
        })
        .sum();
    if crossings > MAX_PANES {
        return Err(GpuError::Unsupported(format!(
            "glass a ray may cross {crossings} times (the GPU keeps at most {MAX_PANES} panes per shadow ray or map texel)"
        )));
    }
    Ok(())
}

fn primitive(shape: &Shape, material: u32) -> GpuPrimitive {
    let base = GpuPrimitive {
        material,
        ..Default::default()
    };
    match *shape {
        Shape::Sphere(s) => GpuPrimitive {
            kind: SHAPE_SPHERE,
            a: v4(s.center, s.radius),
            ..base
        },
        Shape::Quad(q) => {
            let n = q.edge_u.cross(q.edge_v);
            GpuPrimitive {
                kind: SHAPE_QUAD,
                one_sided: q.one_sided as u32,
                a: v4(q.origin, 0.0),
                b: v4(q.edge_u, 0.0),
                c: v4(q.edge_v, 0.0),
                d: v4(q.normal, 0.0),
                e: v4(n / n.length_squared(), 0.0),
                ..base
            }
        }
        Shape::Triangle(t) => GpuPrimitive {
            kind: SHAPE_TRIANGLE,
            one_sided: t.one_sided as u32,
            a: v4(t.v0, 0.0),
            b: v4(t.e1, 0.0),
            c: v4(t.e2, 0.0),
            d: v4(t.normal, 0.0),
            ..base
        },
    }
}

fn material(m: &Material) -> Result<GpuMaterial, GpuError> {
    Ok(match *m {
        Material::Opaque(s) if s.coat.reflectance > 0.0 => {
            return Err(GpuError::Unsupported(
                "clear coats (glTF KHR_materials_clearcoat, a principled coat)".into(),
            ));
        }
        Material::Opaque(s) => GpuMaterial {
            kind: MATERIAL_OPAQUE,
            roughness: s.roughness,
            color: v4(s.diffuse, 0.0),
            specular: v4(s.specular, 0.0),
            albedo: {
                let row = Ggx::new(s.roughness).map_or([1.0; ALBEDO_COSINES], |g| g.albedo_row());
                std::array::from_fn(|q| std::array::from_fn(|c| row[4 * q + c]))
            },
            ..Default::default()
        },
        Material::Emissive { surface, .. } if surface.reflects() => {
            return Err(GpuError::Unsupported(
                "emitters that also reflect (glTF emission over a base colour)".into(),
            ));
        }
        Material::Emissive {
            radiance,
            two_sided,
            ..
        } => GpuMaterial {
            kind: MATERIAL_EMISSIVE,
            two_sided: two_sided as u32,
            color: v4(radiance, 0.0),
            ..Default::default()
        },
        Material::LampFace { radiance } => GpuMaterial {
            kind: MATERIAL_LAMP_FACE,
            color: v4(radiance, 0.0),
            ..Default::default()
        },
        Material::Glass(g) => GpuMaterial {
            kind: MATERIAL_GLASS,
            alpha: g.alpha,
            color: v4(g.color, 0.0),
            ..Default::default()
        },
        Material::Dielectric { .. } => {
            return Err(GpuError::Unsupported(
                "dielectric (refracting) materials".into(),
            ));
        }
    })
}

/// `l` as a [`GpuLight`]; a mesh light's triangles are appended to
/// `triangles`.
fn light(l: &Light, triangles: &mut Vec<GpuLightTriangle>) -> GpuLight {
    let area_light = |radiance: Rgb, two_sided: bool| GpuLight {
        intensity: v4(radiance, l.area()),
        two_sided: two_sided as u32,
        ..Default::default()
    };
    match l {
        Light::Point(p) => GpuLight {
            kind: LIGHT_POINT,
            position: v4(p.position, 0.0),
            intensity: v4(p.intensity, 0.0),
            ..Default::default()
        },
        Light::Spot(s) => {
            let (profile, cos_inner) = match s.profile {
                SpotProfile::Linear => (0, 0.0),
                SpotProfile::Hard => (1, 0.0),
                SpotProfile::Smooth { cos_inner } => (2, cos_inner),
            };
            GpuLight {
                kind: LIGHT_SPOT,
                profile,
                cos_cutoff: s.cos_cutoff,
                cos_inner,
                position: v4(s.position, 0.0),
                direction: v4(s.direction, 0.0),
                intensity: v4(s.intensity, 0.0),
                ..Default::default()
            }
        }
        Light::Directional(d) => GpuLight {
            kind: LIGHT_DIRECTIONAL,
            direction: v4(d.direction, 0.0),
            intensity: v4(d.irradiance, 0.0),
            ..Default::default()
        },
        Light::Quad(q) => GpuLight {
            kind: LIGHT_QUAD,
            position: v4(q.quad.origin, 0.0),
            direction: v4(q.quad.edge_u, 0.0),
            edge_v: v4(q.quad.edge_v, 0.0),
            normal: v4(q.quad.normal, 0.0),
            rectangle: q.is_rectangle() as u32,
            ..area_light(q.radiance, q.two_sided)
        },
        // Refused by `SceneBuffers::after`: dark if it ever came here.
        Light::Environment(_) => GpuLight {
            intensity: v4(Rgb::ZERO, 0.0),
            ..Default::default()
        },
        Light::Sphere(s) => GpuLight {
            kind: LIGHT_SPHERE,
            position: v4(s.sphere.center, s.sphere.radius),
            ..area_light(s.radiance, s.two_sided)
        },
        Light::Mesh(m) => {
            let first_triangle = triangles.len() as u32;
            triangles.extend(
                m.triangles()
                    .iter()
                    .zip(m.selection_cdf())
                    .map(|(t, &cdf)| GpuLightTriangle {
                        v0: v4(t.v0, cdf as f32),
                        e1: v4(t.e1, t.area()),
                        e2: v4(t.e2, 0.0),
                        normal: v4(t.normal, 0.0),
                    }),
            );
            GpuLight {
                kind: LIGHT_MESH,
                first_triangle,
                triangle_count: m.triangles().len() as u32,
                ..area_light(m.radiance, m.two_sided)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tyndall::camera::CameraSpec;
    use tyndall::description::{Origin, SceneDesc, Sourced, SurfaceTexture};
    use tyndall::materials::Surface;
    use tyndall::shapes::Triangle;
    use tyndall::texture::{Texture, Wrap};

    /// A scene of one grey triangle, smooth-shaded or textured.
    fn triangle_scene(smooth: bool, textured: bool) -> Scene {
        let camera = CameraSpec::looking_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0);
        let mut desc = SceneDesc::new(Sourced::code(camera));
        let grey = desc.add_material(
            Material::Opaque(Surface::diffuse(Rgb::splat(0.5))),
            Origin::Code,
        );
        let triangle = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y).unwrap();
        let normals = if smooth {
            vec![[Vec3::Z; 3]]
        } else {
            Vec::new()
        };
        let texture = textured.then(|| {
            let image = Texture::new(1, 1, vec![[200, 100, 50]], [Wrap::Repeat; 2]).unwrap();
            SurfaceTexture {
                texture: desc.add_texture(std::sync::Arc::new(image), Origin::Code),
                uvs: Vec::new(),
            }
        });
        let attributes = tyndall::description::MeshAttributes {
            vertex_normals: normals,
            texture,
            ..Default::default()
        };
        desc.add_mesh(vec![triangle], attributes, grey, Origin::Code);
        Scene::build(&desc).unwrap()
    }

    /// Eight spheres in a row, the fourth at `x4`.
    fn spheres(x4: f32) -> Scene {
        let camera = CameraSpec::looking_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0);
        let mut desc = SceneDesc::new(Sourced::code(camera));
        let grey = desc.add_material(
            Material::Opaque(Surface::diffuse(Rgb::splat(0.5))),
            Origin::Code,
        );
        let shapes = (0..8)
            .map(|i| {
                let x = if i == 4 { x4 } else { i as f32 };
                Shape::Sphere(tyndall::shapes::Sphere {
                    center: Vec3::new(x, 0.0, 0.0),
                    radius: 0.4,
                })
            })
            .collect();
        desc.add_shapes(shapes, grey, Origin::Code);
        Scene::build(&desc).unwrap()
    }

    /// Two emissive meshes (of 1 and 3 triangles) after a point light:
    /// each mesh light's range covers its own triangles, in order, and its
    /// table climbs with the triangles' areas to 1.
    #[test]
    fn mesh_lights_index_their_own_triangles() {
        let camera = CameraSpec::looking_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0);
        let mut desc = SceneDesc::new(Sourced::code(camera));
        desc.add_light(
            tyndall::description::LightDesc::Point(tyndall::lights::PointLight {
                luminaire: None,
                position: Vec3::Y,
                intensity: Rgb::ONE,
            }),
            Origin::Code,
        );
        let glow = desc.add_material(Material::emitter(Rgb::ONE, false), Origin::Code);
        // Triangle k of a mesh has legs k + 1 and 1: area (k + 1)/2.
        let mesh = |z: f32, count: usize| -> Vec<Shape> {
            (0..count)
                .map(|k| {
                    let o = Vec3::new(3.0 * k as f32, 0.0, z);
                    let legs = Vec3::X * (k + 1) as f32;
                    Shape::Triangle(Triangle::new(o, o + legs, o + Vec3::Y).unwrap())
                })
                .collect()
        };
        desc.add_shapes(mesh(0.0, 1), glow, Origin::Code);
        desc.add_shapes(mesh(-1.0, 3), glow, Origin::Code);
        let buffers = SceneBuffers::new(&Scene::build(&desc).unwrap()).unwrap();
        let meshes: Vec<&GpuLight> = buffers
            .lights
            .iter()
            .filter(|l| l.kind == LIGHT_MESH)
            .collect();
        assert_eq!(meshes.len(), 2);
        assert_eq!(buffers.light_triangles.len(), 4);
        let mut covered = Vec::new();
        for light in meshes {
            let range = light.first_triangle as usize
                ..(light.first_triangle + light.triangle_count) as usize;
            let triangles = &buffers.light_triangles[range.clone()];
            covered.extend(range);
            let total: f32 = triangles.iter().map(|t| t.e1[3]).sum();
            assert_eq!(light.intensity[3], total, "the light's area");
            let mut sum = 0.0;
            for t in triangles {
                sum += t.e1[3];
                assert!((t.v0[3] - sum / total).abs() <= 1e-6, "the table");
            }
            assert_eq!(triangles.last().unwrap().v0[3], 1.0);
            let z = triangles[0].v0[2];
            assert!(
                triangles.iter().all(|t| t.v0[2] == z),
                "one mesh's triangles"
            );
            assert_eq!(triangles.len(), if z == 0.0 { 1 } else { 3 });
        }
        covered.sort();
        assert_eq!(covered, vec![0, 1, 2, 3]);
    }

    fn bytes<T: Pod>(items: &[T]) -> &[u8] {
        bytemuck::cast_slice(items)
    }

    /// A live update keeps the previous BVH only for the same geometry:
    /// with a sphere moved, it gets what a fresh flattening gives.
    #[test]
    fn the_previous_bvh_is_kept_only_for_the_same_geometry() {
        let before = SceneBuffers::new(&spheres(4.0)).unwrap();
        let same = SceneBuffers::after(&spheres(4.0), Some(&before)).unwrap();
        assert_eq!(bytes(&same.bvh_nodes), bytes(&before.bvh_nodes));
        assert_eq!(bytes(&same.primitives), bytes(&before.primitives));
        let moved = spheres(-20.0);
        let after = SceneBuffers::after(&moved, Some(&before)).unwrap();
        let fresh = SceneBuffers::new(&moved).unwrap();
        assert_eq!(bytes(&after.bvh_nodes), bytes(&fresh.bvh_nodes));
        assert_eq!(bytes(&after.primitives), bytes(&fresh.primitives));
        assert_ne!(
            bytes(&after.bvh_nodes),
            bytes(&before.bvh_nodes),
            "the moved sphere's box"
        );
    }

    /// What the GPU march would shade differently from the CPU is refused,
    /// naming it, rather than rendered flat or untextured.
    #[test]
    fn smooth_and_textured_meshes_are_refused() {
        assert!(SceneBuffers::new(&triangle_scene(false, false)).is_ok());
        for (smooth, textured, named) in
            [(true, false, "vertex normals"), (false, true, "textured")]
        {
            match SceneBuffers::new(&triangle_scene(smooth, textured)) {
                Err(GpuError::Unsupported(what)) => assert!(what.contains(named), "{what}"),
                Err(e) => panic!("{e}"),
                Ok(_) => panic!("{named}: accepted"),
            }
        }
    }

    /// A measured profile or a gobo is refused, naming the light.
    #[test]
    fn patterned_lights_are_refused() {
        use tyndall::lights::{Gobo, Luminaire, PhotometricProfile, SpotLight, SpotProfile};
        let profile =
            PhotometricProfile::new(vec![0.0, 90.0], vec![0.0], &[vec![1.0, 0.5]]).unwrap();
        let image = Texture::new(1, 1, vec![[200, 100, 50]], [Wrap::Clamp; 2]).unwrap();
        let spot = |luminaire, gobo| SpotLight {
            position: Vec3::Y,
            direction: -Vec3::Y,
            cos_cutoff: 0.9,
            profile: SpotProfile::Hard,
            intensity: Rgb::ONE,
            luminaire,
            gobo,
        };
        let measured = Luminaire::new(std::sync::Arc::new(profile), -Vec3::Y, 0.0);
        let gobo = Gobo::new(std::sync::Arc::new(image), -Vec3::Y, 25.0, 0.0).unwrap();
        for (light, named) in [
            (spot(Some(measured), None), "`ies`"),
            (spot(None, Some(gobo)), "gobo"),
        ] {
            let camera = CameraSpec::looking_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0);
            let mut desc = SceneDesc::new(Sourced::code(camera));
            desc.add_light(tyndall::description::LightDesc::Spot(light), Origin::Code);
            match SceneBuffers::new(&Scene::build(&desc).unwrap()) {
                Err(GpuError::Unsupported(what)) => {
                    assert!(what.contains(named) && what.contains("light #0"), "{what}")
                }
                Err(e) => panic!("{e}"),
                Ok(_) => panic!("{named}: accepted"),
            }
        }
    }

    /// An environment light is refused, naming it.
    #[test]
    fn environment_lights_are_refused() {
        let camera = CameraSpec::looking_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 40.0);
        let mut desc = SceneDesc::new(Sourced::code(camera));
        desc.add_light(
            tyndall::description::LightDesc::Environment(
                tyndall::lights::EnvironmentLight::uniform(Rgb::ONE),
            ),
            Origin::Code,
        );
        match SceneBuffers::new(&Scene::build(&desc).unwrap()) {
            Err(GpuError::Unsupported(what)) => assert!(what.contains("environment"), "{what}"),
            Err(e) => panic!("{e}"),
            Ok(_) => panic!("an environment light was accepted"),
        }
    }
}
