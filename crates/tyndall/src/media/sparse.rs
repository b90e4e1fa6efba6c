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
//! 2 KiB of `f32` or, for grids saved as half floats (as Blender's and
//! Houdini's caches are), 1 KiB of IEEE 754 binary16 values, kept as the
//! file held them and widened on each read; a constant brick is a map
//! entry.

use glam::{IVec3, Mat4, Vec3};
use half::f16;
use rustc_hash::{FxHashMap, FxHasher};
use std::hash::Hasher;

/// log₂ of a brick's side in voxels.
const BRICK_LOG2: i32 = 3;
/// A brick's side in voxels (OpenVDB's leaf node).
pub const BRICK: i32 = 1 << BRICK_LOG2;
/// Voxels in a brick, in the order of [`SparseGrid::insert_leaf`]'s
/// values: x slowest, z fastest (OpenVDB's leaf slot order).
pub const BRICK_VOXELS: usize = (BRICK * BRICK * BRICK) as usize;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Brick {
    /// Slot in [`SparseGrid::voxels`].
    Voxels(u32),
    /// Every voxel of the brick holds this value (an OpenVDB tile).
    Constant(f32),
}

/// The precision a grid stores its voxel bricks in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// `f32`: 4 bytes a voxel.
    Full,
    /// IEEE 754 binary16: 2 bytes a voxel, values rounded to the nearest
    /// half (exact for values read from a half-float file).
    Half,
}

/// The voxel bricks, in one precision, by slot.
#[derive(Clone, Debug, PartialEq)]
enum BrickValues {
    Full(Vec<[f32; BRICK_VOXELS]>),
    /// Bit patterns of binary16 values.
    Half(Vec<[u16; BRICK_VOXELS]>),
}

impl BrickValues {
    fn len(&self) -> usize {
        match self {
            Self::Full(v) => v.len(),
            Self::Half(v) => v.len(),
        }
    }

    /// `value` as this storage holds it.
    fn stored(&self, value: f32) -> f32 {
        match self {
            Self::Full(_) => value,
            Self::Half(_) => f16::from_f32(value).to_f32(),
        }
    }

    fn push(&mut self, fill: f32) {
        match self {
            Self::Full(v) => v.push([fill; BRICK_VOXELS]),
            Self::Half(v) => v.push([f16::from_f32(fill).to_bits(); BRICK_VOXELS]),
        }
    }

    /// Stores `value`, already [`Self::stored`], at voxel `n` of brick `slot`.
    #[inline]
    fn set(&mut self, slot: usize, n: usize, value: f32) {
        match self {
            Self::Full(v) => v[slot][n] = value,
            Self::Half(v) => v[slot][n] = f16::from_f32(value).to_bits(),
        }
    }

    #[inline]
    fn get(&self, slot: usize, n: usize) -> f32 {
        match self {
            Self::Full(v) => v[slot][n],
            Self::Half(v) => f16::from_bits(v[slot][n]).to_f32(),
        }
    }

    fn bytes(&self) -> usize {
        match self {
            Self::Full(v) => std::mem::size_of_val(v.as_slice()),
            Self::Half(v) => std::mem::size_of_val(v.as_slice()),
        }
    }

    fn shrink_to_fit(&mut self) {
        match self {
            Self::Full(v) => v.shrink_to_fit(),
            Self::Half(v) => v.shrink_to_fit(),
        }
    }
}

/// A sparse grid of non-negative densities in index space, background 0.
#[derive(Clone, PartialEq)]
pub struct SparseGrid {
    /// Brick coordinate (voxel index >> 3) → contents. Every density
    /// lookup reads it: Fx hashing (rustc-hash) costs a few instructions
    /// where the standard SipHash, which resists hash flooding that brick
    /// coordinates do not need, cost 5 % of a smoke render's time.
    bricks: FxHashMap<IVec3, Brick>,
    voxels: BrickValues,
    /// Largest value of each voxel brick, by slot.
    voxel_brick_max: Vec<f32>,
    index_to_world: Mat4,
    /// Inclusive index bounds of the values set (empty: min > max).
    active_min: IVec3,
    active_max: IVec3,
}

/// A summary, not the voxels (a cloud holds millions, and render parts
/// hash a scene through its `Debug` form, `parts::scene_hash`): the
/// bricks, precision, active bounds, transform and
/// [`SparseGrid::content_digest`].
impl std::fmt::Debug for SparseGrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseGrid")
            .field("bricks", &self.brick_counts())
            .field("precision", &self.precision())
            .field("active", &self.active_bounds())
            .field("index_to_world", &self.index_to_world)
            .field("digest", &format_args!("{:016x}", self.content_digest()))
            .finish()
    }
}

impl SparseGrid {
    /// A 64-bit digest (Fx hashing) of the grid's contents in a canonical
    /// order: its bricks sorted by coordinate, each with its tile value or
    /// its voxels as stored. Grids that hold the same values digest alike
    /// however they were built, which the brick map's iteration order
    /// does not promise: a scene hash that followed it (the derived
    /// `Debug`, under the standard hasher's per-map random keys) told two
    /// loads of one VDB file apart, so their render parts did not merge.
    pub fn content_digest(&self) -> u64 {
        let mut keys: Vec<(IVec3, Brick)> = self.bricks.iter().map(|(k, b)| (*k, *b)).collect();
        keys.sort_unstable_by_key(|(k, _)| (k.z, k.y, k.x));
        let mut h = FxHasher::default();
        for (key, brick) in keys {
            for c in key.to_array() {
                h.write_i32(c);
            }
            match brick {
                Brick::Constant(c) => {
                    h.write_u8(0);
                    h.write_u32(c.to_bits());
                }
                Brick::Voxels(slot) => {
                    h.write_u8(1);
                    match &self.voxels {
                        BrickValues::Full(v) => v[slot as usize]
                            .iter()
                            .for_each(|x| h.write_u32(x.to_bits())),
                        BrickValues::Half(v) => {
                            v[slot as usize].iter().for_each(|x| h.write_u16(*x))
                        }
                    }
                }
            }
        }
        h.finish()
    }

    /// An empty grid (all background) of `f32` voxels with its
    /// index-to-world transform.
    pub fn new(index_to_world: Mat4) -> Self {
        Self::with_precision(index_to_world, Precision::Full)
    }

    /// An empty grid (all background) storing its voxels in `precision`.
    pub fn with_precision(index_to_world: Mat4, precision: Precision) -> Self {
        Self {
            bricks: FxHashMap::default(),
            voxels: match precision {
                Precision::Full => BrickValues::Full(Vec::new()),
                Precision::Half => BrickValues::Half(Vec::new()),
            },
            voxel_brick_max: Vec::new(),
            index_to_world,
            active_min: IVec3::MAX,
            active_max: IVec3::MIN,
        }
    }

    /// The precision of the voxel bricks.
    pub fn precision(&self) -> Precision {
        match self.voxels {
            BrickValues::Full(_) => Precision::Full,
            BrickValues::Half(_) => Precision::Half,
        }
    }

    /// `value` as stored, or why it cannot be a density.
    fn checked(&self, value: f32) -> Result<f32, String> {
        if !(value.is_finite() && value >= 0.0) {
            return Err(format!("densities must be finite and ≥ 0, found {value}"));
        }
        let stored = self.voxels.stored(value);
        if !stored.is_finite() {
            return Err(format!(
                "{value} exceeds the largest half float ({})",
                f16::MAX
            ));
        }
        // −0 is stored as +0.
        Ok(if stored == 0.0 { 0.0 } else { stored })
    }

    fn local(i: IVec3) -> usize {
        let l = i & (BRICK - 1);
        (l.x + BRICK * (l.y + BRICK * l.z)) as usize
    }

    /// The slot of the voxel brick at brick coordinate `key`, made (from
    /// the tile there, or background) if there is none.
    fn voxel_slot(&mut self, key: IVec3) -> usize {
        match self.bricks.get(&key) {
            Some(Brick::Voxels(slot)) => *slot as usize,
            other => {
                let fill = match other {
                    Some(Brick::Constant(c)) => *c,
                    _ => 0.0,
                };
                self.voxels.push(fill);
                self.voxel_brick_max.push(fill);
                let slot = self.voxels.len() - 1;
                self.bricks.insert(key, Brick::Voxels(slot as u32));
                slot
            }
        }
    }

    /// Sets the value of voxel `i` (rounded to the grid's precision).
    pub fn set_voxel(&mut self, i: IVec3, value: f32) -> Result<(), String> {
        let value = self.checked(value)?;
        let slot = self.voxel_slot(i >> BRICK_LOG2);
        self.voxels.set(slot, Self::local(i), value);
        self.voxel_brick_max[slot] = self.voxel_brick_max[slot].max(value);
        self.active_min = self.active_min.min(i);
        self.active_max = self.active_max.max(i);
        Ok(())
    }

    /// Sets the active voxels of the brick at `origin` (a multiple of 8)
    /// at once, as an OpenVDB leaf holds them: `values` in slot order
    /// (voxel `origin + (x, y, z)` at `64x + 8y + z`), voxel `n` active
    /// where bit `n % 64` of `mask[n / 64]` is set. Inactive voxels keep
    /// what the brick held. On an error nothing is set; it names the
    /// voxel.
    pub fn insert_leaf(
        &mut self,
        origin: IVec3,
        mask: &[u64; BRICK_VOXELS / 64],
        values: &[f32; BRICK_VOXELS],
    ) -> Result<(), String> {
        if origin % BRICK != IVec3::ZERO {
            return Err(format!(
                "a leaf's origin must be a multiple of {BRICK}, got {origin}"
            ));
        }
        let active = |n: usize| mask[n / 64] >> (n % 64) & 1 == 1;
        // OpenVDB's slot n = 64x + 8y + z; a brick's local index is x + 8y + 64z.
        let voxel = |n: usize| IVec3::new((n >> 6) as i32, (n >> 3 & 7) as i32, (n & 7) as i32);
        let mut stored = [0.0f32; BRICK_VOXELS];
        let (mut lo, mut hi) = (IVec3::splat(BRICK), IVec3::splat(-1));
        let mut max = 0.0f32;
        for n in (0..BRICK_VOXELS).filter(|&n| active(n)) {
            let v = self
                .checked(values[n])
                .map_err(|e| format!("voxel {}: {e}", origin + voxel(n)))?;
            stored[n] = v;
            max = max.max(v);
            lo = lo.min(voxel(n));
            hi = hi.max(voxel(n));
        }
        if hi.x < 0 {
            return Ok(());
        }
        let slot = self.voxel_slot(origin >> BRICK_LOG2);
        for n in (0..BRICK_VOXELS).filter(|&n| active(n)) {
            self.voxels.set(slot, Self::local(voxel(n)), stored[n]);
        }
        self.voxel_brick_max[slot] = self.voxel_brick_max[slot].max(max);
        self.active_min = self.active_min.min(origin + lo);
        self.active_max = self.active_max.max(origin + hi);
        Ok(())
    }

    /// Releases the spare capacity that growing the grid left: call when
    /// every brick is in.
    pub fn shrink_to_fit(&mut self) {
        self.bricks.shrink_to_fit();
        self.voxels.shrink_to_fit();
        self.voxel_brick_max.shrink_to_fit();
    }

    /// Voxels of non-zero value, in voxel bricks and in constant bricks.
    pub fn nonzero_voxels(&self) -> u64 {
        let in_bricks: usize = match &self.voxels {
            BrickValues::Full(v) => v.iter().flatten().filter(|&&x| x != 0.0).count(),
            // +0 is the only zero stored (`checked` turns −0 into +0).
            BrickValues::Half(v) => v.iter().flatten().filter(|&&x| x != 0).count(),
        };
        let tiles = self
            .bricks
            .values()
            .filter(|b| matches!(b, Brick::Constant(c) if *c != 0.0))
            .count();
        in_bricks as u64 + (tiles * BRICK_VOXELS) as u64
    }

    /// Bytes held by the voxel bricks, their maxima and the brick map:
    /// an entry and a control byte per bucket, the buckets a power of two
    /// of which the map fills at most 7/8 (std's SwissTable).
    pub fn storage_bytes(&self) -> usize {
        let entry = std::mem::size_of::<(IVec3, Brick)>() + 1;
        let buckets = match self.bricks.capacity() {
            0 => 0,
            capacity => (capacity * 8).div_ceil(7).next_power_of_two(),
        };
        self.voxels.bytes()
            + std::mem::size_of_val(self.voxel_brick_max.as_slice())
            + buckets * entry
    }

    /// Sets every voxel of the cube of side `size` (a multiple of 8) from
    /// `origin` (a multiple of 8) to `value`: an OpenVDB tile.
    pub fn fill_tile(&mut self, origin: IVec3, size: i32, value: f32) -> Result<(), String> {
        let value = self.checked(value)?;
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
            Some(Brick::Voxels(slot)) => self.voxels.get(*slot as usize, Self::local(i)),
            Some(Brick::Constant(c)) => *c,
            None => 0.0,
        }
    }

    /// Trilinear interpolation between the voxels around index-space
    /// point `g`.
    #[inline]
    pub fn eval_index(&self, g: Vec3) -> f32 {
        self.interpolate_mapped(g, |v| v)
    }

    /// Trilinear interpolation between the voxels around index-space
    /// point `g` of `map` of their values (background voxels: `map(0)`):
    /// the mean of `map` at one voxel drawn with the trilinear weights,
    /// which is what a renderer that interpolates stochastically (one
    /// tap, as Cycles does) computes for a shader `map` of the grid.
    #[inline]
    pub fn interpolate_mapped<V: Interpolant>(&self, g: Vec3, map: impl Fn(f32) -> V) -> V {
        let base = g.floor();
        let f = g - base;
        let i = base.as_ivec3();
        // Most points have all eight neighbours in one brick: one lookup.
        if (i & (BRICK - 1)).cmplt(IVec3::splat(BRICK - 1)).all() {
            return match self.bricks.get(&(i >> BRICK_LOG2)) {
                None => map(0.0),
                Some(Brick::Constant(c)) => map(*c),
                Some(Brick::Voxels(slot)) => match &self.voxels {
                    BrickValues::Full(v) => {
                        let voxels = &v[*slot as usize];
                        trilinear(i, f, |j| map(voxels[Self::local(j)]))
                    }
                    BrickValues::Half(v) => {
                        let voxels = &v[*slot as usize];
                        trilinear(i, f, |j| {
                            map(f16::from_bits(voxels[Self::local(j)]).to_f32())
                        })
                    }
                },
            };
        }
        trilinear(i, f, |j| map(self.value(j)))
    }

    /// An upper bound of interpolation ([`Self::eval_index`]) over the
    /// index-space box `[lo, hi]`, the largest voxel it reads there (a
    /// brick read whole gives its recorded maximum, which a voxel lowered
    /// after it was set leaves above its values): a point `g` reads the voxels
    /// `floor(g)` and `floor(g) + 1` on each axis, so the box reads
    /// `floor(lo) ..= floor(hi) + 1`, and trilinear interpolation, a
    /// convex combination of them, is at most their largest value (exact
    /// where one of them is that large). Bricks whose maximum (from their
    /// leaf or tile) cannot raise the bound are not read, and a brick the
    /// box covers whole is its maximum, so a box reads few voxels beyond
    /// its fringe. A bound by whole bricks was looser: a majorant cell of
    /// one brick's size, offset by half a voxel, took the largest of up
    /// to 27 bricks, and scenes/reference/smoke-grid took 1.2× the time
    /// per sample (docs/benchmarks.md).
    pub fn max_in_index(&self, lo: Vec3, hi: Vec3) -> f32 {
        let (v0, v1) = (lo.floor().as_ivec3(), hi.floor().as_ivec3() + 1);
        let (first, last) = (v0 >> BRICK_LOG2, v1 >> BRICK_LOG2);
        let mut max = 0.0f32;
        let mut visit = |key: IVec3, brick: &Brick| {
            let slot = match brick {
                Brick::Constant(c) => {
                    max = max.max(*c);
                    return;
                }
                Brick::Voxels(slot) => *slot as usize,
            };
            if self.voxel_brick_max[slot] <= max {
                return;
            }
            let origin = key << BRICK_LOG2;
            let (a, b) = (
                (v0 - origin).max(IVec3::ZERO),
                (v1 - origin).min(IVec3::splat(BRICK - 1)),
            );
            if a == IVec3::ZERO && b == IVec3::splat(BRICK - 1) {
                max = self.voxel_brick_max[slot];
                return;
            }
            for z in a.z..=b.z {
                for y in a.y..=b.y {
                    for x in a.x..=b.x {
                        max = max.max(self.voxels.get(slot, Self::local(IVec3::new(x, y, z))));
                    }
                }
            }
        };
        let span = (last - first + 1).max(IVec3::ZERO).as_i64vec3();
        if span.element_product() > self.bricks.len() as i64 {
            // Fewer stored bricks than brick positions: scan the bricks.
            for (key, brick) in &self.bricks {
                if key.cmpge(first).all() && key.cmple(last).all() {
                    visit(*key, brick);
                }
            }
            return max;
        }
        for z in first.z..=last.z {
            for y in first.y..=last.y {
                for x in first.x..=last.x {
                    let key = IVec3::new(x, y, z);
                    if let Some(brick) = self.bricks.get(&key) {
                        visit(key, brick);
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

/// A value trilinear interpolation can weigh: a density (`f32`) or a
/// colour.
pub trait Interpolant:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<f32, Output = Self>
{
}

impl<V> Interpolant for V where
    V: Copy
        + std::ops::Add<Output = V>
        + std::ops::Sub<Output = V>
        + std::ops::Mul<f32, Output = V>
{
}

/// Trilinear interpolation at fraction `f` of the cell whose lowest corner
/// is voxel `i`, the corners' values given by `at`.
#[inline]
fn trilinear<V: Interpolant>(i: IVec3, f: Vec3, at: impl Fn(IVec3) -> V) -> V {
    let lerp = |a: V, b: V, t: f32| a + (b - a) * t;
    let row = |dy: i32, dz: i32| {
        lerp(
            at(i + IVec3::new(0, dy, dz)),
            at(i + IVec3::new(1, dy, dz)),
            f.x,
        )
    };
    let plane = |dz: i32| lerp(row(0, dz), row(1, dz), f.y);
    lerp(plane(0), plane(1), f.z)
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

    /// [`SparseGrid::interpolate_mapped`] at `u` in the unit cube.
    #[inline]
    pub fn eval_mapped<V: Interpolant>(&self, u: Vec3, map: impl Fn(f32) -> V) -> V {
        self.grid
            .interpolate_mapped(self.unit_to_index.transform_point3(u), map)
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

    /// The bound over a box is the largest voxel its interpolation reads,
    /// found by reading every one of them, on boxes across brick faces,
    /// inside one brick, over tiles and over empty space; and no sampled
    /// interpolated value exceeds it.
    #[test]
    fn max_in_index_is_the_largest_voxel_interpolation_reads() {
        let mut g = SparseGrid::with_precision(Mat4::IDENTITY, Precision::Half);
        g.fill_tile(IVec3::new(16, 0, 0), 8, 0.25).unwrap();
        let mut stream = crate::sampler::RandomStream::new(11);
        for _ in 0..600 {
            let i = IVec3::new(
                (stream.next_f32() * 24.0) as i32 - 8,
                (stream.next_f32() * 16.0) as i32,
                (stream.next_f32() * 16.0) as i32,
            );
            g.set_voxel(i, stream.next_f32() * 4.0).unwrap();
        }
        for _ in 0..300 {
            let corner = |s: &mut crate::sampler::RandomStream| {
                Vec3::new(
                    s.next_f32() * 40.0 - 12.0,
                    s.next_f32() * 20.0 - 2.0,
                    s.next_f32() * 20.0 - 2.0,
                )
            };
            let (a, b) = (corner(&mut stream), corner(&mut stream));
            let (lo, hi) = (
                a.min(b),
                a.min(b) + (a.max(b) - a.min(b)) * stream.next_f32() * 0.4,
            );
            let (v0, v1) = (lo.floor().as_ivec3(), hi.floor().as_ivec3() + 1);
            let mut exact = 0.0f32;
            for z in v0.z..=v1.z {
                for y in v0.y..=v1.y {
                    for x in v0.x..=v1.x {
                        exact = exact.max(g.value(IVec3::new(x, y, z)));
                    }
                }
            }
            assert_eq!(g.max_in_index(lo, hi), exact, "box {lo} .. {hi}");
            for _ in 0..20 {
                let f = Vec3::new(stream.next_f32(), stream.next_f32(), stream.next_f32());
                assert!(g.eval_index(lo + (hi - lo) * f) <= exact * (1.0 + 1e-6));
            }
        }
    }

    /// Two grids of the same voxels built in opposite orders print (and so
    /// hash into a scene) alike; one voxel changed, they do not.
    #[test]
    fn debug_form_digests_the_contents_whatever_the_order_they_came_in() {
        let voxels: Vec<(IVec3, f32)> = (0..2000)
            .map(|n| {
                (
                    IVec3::new(n % 37 - 18, n / 37 % 23, n / 851 * 9),
                    0.01 * (n % 97) as f32,
                )
            })
            .collect();
        let build = |order: &mut dyn Iterator<Item = &(IVec3, f32)>| {
            let mut g = SparseGrid::with_precision(Mat4::IDENTITY, Precision::Half);
            g.fill_tile(IVec3::new(64, 0, 0), 8, 0.5).unwrap();
            for (i, v) in order {
                g.set_voxel(*i, *v).unwrap();
            }
            g
        };
        let forward = build(&mut voxels.iter());
        let backward = build(&mut voxels.iter().rev());
        assert_eq!(format!("{forward:?}"), format!("{backward:?}"));
        let mut changed = build(&mut voxels.iter());
        changed.set_voxel(IVec3::new(3, 4, 0), 0.75).unwrap();
        assert_ne!(format!("{forward:?}"), format!("{changed:?}"));
    }

    #[test]
    fn a_leaf_inserted_at_once_is_its_voxels_set_one_by_one() {
        let origin = IVec3::new(-8, 16, 24);
        let mut mask = [0u64; BRICK_VOXELS / 64];
        let mut values = [0.0f32; BRICK_VOXELS];
        for n in (0..BRICK_VOXELS).filter(|n| n % 3 != 1) {
            mask[n / 64] |= 1 << (n % 64);
            values[n] = 0.01 * n as f32;
        }
        for precision in [Precision::Full, Precision::Half] {
            let mut bulk = SparseGrid::with_precision(Mat4::IDENTITY, precision);
            bulk.insert_leaf(origin, &mask, &values).unwrap();
            let mut single = SparseGrid::with_precision(Mat4::IDENTITY, precision);
            for n in (0..BRICK_VOXELS).filter(|n| n % 3 != 1) {
                let local = IVec3::new(n as i32 >> 6, n as i32 >> 3 & 7, n as i32 & 7);
                single.set_voxel(origin + local, values[n]).unwrap();
            }
            assert_eq!(bulk, single, "{precision:?}");
            // Active are n ≢ 1 (mod 3), so voxel n = 0 and n = 511 are.
            assert_eq!(bulk.active_bounds(), Some((origin, origin + 7)));
            assert_eq!(
                bulk.nonzero_voxels(),
                (1..BRICK_VOXELS).filter(|n| n % 3 != 1).count() as u64
            );
        }
        // Half storage rounds to the nearest half: 0.01·3 = 0.03 is not one.
        let mut half = SparseGrid::with_precision(Mat4::IDENTITY, Precision::Half);
        half.insert_leaf(origin, &mask, &values).unwrap();
        let v = half.value(origin + IVec3::new(0, 0, 3));
        assert_eq!(v, f16::from_f32(0.03).to_f32());
        assert!((v - 0.03).abs() <= 0.03 * 2f32.powi(-11), "{v}");
        assert_eq!(SparseGrid::new(Mat4::IDENTITY).storage_bytes(), 0);
        // 1 KiB of halves, the brick's maximum, and whole map buckets.
        let map = half.storage_bytes() - (BRICK_VOXELS * 2 + 4);
        let entry = std::mem::size_of::<(IVec3, Brick)>() + 1;
        assert!(
            map >= entry && map.is_multiple_of(entry),
            "{map} bytes of map"
        );
    }

    #[test]
    fn bad_values_are_refused_and_leave_the_grid_unchanged() {
        let mut mask = [0u64; BRICK_VOXELS / 64];
        mask[1] = 1 << 5; // voxel n = 69: local (1, 0, 5)
        let mut values = [0.0f32; BRICK_VOXELS];
        values[69] = -1.0;
        let mut g = SparseGrid::with_precision(Mat4::IDENTITY, Precision::Half);
        let e = g.insert_leaf(IVec3::ZERO, &mask, &values).unwrap_err();
        assert!(e.contains("voxel [1, 0, 5]") && e.contains("≥ 0"), "{e}");
        values[69] = 1e6;
        let e = g.insert_leaf(IVec3::ZERO, &mask, &values).unwrap_err();
        assert!(e.contains("largest half float"), "{e}");
        // Inactive voxels are not read, bad or not.
        values[70] = f32::NAN;
        values[69] = 2.0;
        g.insert_leaf(IVec3::ZERO, &mask, &values).unwrap();
        assert_eq!(g.value(IVec3::new(1, 0, 5)), 2.0);
        assert_eq!(g.value(IVec3::new(1, 0, 6)), 0.0);
        let e = g
            .insert_leaf(IVec3::new(4, 0, 0), &mask, &values)
            .unwrap_err();
        assert!(e.contains("multiple of 8"), "{e}");
        assert_eq!(g.brick_counts(), (1, 0));
        // −0 is stored as +0 and is no non-zero voxel.
        g.set_voxel(IVec3::new(0, 0, 1), -0.0).unwrap();
        assert_eq!(g.nonzero_voxels(), 1);
    }
}
