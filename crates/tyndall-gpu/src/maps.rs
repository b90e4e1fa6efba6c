//! The projections of the GPU's shadow maps, chosen per light exactly as
//! `tyndall::shadow_maps` chooses them on the CPU (the kernels that render
//! and read them are in `shaders/maps.wgsl`): a spot of cutoff ≤ 60° gets
//! one perspective face over its cone, point lights and wider spots a
//! cube (six 90° faces), a sun an orthographic face over the scene's
//! bounding sphere.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use tyndall::Scene;
use tyndall::lights::LightOrigin;
use tyndall::shadow_map_layout::{CUBE_FACES, is_narrow};

/// One face: a frame at the light and its projection (`Face` in
/// `maps.wgsl`). `forward_kind.w` is 0 for perspective, 1 for
/// orthographic; `scale` is tan(half angle) or the half extent.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct GpuFace {
    origin: [f32; 4],
    right: [f32; 4],
    up: [f32; 4],
    forward_kind: [f32; 4],
    scale: f32,
    texel_base: u32,
    pad: [u32; 2],
}

/// Which faces belong to a light (`LightMap` in `maps.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub(crate) struct GpuLightMap {
    face_base: u32,
    face_count: u32,
    pad: [u32; 2],
}

impl GpuLightMap {
    /// The indices of this light's faces in the face array.
    pub(crate) fn face_range(&self) -> std::ops::Range<usize> {
        self.face_base as usize..(self.face_base + self.face_count) as usize
    }
}

fn v4(v: Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}

fn perspective(origin: Vec3, right: Vec3, up: Vec3, forward: Vec3, tan_half: f32) -> GpuFace {
    GpuFace {
        origin: v4(origin, 0.0),
        right: v4(right, 0.0),
        up: v4(up, 0.0),
        forward_kind: v4(forward, 0.0),
        scale: tan_half,
        ..Default::default()
    }
}

/// The faces of every light's map, in the scene's light order, each with
/// its first texel in one array of `resolution²` texels per face.
pub(crate) fn faces(scene: &Scene, resolution: u32) -> (Vec<GpuLightMap>, Vec<GpuFace>) {
    let mut maps = Vec::new();
    let mut faces: Vec<GpuFace> = Vec::new();
    for light in scene.lights() {
        let face_base = faces.len() as u32;
        match light.origin() {
            LightOrigin::Cone {
                apex,
                axis,
                cos_cutoff,
            } if is_narrow(cos_cutoff) => {
                let (right, up) = axis.any_orthonormal_pair();
                let tan_half = cos_cutoff.acos().tan();
                faces.push(perspective(apex, right, up, axis, tan_half));
            }
            LightOrigin::Cone { apex: position, .. } | LightOrigin::Point { position } => {
                for (forward, right, up) in CUBE_FACES {
                    faces.push(perspective(position, right, up, forward, 1.0));
                }
            }
            LightOrigin::Parallel { direction } => {
                let b = scene.geometry().bounds();
                let (center, radius) = if b.is_empty() {
                    (Vec3::ZERO, 1.0)
                } else {
                    (b.center(), (0.5 * b.extent().length()).max(1e-3))
                };
                let (right, up) = direction.any_orthonormal_pair();
                let half_extent = radius * 1.01 + 1e-3;
                faces.push(GpuFace {
                    origin: v4(center - direction * half_extent, 0.0),
                    right: v4(right, 0.0),
                    up: v4(up, 0.0),
                    forward_kind: v4(direction, 1.0),
                    scale: half_extent,
                    ..Default::default()
                });
            }
            // Area lights have no map: they keep shadow rays, as on the
            // CPU (`tyndall::shadow_maps`).
            LightOrigin::Surface | LightOrigin::Surrounding => {}
        }
        maps.push(GpuLightMap {
            face_base,
            face_count: faces.len() as u32 - face_base,
            pad: [0; 2],
        });
    }
    let texels = resolution * resolution;
    for (i, face) in faces.iter_mut().enumerate() {
        face.texel_base = i as u32 * texels;
    }
    (maps, faces)
}
