//! Sparse voxel grids: densities stored only where they are, in bricks of
//! 8³ voxels as OpenVDB's leaf nodes, plus constant bricks for OpenVDB's
//! tiles; everything else holds the background value 0.
//!
//! Values sit at integer index points (voxel centres, OpenVDB's
//! convention) and are interpolated trilinearly between them. The grid's
//! own index-to-world transform is kept beside it; [`SparseDensity`] maps
//! a volume's unit cube into index space.
//!
//! Memory is proportional to the active leaves: a brick of voxels is
//! 2 KiB, a constant brick a map entry.

use glam::{IVec3, Mat4, Vec3};
use std::collections::HashMap;

/// log₂ of a brick's side in voxels.
const BRICK_LOG2: i32 = 3;
/// A brick's side in voxels (OpenVDB's leaf node).
pub const BRICK: i32 = 1 << BRICK_LOG2;
const BRICK_VOXELS: usize = (BRICK * BRICK * BRICK) as usize;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Brick {
    /// Slot in [`SparseGrid::voxels`].
    Voxels(u32),
    /// Every voxel of the brick holds this value (an OpenVDB tile).
    Constant(f32),
}

/// A sparse grid of non-negative densities in index space, background 0.
#[derive(Clone, Debug, PartialEq)]
pub struct SparseGrid {
    /// Brick coordinate (voxel index >> 3) → contents.
    bricks: HashMap<IVec3, Brick>,
    voxels: Vec<[f32; BRICK_VOXELS]>,
    /// Largest value of each voxel brick, by slot.
    voxel_brick_max: Vec<f32>,
    index_to_world: Mat4,
    /// Inclusive index bounds of the values set (empty: min > max).
    active_min: IVec3,
    active_max: IVec3,
}

impl SparseGrid {
    /// An empty grid (all background) with its index-to-world transform.
    pub fn new(index_to_world: Mat4) -> Self {
        Self {
            bricks: HashMap::new(),
            voxels: Vec::new(),
            voxel_brick_max: Vec::new(),
            index_to_world,
            active_min: IVec3::MAX,
            active_max: IVec3::MIN,
        }
    }

    fn check(value: f32) -> Result<(), String> {
        if value.is_finite() && value >= 0.0 {
            Ok(())
        } else {
            Err(format!("densities must be finite and ≥ 0, found {value}"))
        }
    }

    fn local(i: IVec3) -> usize {
        let l = i & (BRICK - 1);
        (l.x + BRICK * (l.y + BRICK * l.z)) as usize
    }

    /// Sets the value of voxel `i`.
    pub fn set_voxel(&mut self, i: IVec3, value: f32) -> Result<(), String> {
        Self::check(value)?;
        let key = i >> BRICK_LOG2;
        let slot = match self.bricks.get(&key) {
            Some(Brick::Voxels(slot)) => *slot as usize,
            other => {
                let fill = match other {
                    Some(Brick::Constant(c)) => *c,
                    _ => 0.0,
                };
                self.voxels.push([fill; BRICK_VOXELS]);
                self.voxel_brick_max.push(fill);
                let slot = self.voxels.len() - 1;
                self.bricks.insert(key, Brick::Voxels(slot as u32));
                slot
            }
        };
        self.voxels[slot][Self::local(i)] = value;
        self.voxel_brick_max[slot] = self.voxel_brick_max[slot].max(value);
        self.active_min = self.active_min.min(i);
        self.active_max = self.active_max.max(i);
        Ok(())
    }

    /// Sets every voxel of the cube of side `size` (a multiple of 8) from
    /// `origin` (a multiple of 8) to `value`: an OpenVDB tile.
    pub fn fill_tile(&mut self, origin: IVec3, size: i32, value: f32) -> Result<(), String> {
        Self::check(value)?;
        if size <= 0 || size % BRICK != 0 || origin % BRICK != IVec3::ZERO {
            return Err(format!(
                "a tile must be whole bricks of {BRICK}³ voxels, got size {size} at {origin}"
            ));
        }
        let n = size / BRICK;
        let first = origin >> BRICK_LOG2;
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    self.bricks
                        .insert(first + IVec3::new(x, y, z), Brick::Constant(value));
                }
            }
        }
        self.active_min = self.active_min.min(origin);
        self.active_max = self.active_max.max(origin + size - 1);
        Ok(())
    }

    /// The value of voxel `i` (0 outside the stored bricks).
    #[inline]
    pub fn value(&self, i: IVec3) -> f32 {
        match self.bricks.get(&(i >> BRICK_LOG2)) {
            Some(Brick::Voxels(slot)) => self.voxels[*slot as usize][Self::local(i)],
            Some(Brick::Constant(c)) => *c,
            None => 0.0,
        }
    }

    /// Trilinear interpolation between the voxels around index-space
    /// point `g`.
    #[inline]
    pub fn eval_index(&self, g: Vec3) -> f32 {
        let base = g.floor();
        let f = g - base;
        let i = base.as_ivec3();
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let trilinear = |at: &dyn Fn(IVec3) -> f32| {
            let plane = |dz: i32| {
                let row = |dy: i32| {
                    lerp(
                        at(i + IVec3::new(0, dy, dz)),
                        at(i + IVec3::new(1, dy, dz)),
                        f.x,
                    )
                };
                lerp(row(0), row(1), f.y)
            };
            lerp(plane(0), plane(1), f.z)
        };
        // Most points have all eight neighbours in one brick: one lookup.
        if (i & (BRICK - 1)).cmplt(IVec3::splat(BRICK - 1)).all() {
            return match self.bricks.get(&(i >> BRICK_LOG2)) {
                None => 0.0,
                Some(Brick::Constant(c)) => *c,
                Some(Brick::Voxels(slot)) => {
                    let voxels = &self.voxels[*slot as usize];
                    trilinear(&|j| voxels[Self::local(j)])
                }
            };
        }
        trilinear(&|j| self.value(j))
    }

    /// An upper bound of [`Self::eval_index`] over the index-space box
    /// `[lo, hi]`: the largest value of the bricks holding the voxels
    /// that interpolation there reads (each brick's maximum, from its
    /// leaf or tile).
    pub fn max_in_index(&self, lo: Vec3, hi: Vec3) -> f32 {
        let first = lo.floor().as_ivec3() >> BRICK_LOG2;
        let last = (hi.floor().as_ivec3() + 1) >> BRICK_LOG2;
        let brick_max = |b: &Brick| match b {
            Brick::Voxels(slot) => self.voxel_brick_max[*slot as usize],
            Brick::Constant(c) => *c,
        };
        let span = (last - first + 1).max(IVec3::ZERO).as_i64vec3();
        if span.element_product() > self.bricks.len() as i64 {
            // Fewer stored bricks than brick positions: scan the bricks.
            return self
                .bricks
                .iter()
                .filter(|(k, _)| k.cmpge(first).all() && k.cmple(last).all())
                .map(|(_, b)| brick_max(b))
                .fold(0.0, f32::max);
        }
        let mut max = 0.0f32;
        for z in first.z..=last.z {
            for y in first.y..=last.y {
                for x in first.x..=last.x {
                    if let Some(b) = self.bricks.get(&IVec3::new(x, y, z)) {
                        max = max.max(brick_max(b));
                    }
                }
            }
        }
        max
    }

    /// Inclusive index bounds of the values set; `None` if none was.
    pub fn active_bounds(&self) -> Option<(IVec3, IVec3)> {
        self.active_min
            .cmple(self.active_max)
            .all()
            .then_some((self.active_min, self.active_max))
    }

    /// The grid's index-to-world transform (its own, before placement).
    pub fn index_to_world(&self) -> Mat4 {
        self.index_to_world
    }

    /// Bricks of voxels stored (leaves), and constant bricks (from tiles).
    pub fn brick_counts(&self) -> (usize, usize) {
        (self.voxels.len(), self.bricks.len() - self.voxels.len())
    }
}

/// A sparse grid as a volume's density field: `unit_to_index` maps the
/// volume's unit cube (its field box) into the grid's index space.
#[derive(Clone, Debug, PartialEq)]
pub struct SparseDensity {
    pub grid: SparseGrid,
    pub unit_to_index: Mat4,
}

impl SparseDensity {
    /// Density at `u` in the unit cube.
    #[inline]
    pub fn eval(&self, u: Vec3) -> f32 {
        self.grid.eval_index(self.unit_to_index.transform_point3(u))
    }

    /// An upper bound of the density over the unit-cube box `[lo, hi]`:
    /// the grid's bound over the index-space box around its image.
    pub fn max_in(&self, lo: Vec3, hi: Vec3) -> f32 {
        let (mut a, mut b) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for k in 0..8 {
            let corner = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let g = self.unit_to_index.transform_point3(corner);
            a = a.min(g);
            b = b.max(g);
        }
        self.grid.max_in_index(a, b)
    }

    /// Majorant cells per axis: about one brick of voxels each.
    pub fn majorant_cells(&self) -> glam::UVec3 {
        let m = self.unit_to_index;
        let voxels = Vec3::new(
            m.x_axis.truncate().length(),
            m.y_axis.truncate().length(),
            m.z_axis.truncate().length(),
        );
        (voxels / BRICK as f32)
            .ceil()
            .clamp(Vec3::ONE, Vec3::splat(256.0))
            .as_uvec3()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trilinear_between_voxel_centres_and_background_outside() {
        let mut g = SparseGrid::new(Mat4::IDENTITY);
        g.set_voxel(IVec3::new(-1, 0, 0), 2.0).unwrap();
        g.set_voxel(IVec3::new(0, 0, 0), 4.0).unwrap();
        assert_eq!(g.eval_index(Vec3::new(-1.0, 0.0, 0.0)), 2.0);
        assert_eq!(g.eval_index(Vec3::new(-0.5, 0.0, 0.0)), 3.0);
        assert_eq!(g.eval_index(Vec3::new(0.5, 0.0, 0.0)), 2.0);
        assert_eq!(g.eval_index(Vec3::new(0.0, 0.5, 0.0)), 2.0);
        assert_eq!(g.eval_index(Vec3::new(100.0, 0.0, 0.0)), 0.0);
        // Inside one brick (the single-lookup path) and across bricks agree
        // with the trilinear formula.
        g.set_voxel(IVec3::new(1, 0, 0), 8.0).unwrap();
        assert_eq!(g.eval_index(Vec3::new(0.25, 0.0, 0.0)), 5.0);
        assert_eq!(g.eval_index(Vec3::new(-0.75, 0.0, 0.0)), 2.5);
        assert_eq!(
            g.brick_counts(),
            (2, 0),
            "voxels −1 and 0 lie in two bricks"
        );
    }

    #[test]
    fn tiles_are_constant_bricks_and_bound_the_maximum() {
        let mut g = SparseGrid::new(Mat4::IDENTITY);
        g.fill_tile(IVec3::splat(8), 16, 1.5).unwrap();
        g.set_voxel(IVec3::new(9, 9, 9), 3.0).unwrap();
        assert_eq!(g.value(IVec3::new(20, 20, 20)), 1.5);
        assert_eq!(g.value(IVec3::new(9, 9, 9)), 3.0);
        assert_eq!(
            g.value(IVec3::new(10, 9, 9)),
            1.5,
            "the rest of the brick keeps the tile value"
        );
        assert_eq!(g.brick_counts(), (1, 7));
        assert_eq!(g.max_in_index(Vec3::splat(17.0), Vec3::splat(18.0)), 1.5);
        assert_eq!(g.max_in_index(Vec3::splat(0.0), Vec3::splat(30.0)), 3.0);
        assert_eq!(g.max_in_index(Vec3::splat(40.0), Vec3::splat(50.0)), 0.0);
        assert_eq!(g.active_bounds(), Some((IVec3::splat(8), IVec3::splat(23))));
        assert!(g.set_voxel(IVec3::ZERO, f32::NAN).is_err());
    }
}
