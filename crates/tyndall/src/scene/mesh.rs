//! Triangle meshes from Wavefront .obj files (via tobj).

use crate::shapes::Triangle;
use glam::{EulerRot, Mat4, Quat, Vec3};
use std::path::Path;

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
/// sides are triangulated). Materials in the file are ignored: the scene
/// assigns one. The error message names the file and the problem.
pub fn load_obj_mesh(path: &Path, transform: &MeshTransform) -> Result<MeshTriangles, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _materials) = tobj::load_obj(path, &options).map_err(|e| match e {
        tobj::LoadError::OpenFileFailed => format!("cannot open mesh file `{}`", path.display()),
        other => format!("cannot read mesh file `{}`: {other}", path.display()),
    })?;
    let m = transform.matrix();
    let mut triangles = Vec::new();
    let mut skipped_degenerate = 0;
    for model in &models {
        let mesh = &model.mesh;
        let vertex = |i: u32| -> Result<Vec3, String> {
            let i = i as usize;
            mesh.positions
                .get(3 * i..3 * i + 3)
                .map(|p| m.transform_point3(Vec3::new(p[0], p[1], p[2])))
                .ok_or_else(|| {
                    format!(
                        "mesh file `{}`: face refers to missing vertex {}",
                        path.display(),
                        i + 1
                    )
                })
        };
        for face in mesh.indices.chunks_exact(3) {
            let (a, b, c) = (vertex(face[0])?, vertex(face[1])?, vertex(face[2])?);
            if !(a.is_finite() && b.is_finite() && c.is_finite()) {
                return Err(format!(
                    "mesh file `{}`: vertex coordinates must be finite",
                    path.display()
                ));
            }
            match Triangle::new(a, b, c) {
                Some(t) => triangles.push(t),
                None => skipped_degenerate += 1,
            }
        }
    }
    if triangles.is_empty() {
        return Err(format!("mesh file `{}` has no triangles", path.display()));
    }
    Ok(MeshTriangles {
        triangles,
        skipped_degenerate,
    })
}
