//! The dimensionless density fields a [`super::volume::Volume`] scales
//! by its `sigma_t`: uniform, procedural, a dense voxel grid or a sparse
//! one; each evaluates itself and bounds itself over a box (the
//! majorants of delta and ratio tracking).

use super::grid::VoxelGrid;
use super::noise::SmokeNoise;
use super::sparse::{Interpolant, SparseDensity};
use glam::{UVec3, Vec3};

/// Majorant cells per axis over a procedural density's box.
const NOISE_MAJORANT_CELLS: u32 = 16;

/// Voxels per majorant cell along each axis of a grid (a brick of 8³).
/// On the smoke scene (`tyndall bench --only smoke`) bricks of 2³ and 16³
/// were 20–30% slower; 4³ and 8³ were within the machine's noise.
const GRID_BRICK: u32 = 8;

/// The dimensionless density field scaled by a volume's `sigma_t`.
#[derive(Clone, Debug, PartialEq)]
pub enum Density {
    /// 1 everywhere: a homogeneous medium.
    Uniform,
    /// Procedural smoke in [0, 1].
    Noise(SmokeNoise),
    /// A voxel grid read from a `.tgrid` file.
    Grid(VoxelGrid),
    /// A sparse voxel grid (an OpenVDB float grid), placed in the box.
    Sparse(Box<SparseDensity>),
}

impl Density {
    /// Density at `u` in the unit cube.
    #[inline]
    pub fn eval(&self, u: Vec3) -> f32 {
        match self {
            Density::Uniform => 1.0,
            Density::Noise(noise) => noise.eval(u),
            Density::Grid(grid) => grid.eval(u),
            Density::Sparse(sparse) => sparse.eval(u),
        }
    }

    /// `map` of the field at `u`, where the field is voxels: the voxels'
    /// `map` interpolated ([`super::sparse::SparseGrid::interpolate_mapped`],
    /// as a renderer that interpolates a shader's inputs stochastically
    /// sees it); elsewhere `map` of [`Self::eval`].
    #[inline]
    pub fn eval_mapped<V: Interpolant>(&self, u: Vec3, map: impl Fn(f32) -> V) -> V {
        match self {
            Density::Sparse(sparse) => sparse.eval_mapped(u, map),
            _ => map(self.eval(u)),
        }
    }

    /// An upper bound of the density over the box `[lo, hi]` of the unit
    /// cube.
    pub fn max_in(&self, lo: Vec3, hi: Vec3) -> f32 {
        match self {
            Density::Uniform => 1.0,
            Density::Noise(noise) => noise.max_in(lo, hi),
            Density::Grid(grid) => grid.max_in(lo, hi),
            Density::Sparse(sparse) => sparse.max_in(lo, hi),
        }
    }

    /// Majorant grid resolution suited to the field.
    pub(super) fn majorant_cells(&self) -> UVec3 {
        match self {
            Density::Uniform => UVec3::ONE,
            Density::Noise(_) => UVec3::splat(NOISE_MAJORANT_CELLS),
            Density::Grid(grid) => grid.size().map(|n| n.div_ceil(GRID_BRICK)),
            Density::Sparse(sparse) => sparse.majorant_cells(),
        }
    }
}
