//! Tangent frames for normal maps (glTF 2.0 §3.7.2.1): a primitive's
//! `TANGENT` attribute where it has one, else the MikkTSpace tangents
//! (Mikkelsen 2008, "Simulation of Wrinkled Surfaces Revisited") that the
//! specification asks for and Blender computes for Cycles — by
//! `bevy_mikktspace`, a port of the reference implementation
//! (github.com/mmikk/MikkTSpace) that gives its results bit for bit.

use glam::{Vec2, Vec3, Vec4};

/// A triangle mesh as MikkTSpace reads it: each triangle's corners, in
/// the order the mesh keeps them (counter-clockwise about the normal).
pub(super) struct TangentInput<'a> {
    pub positions: &'a [[Vec3; 3]],
    /// The corners' shading normals; empty for a flat-shaded mesh, whose
    /// corners take their triangle's normal.
    pub normals: &'a [[Vec3; 3]],
    /// The normal map's texture coordinates (glTF's, v down the image).
    pub uvs: &'a [[Vec2; 3]],
}

/// MikkTSpace's tangent and handedness at every corner of `mesh`, with
/// the bitangent `w·(N × T)` pointing up the normal map's image (glTF's
/// +y, as Blender reads it). MikkTSpace's bitangent follows increasing v,
/// so it is given `(u, 1 − v)`, the coordinates Blender's importer
/// writes. A corner where no frame exists (its triangle's coordinates
/// span no area, and no neighbour lends one) gets a tangent
/// perpendicular to its normal: the map is constant along such a
/// triangle, and any frame reads it alike.
pub(super) fn mikktspace(mesh: &TangentInput) -> Vec<[Vec4; 3]> {
    let mut geometry = Geometry {
        mesh,
        tangents: vec![[Vec4::ZERO; 3]; mesh.positions.len()],
    };
    // An error only for meshes without faces, which have no corners to
    // fill.
    let _ = bevy_mikktspace::generate_tangents(&mut geometry);
    let mut tangents = geometry.tangents;
    for (t, corners) in tangents.iter_mut().enumerate() {
        for (k, corner) in corners.iter_mut().enumerate() {
            if !(corner.truncate().length_squared() > 0.0 && corner.is_finite()) {
                let normal = Geometry::normal_of(mesh, t, k);
                *corner = normal.any_orthonormal_vector().extend(1.0);
            }
        }
    }
    tangents
}

struct Geometry<'a> {
    mesh: &'a TangentInput<'a>,
    tangents: Vec<[Vec4; 3]>,
}

impl Geometry<'_> {
    fn normal_of(mesh: &TangentInput, face: usize, vert: usize) -> Vec3 {
        match mesh.normals.get(face) {
            Some(normals) => normals[vert],
            None => {
                let [a, b, c] = mesh.positions[face];
                (b - a).cross(c - a).normalize_or(Vec3::Z)
            }
        }
    }
}

impl bevy_mikktspace::Geometry for Geometry<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.positions.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[face][vert].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        Self::normal_of(self.mesh, face, vert).to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self.mesh.uvs[face][vert];
        [uv.x, 1.0 - uv.y]
    }

    fn set_tangent(
        &mut self,
        tangent_space: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        if let Some(space) = tangent_space {
            self.tangents[face][vert] = Vec4::from_array(space.tangent_encoded());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square of two triangles in the xz-plane facing +y, its texture
    /// laid with u along +x and v along +z (glTF's v runs down the image,
    /// so the image's up is −z): every corner's tangent is +x and the
    /// bitangent w·(N × T) = w·(y × x) = −w·z points up the image, −z, so
    /// w = +1. The same square with u along −x mirrors the map: T = −x
    /// and the bitangent still −z, w = −1.
    #[test]
    fn tangents_follow_u_and_bitangents_point_up_the_image() {
        let (p00, p10, p01, p11) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
        );
        // Counter-clockwise about +y seen from above: (p00, p01, p10).
        let positions = [[p00, p01, p10], [p10, p01, p11]];
        let normals = [[Vec3::Y; 3]; 2];
        for (mirror, expected_t, expected_w) in [(false, Vec3::X, 1.0), (true, -Vec3::X, -1.0)] {
            let uv = |p: Vec3| Vec2::new(if mirror { 1.0 - p.x } else { p.x }, p.z);
            let uvs = positions.map(|corners| corners.map(uv));
            for normals in [&normals[..], &[]] {
                let tangents = mikktspace(&TangentInput {
                    positions: &positions,
                    normals,
                    uvs: &uvs,
                });
                for corner in tangents.iter().flatten() {
                    assert!(
                        (corner.truncate() - expected_t).length() < 1e-5,
                        "mirror {mirror}: {corner}"
                    );
                    assert_eq!(corner.w, expected_w, "mirror {mirror}");
                    let bitangent = Vec3::Y.cross(corner.truncate()) * corner.w;
                    assert!((bitangent + Vec3::Z).length() < 1e-5);
                }
            }
        }
    }

    /// A triangle whose coordinates span no area still gets a unit
    /// tangent perpendicular to its normal.
    #[test]
    fn a_triangle_without_a_frame_gets_one_perpendicular_to_its_normal() {
        let positions = [[Vec3::ZERO, Vec3::Z, Vec3::X]];
        let tangents = mikktspace(&TangentInput {
            positions: &positions,
            normals: &[],
            uvs: &[[Vec2::splat(0.5); 3]],
        });
        for corner in tangents[0] {
            assert!(corner.is_finite() && corner.truncate().dot(Vec3::Y).abs() < 1e-5);
            assert!((corner.truncate().length() - 1.0).abs() < 1e-5);
            assert_eq!(corner.w.abs(), 1.0);
        }
    }
}
