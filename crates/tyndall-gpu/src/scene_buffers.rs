//! The scene as flat GPU buffers: primitives, materials and lights as
//! arrays of 16-byte-aligned plain structs (WGSL `std430` layout), read by
//! `shaders/march.wgsl`, whose struct declarations mirror these.
//!
//! Built from the core's runtime [`tyndall::Scene`]; anything the GPU
//! march does not implement is refused here with a message naming it, so
//! no scene renders silently wrong.

use crate::bvh::{FlatBvh, GpuBvhNode};
use crate::device::GpuError;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use tyndall::Scene;
use tyndall::lights::{Light, SpotProfile};
use tyndall::materials::Material;
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
/// reflective layer's reflectance.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuMaterial {
    pub kind: u32,
    pub two_sided: u32,
    pub roughness: f32,
    pub alpha: f32,
    pub color: [f32; 4],
    pub specular: [f32; 4],
}

/// One delta light: `position` (point, spot), unit `direction` (spot
/// axis, or the direction a sun's light travels), `intensity` (W/sr, or
/// a sun's irradiance W/m²).
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
        if scene.has_textures() {
            return Err(GpuError::Unsupported("textured surfaces".into()));
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
        let lights = scene.lights().iter().map(light).collect::<Result<_, _>>()?;
        Ok(Self {
            primitives,
            bvh_nodes: bvh.nodes,
            order: bvh.order,
            materials,
            lights,
        })
    }
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
        Material::Opaque(s) => GpuMaterial {
            kind: MATERIAL_OPAQUE,
            roughness: s.roughness,
            color: v4(s.diffuse, 0.0),
            specular: v4(s.specular, 0.0),
            ..Default::default()
        },
        Material::Emissive {
            radiance,
            two_sided,
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

fn light(l: &Light) -> Result<GpuLight, GpuError> {
    Ok(match l {
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
            }
        }
        Light::Directional(d) => GpuLight {
            kind: LIGHT_DIRECTIONAL,
            direction: v4(d.direction, 0.0),
            intensity: v4(d.irradiance, 0.0),
            ..Default::default()
        },
        Light::Quad(_) | Light::Sphere(_) | Light::Mesh(_) => {
            return Err(GpuError::Unsupported(
                "area lights (emissive quads, spheres, meshes): the CPU march samples them exactly with shadow rays, which the GPU march does not implement".into(),
            ));
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use tyndall::camera::CameraSpec;
    use tyndall::color::Rgb;
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
        desc.add_mesh(vec![triangle], normals, texture, grey, Origin::Code);
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
}
