//! Voxel density grids (their `.tgrid` file format is read and written by
//! `tyndall-load`).
//!
//! Densities are dimensionless, finite and non-negative; the medium's
//! `sigma_t` scales them to extinction. Values sit at voxel centres
//! (voxel `(i, j, k)` covers `[i, i+1]/nx × …` of the medium's box) and
//! are interpolated trilinearly between centres, clamped at the faces.

use glam::{IVec3, UVec3, Vec3};
use std::hash::Hasher;

/// Most voxels a grid may hold (1 GiB of f32), so a corrupt header cannot
/// ask for absurd memory.
pub const MAX_VOXELS: u64 = 1 << 28;

/// A dense grid of densities over the unit cube.
#[derive(Clone, PartialEq)]
pub struct VoxelGrid {
    size: UVec3,
    values: Vec<f32>,
}

/// A summary, not the values (up to [`MAX_VOXELS`] of them; render parts
/// hash a scene through its `Debug` form, `parts::scene_hash`): the size
/// and a 64-bit digest (Fx hashing) of the values' bits in order.
impl std::fmt::Debug for VoxelGrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut h = rustc_hash::FxHasher::default();
        self.values.iter().for_each(|v| h.write_u32(v.to_bits()));
        f.debug_struct("VoxelGrid")
            .field("size", &self.size)
            .field("digest", &format_args!("{:016x}", h.finish()))
            .finish()
    }
}

impl VoxelGrid {
    /// A grid of `size` voxels from values in x-fastest order; `None`
    /// unless the count matches and every value is finite and ≥ 0.
    pub fn new(size: UVec3, values: Vec<f32>) -> Option<Self> {
        let ok = size.min_element() > 0
            && voxel_count(size) == Some(values.len() as u64)
            && values.iter().all(|v| v.is_finite() && *v >= 0.0);
        ok.then_some(Self { size, values })
    }

    pub fn size(&self) -> UVec3 {
        self.size
    }

    /// The densities, x fastest, then y, then z.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    #[inline]
    fn at(&self, i: IVec3) -> f32 {
        let i = i.clamp(IVec3::ZERO, self.size.as_ivec3() - 1).as_uvec3();
        self.values[(i.x + self.size.x * (i.y + self.size.y * i.z)) as usize]
    }

    /// Trilinearly interpolated density at `u` in the unit cube.
    #[inline]
    pub fn eval(&self, u: Vec3) -> f32 {
        let g = u * self.size.as_vec3() - 0.5;
        let base = g.floor();
        let f = g - base;
        let i = base.as_ivec3();
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let plane = |dz: i32| {
            let row = |dy: i32| {
                lerp(
                    self.at(i + IVec3::new(0, dy, dz)),
                    self.at(i + IVec3::new(1, dy, dz)),
                    f.x,
                )
            };
            lerp(row(0), row(1), f.y)
        };
        lerp(plane(0), plane(1), f.z)
    }

    /// The largest density [`VoxelGrid::eval`] takes in the box
    /// `[lo, hi]` of the unit cube: trilinear interpolation is a convex
    /// combination of the voxels around a point, so the maximum over the
    /// voxels whose centres' cells touch the box bounds it exactly.
    pub fn max_in(&self, lo: Vec3, hi: Vec3) -> f32 {
        let n = self.size.as_vec3();
        let first = (lo * n - 0.5).floor().as_ivec3().max(IVec3::ZERO);
        let last = ((hi * n - 0.5).floor().as_ivec3() + 1).min(self.size.as_ivec3() - 1);
        let mut max = 0.0f32;
        for z in first.z..=last.z {
            for y in first.y..=last.y {
                for x in first.x..=last.x {
                    max = max.max(self.at(IVec3::new(x, y, z)));
                }
            }
        }
        max
    }
}

/// `nx·ny·nz` in checked arithmetic (`None` on overflow).
pub fn voxel_count(size: UVec3) -> Option<u64> {
    (size.x as u64)
        .checked_mul(size.y as u64)?
        .checked_mul(size.z as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> VoxelGrid {
        let size = UVec3::new(4, 3, 2);
        let values = (0..24).map(|i| i as f32).collect();
        VoxelGrid::new(size, values).unwrap()
    }

    #[test]
    fn interpolates_between_voxel_centres() {
        let grid = ramp();
        // Voxel (1, 1, 0) = 1 + 4·1 = 5 at its centre.
        let centre = (Vec3::new(1.0, 1.0, 0.0) + 0.5) / grid.size().as_vec3();
        assert!((grid.eval(centre) - 5.0).abs() < 1e-5);
        // Half-way between voxels (1,1,0) and (2,1,0): 5.5.
        let mid = centre + Vec3::new(0.5 / 4.0, 0.0, 0.0);
        assert!((grid.eval(mid) - 5.5).abs() < 1e-5);
    }

    /// The `Debug` form (what render parts hash) is short, and tells a
    /// grid from one with a voxel changed but not from an equal one.
    #[test]
    fn debug_form_digests_the_values() {
        let (a, b) = (ramp(), ramp());
        let mut values = a.values().to_vec();
        values[13] += 0.5;
        let c = VoxelGrid::new(a.size(), values).unwrap();
        assert_eq!(format!("{a:?}"), format!("{b:?}"));
        assert_ne!(format!("{a:?}"), format!("{c:?}"));
        assert!(format!("{a:?}").len() < 80, "{a:?}");
    }

    #[test]
    fn max_in_bounds_every_interpolated_value() {
        let grid = ramp();
        let (lo, hi) = (Vec3::new(0.1, 0.2, 0.0), Vec3::new(0.4, 0.5, 0.6));
        let bound = grid.max_in(lo, hi);
        let mut largest = 0.0f32;
        for i in 0..1000 {
            let f = Vec3::new(
                (i % 10) as f32 / 9.0,
                (i / 10 % 10) as f32 / 9.0,
                (i / 100) as f32 / 9.0,
            );
            largest = largest.max(grid.eval(lo + (hi - lo) * f));
        }
        assert!(largest <= bound + 1e-5, "{largest} > {bound}");
    }
}
