//! Triangle meshes from Wavefront .obj files (via tobj).

use crate::files::{MAX_MESH_FILE_BYTES, read_capped};
use glam::{EulerRot, Mat4, Quat, Vec3};
use std::path::Path;
use tyndall::limits::check_coordinates;
use tyndall::shapes::Triangle;

/// Placement of a mesh: scale, then rotate (X, then Y, then Z, degrees),
/// then translate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshTransform {
    pub translate: Vec3,
    pub scale: Vec3,
    pub rotate_deg: Vec3,
}

impl MeshTransform {
    pub fn matrix(&self) -> Mat4 {
        let r = self.rotate_deg * (std::f32::consts::PI / 180.0);
        let rotation = Quat::from_euler(EulerRot::ZYX, r.z, r.y, r.x);
        Mat4::from_scale_rotation_translation(self.scale, rotation, self.translate)
    }
}

/// The triangles of a mesh file, placed in the scene.
pub struct MeshTriangles {
    pub triangles: Vec<Triangle>,
    /// Zero-area triangles dropped (they can never be hit).
    pub skipped_degenerate: usize,
}

/// Loads every object of an .obj file as triangles (faces with more
/// sides are triangulated). Materials in the file are ignored, and
/// `mtllib` lines are not followed: the scene assigns one. Files longer
/// than [`MAX_MESH_FILE_BYTES`] are refused before they are read whole.
/// The error message names the file and the problem.
pub fn load_obj_mesh(path: &Path, transform: &MeshTransform) -> Result<MeshTriangles, String> {
    let bytes = read_capped(path, MAX_MESH_FILE_BYTES)
        .map_err(|e| format!("cannot read mesh file `{}`: {e}", path.display()))?;
    parse_obj_mesh(&bytes, transform).map_err(|e| format!("mesh file `{}`: {e}", path.display()))
}

/// The triangles of an .obj file's bytes, placed by `transform` (see
/// [`load_obj_mesh`]); the error does not name the file.
pub fn parse_obj_mesh(bytes: &[u8], transform: &MeshTransform) -> Result<MeshTriangles, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // No material file is ever opened: an `mtllib` line could name any
    // file (even `/dev/zero`), and the scene assigns the material.
    let no_materials = |_: &Path| -> tobj::MTLLoadResult { Ok(Default::default()) };
    let (models, _materials) = tobj::load_obj_buf(&mut &bytes[..], &options, no_materials)
        .map_err(|e| format!("cannot parse it: {e}"))?;
    let m = transform.matrix();
    let mut triangles = Vec::new();
    let mut skipped_degenerate = 0;
    for model in &models {
        let mesh = &model.mesh;
        let vertex = |i: u32| -> Result<Vec3, String> {
            let i = i as usize;
            let p = mesh
                .positions
                .get(3 * i..3 * i + 3)
                .ok_or_else(|| format!("a face refers to missing vertex {}", i + 1))?;
            let placed = m.transform_point3(Vec3::new(p[0], p[1], p[2]));
            check_coordinates(&format!("vertex {} (placed)", i + 1), placed)?;
            Ok(placed)
        };
        for face in mesh.indices.chunks_exact(3) {
            let (a, b, c) = (vertex(face[0])?, vertex(face[1])?, vertex(face[2])?);
            match Triangle::new(a, b, c) {
                Some(t) => triangles.push(t),
                None => skipped_degenerate += 1,
            }
        }
    }
    if triangles.is_empty() {
        return Err("it has no triangles".into());
    }
    Ok(MeshTriangles {
        triangles,
        skipped_degenerate,
    })
}
