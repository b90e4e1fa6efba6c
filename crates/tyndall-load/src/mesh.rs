//! Triangle meshes from Wavefront .obj files (via tobj).

use crate::files::{MAX_MESH_FILE_BYTES, read_capped};
use glam::{EulerRot, Mat3, Mat4, Quat, Vec3};
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

/// Most triangles a mesh may have: a glTF scene over all its mesh
/// instances, a native `triangles` shape.
pub const MAX_TRIANGLES: u64 = 1 << 24;

/// The triangles of a mesh file, placed in the scene.
pub struct MeshTriangles {
    pub triangles: Vec<Triangle>,
    /// The unit vertex normals (`vn`) at each triangle's corners, placed
    /// by the inverse transpose of the placement; empty unless every face
    /// of the file gives them (the mesh is then flat-shaded).
    pub vertex_normals: Vec<[Vec3; 3]>,
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
    let normal_matrix = Mat3::from_mat4(m).inverse().transpose();
    // tobj fills a corner without a normal with the previous corner's,
    // so which faces gave normals is read off the file itself.
    let smooth = every_face_has_normals(bytes)
        && models
            .iter()
            .all(|model| model.mesh.normal_indices.len() == model.mesh.indices.len());
    let mut triangles = Vec::new();
    let mut vertex_normals = Vec::new();
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
        let normal = |i: u32| -> Result<Vec3, String> {
            let i = i as usize;
            let n = mesh
                .normals
                .get(3 * i..3 * i + 3)
                .ok_or_else(|| format!("a face refers to missing normal {}", i + 1))?;
            (normal_matrix * Vec3::new(n[0], n[1], n[2]))
                .try_normalize()
                .ok_or_else(|| format!("normal {} is zero or not finite", i + 1))
        };
        for (f, face) in mesh.indices.chunks_exact(3).enumerate() {
            let (a, b, c) = (vertex(face[0])?, vertex(face[1])?, vertex(face[2])?);
            match Triangle::new(a, b, c) {
                Some(t) => {
                    triangles.push(t);
                    if smooth {
                        let corners = &mesh.normal_indices[3 * f..3 * f + 3];
                        vertex_normals.push([
                            normal(corners[0])?,
                            normal(corners[1])?,
                            normal(corners[2])?,
                        ]);
                    }
                }
                None => skipped_degenerate += 1,
            }
        }
    }
    if triangles.is_empty() {
        return Err("it has no triangles".into());
    }
    Ok(MeshTriangles {
        triangles,
        vertex_normals,
        skipped_degenerate,
    })
}

/// Whether the .obj text has `vn` normals and every corner of every face
/// (`f v//vn` or `f v/vt/vn`) names one; lines continued with `\\` are
/// joined first.
fn every_face_has_normals(bytes: &[u8]) -> bool {
    let text = String::from_utf8_lossy(bytes)
        .replace("\\\r\n", " ")
        .replace("\\\n", " ");
    let mut normals = false;
    for line in text.lines() {
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("vn") => normals = true,
            Some("f") => {
                let named = |corner: &str| corner.split('/').nth(2).is_some_and(|n| !n.is_empty());
                if !tokens.all(named) {
                    return false;
                }
            }
            _ => {}
        }
    }
    normals
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `vn` normals follow the placement by its inverse transpose (a
    /// surface stretched along x leans its normals away from x), per
    /// corner; a file where some face has no normals is flat-shaded.
    #[test]
    fn vertex_normals_are_placed_by_the_inverse_transpose() {
        let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 1 0\nvn 0 0 1\nf 1//1 2//2 3//1\n";
        let stretch = MeshTransform {
            translate: Vec3::new(5.0, 0.0, 0.0),
            scale: Vec3::new(2.0, 1.0, 1.0),
            rotate_deg: Vec3::ZERO,
        };
        let mesh = parse_obj_mesh(obj, &stretch).unwrap();
        assert_eq!(mesh.triangles.len(), 1);
        let [a, b, c] = mesh.vertex_normals[0];
        // (1, 1, 0) scaled by (1/2, 1, 1), then normalised.
        let leaned = Vec3::new(0.5, 1.0, 0.0).normalize();
        assert!(
            (a - leaned).length() < 1e-6 && (c - leaned).length() < 1e-6,
            "{a} {c}"
        );
        assert!((b - Vec3::Z).length() < 1e-6, "{b}");

        let partly = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 2 4 3\n";
        let mesh = parse_obj_mesh(partly, &stretch).unwrap();
        assert_eq!(mesh.triangles.len(), 2);
        assert!(mesh.vertex_normals.is_empty(), "{:?}", mesh.vertex_normals);

        let zero = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n";
        let error = parse_obj_mesh(zero, &stretch).err().unwrap();
        assert!(error.contains("normal 1"), "{error}");
    }
}
