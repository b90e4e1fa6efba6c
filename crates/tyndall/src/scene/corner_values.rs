//! Values given at each corner of a mesh's triangles and interpolated
//! across them by barycentric weights: shading normals of smooth meshes
//! (Phong 1975, "Illumination for computer generated pictures"), so that
//! a tessellated curved surface shades smoothly, and vertex colours
//! (glTF `COLOR_0`), which multiply the surface's diffuse reflectance.

use crate::shapes::Triangle;
use glam::Vec3;

/// Corner values (three-vectors: normals, linear colours) of the
/// primitives that have them, by primitive.
#[derive(Debug, Default)]
pub(crate) struct CornerValues {
    /// Per primitive, its index in `corners` or [`NONE`]; empty while no
    /// primitive has values (scenes without them store nothing).
    slot: Vec<u32>,
    corners: Vec<[Vec3; 3]>,
}

const NONE: u32 = u32::MAX;

impl CornerValues {
    /// Records the corner values of primitive `primitive` (numbered in
    /// increasing order as the scene is built).
    pub fn insert(&mut self, primitive: u32, corners: [Vec3; 3]) {
        let index = primitive as usize;
        if self.slot.len() <= index {
            self.slot.resize(index + 1, NONE);
        }
        self.slot[index] = self.corners.len() as u32;
        self.corners.push(corners);
    }

    /// Whether any primitive has values.
    pub fn is_used(&self) -> bool {
        !self.corners.is_empty()
    }

    /// The value of triangle `triangle` (primitive `primitive`) at its
    /// point `p`, interpolated from its corners' by
    /// [`Triangle::corner_weights`], if it has them.
    #[inline]
    pub fn at(&self, primitive: u32, triangle: &Triangle, p: Vec3) -> Option<Vec3> {
        let slot = *self.slot.get(primitive as usize)?;
        if slot == NONE {
            return None;
        }
        let [n0, n1, n2] = self.corners[slot as usize];
        let [b0, b1, b2] = triangle.corner_weights(p);
        Some(n0 * b0 + n1 * b1 + n2 * b2)
    }

    /// The unit shading normal at `p` ([`CornerValues::at`] of corner
    /// normals, normalised); a zero sum of normals falls back to flat
    /// shading (`None`).
    #[inline]
    pub fn normal_at(&self, primitive: u32, triangle: &Triangle, p: Vec3) -> Option<Vec3> {
        self.at(primitive, triangle, p)?.try_normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At the corners the shading normal is the corner's; at the centroid
    /// it is the normalised mean; primitives without normals get none.
    #[test]
    fn interpolates_corner_normals() {
        let (a, b, c) = (
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 3.0),
        );
        let triangle = Triangle::new(a, b, c).unwrap();
        let corners = [
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.6, 0.8, 0.0),
            Vec3::new(0.0, 0.8, -0.6),
        ];
        let mut normals = CornerValues::default();
        normals.insert(2, corners);
        for (p, n) in [(a, corners[0]), (b, corners[1]), (c, corners[2])] {
            let got = normals.normal_at(2, &triangle, p).unwrap();
            assert!((got - n).length() < 1e-6, "{p}: {got} vs {n}");
        }
        let centroid = (a + b + c) / 3.0;
        let mean = (corners[0] + corners[1] + corners[2]).normalize();
        assert!((normals.normal_at(2, &triangle, centroid).unwrap() - mean).length() < 1e-6);
        assert_eq!(normals.normal_at(1, &triangle, centroid), None);
        assert_eq!(normals.normal_at(3, &triangle, centroid), None);
        // Values that are not normals are interpolated as they are.
        let half = normals.at(2, &triangle, (a + b) / 2.0).unwrap();
        assert!((half - (corners[0] + corners[1]) / 2.0).length() < 1e-6);
    }
}
