//! The tree of a standard 5-4-3 grid: its topology (root, internal nodes,
//! leaf masks) and then its leaf buffers (OpenVDB tree/Tree.h
//! `readTopology`/`readBuffers`, tree/RootNode.h, tree/InternalNode.h,
//! tree/LeafNode.h).
//!
//! Topology: an `i32` buffer count (1), then the root: its background
//! (one full-precision value, even in half-float grids), `u32` counts of
//! tiles and children, each tile its origin (three `i32`), value and an
//! active byte, each child its origin and its subtree. An internal node
//! (32³ children of 128³ voxels at level 2, 16³ of 8³ at level 1) stores
//! its child mask and value mask (one bit per slot, `u64` words), then
//! all its slots' values through `readCompressedValues` (a slot's value
//! is a tile where the child bit is off; it is active where the value bit
//! is on), then its children in slot order. A leaf's topology is its
//! value mask (8³ bits).
//!
//! Buffers: for each leaf, in the order of the root's children sorted by
//! origin (the root keeps them in a `std::map<Coord, …>`, ordered x, then
//! y, then z) and then slot order, its value mask again and its 512
//! values. Slot `n` of a node of side 2^k lies at local
//! `(n >> 2k, (n >> k) & (2^k − 1), n & (2^k − 1))`, scaled by the
//! child's size.

use super::compression::{Codec, bit, read_compressed_values};
use super::stream::Stream;
use glam::IVec3;

/// Sides in voxels of a leaf, of a level-1 and of a level-2 node, and of a
/// root tile.
pub const LEAF: i32 = 8;
pub const NODE1: i32 = 128;
pub const NODE2: i32 = 4096;

/// What the tree reader hands out, in file order.
pub enum Item<'a> {
    /// A leaf: its origin, value mask (8 words) and 512 values
    /// (`components` floats each, in slot order).
    Leaf {
        origin: IVec3,
        mask: &'a [u64],
        values: &'a [f32],
    },
    /// A constant tile of `size`³ voxels from `origin`.
    Tile {
        origin: IVec3,
        size: i32,
        active: bool,
        value: &'a [f32],
    },
}

/// The local offset of slot `n` in a node of side `2^log2`.
pub fn slot(n: usize, log2: u32) -> IVec3 {
    let n = n as i32;
    let m = (1 << log2) - 1;
    IVec3::new(n >> (2 * log2), (n >> log2) & m, n & m)
}

/// Reads a tree's topology and buffers, handing each tile and leaf to
/// `sink`; returns the background value.
pub fn read_tree(
    s: &mut Stream,
    codec: &Codec,
    sink: &mut dyn FnMut(Item) -> Result<(), String>,
) -> Result<Vec<f32>, String> {
    let c = codec.components;
    let buffers = s.i32()?;
    if buffers != 1 {
        return Err(format!("the tree has {buffers} buffers; OpenVDB writes 1"));
    }
    let background: Vec<f32> = (0..c).map(|_| s.f32()).collect::<Result<_, _>>()?;
    let tiles = s.u32()?;
    let children = s.u32()?;
    let mut origins: Vec<[i32; 3]> = Vec::new();
    let aligned = |o: [i32; 3], what: &str| -> Result<IVec3, String> {
        if o.iter().any(|v| v & (NODE2 - 1) != 0) {
            return Err(format!(
                "a root {what} at {o:?} is not aligned to {NODE2} voxels"
            ));
        }
        Ok(IVec3::from_array(o))
    };
    for _ in 0..tiles {
        let o = s.coord()?;
        let value: Vec<f32> = (0..c).map(|_| s.f32()).collect::<Result<_, _>>()?;
        let active = s.u8()? != 0;
        let origin = aligned(o, "tile")?;
        origins.push(o);
        sink(Item::Tile {
            origin,
            size: NODE2,
            active,
            value: &value,
        })?;
    }
    // Leaf origins of each root child, in slot order.
    let mut subtrees: Vec<([i32; 3], Vec<IVec3>)> = Vec::new();
    for _ in 0..children {
        let o = s.coord()?;
        let origin = aligned(o, "child")?;
        origins.push(o);
        let mut leaves = Vec::new();
        read_internal(s, origin, 5, codec, &background, &mut leaves, sink)?;
        subtrees.push((o, leaves));
    }
    origins.sort_unstable();
    if let Some(w) = origins.windows(2).find(|w| w[0] == w[1]) {
        return Err(format!("the root holds two nodes at {:?}", w[0]));
    }
    subtrees.sort_unstable_by_key(|t| t.0);
    let mut values_of_leaf;
    for (_, leaves) in &subtrees {
        for &origin in leaves {
            let mask = s.words(8)?;
            values_of_leaf = read_compressed_values(s, 512, &mask, &background, codec)
                .map_err(|e| format!("the leaf at {origin}: {e}"))?;
            sink(Item::Leaf {
                origin,
                mask: &mask,
                values: &values_of_leaf,
            })?;
        }
    }
    Ok(background)
}

/// Reads the topology of an internal node of side `2^log2` children
/// (5: children are level-1 nodes of 128³ voxels; 4: children are
/// leaves), handing its tiles to `sink` and collecting its leaves'
/// origins.
fn read_internal(
    s: &mut Stream,
    origin: IVec3,
    log2: u32,
    codec: &Codec,
    background: &[f32],
    leaves: &mut Vec<IVec3>,
    sink: &mut dyn FnMut(Item) -> Result<(), String>,
) -> Result<(), String> {
    let n = 1usize << (3 * log2);
    let child_size = if log2 == 5 { NODE1 } else { LEAF };
    let child_mask = s.words(n / 64)?;
    let value_mask = s.words(n / 64)?;
    let values = read_compressed_values(s, n, &value_mask, background, codec)
        .map_err(|e| format!("the node at {origin}: {e}"))?;
    let c = codec.components;
    for i in (0..n).filter(|&i| !bit(&child_mask, i)) {
        sink(Item::Tile {
            origin: origin + slot(i, log2) * child_size,
            size: child_size,
            active: bit(&value_mask, i),
            value: &values[i * c..i * c + c],
        })?;
    }
    for i in (0..n).filter(|&i| bit(&child_mask, i)) {
        let child = origin + slot(i, log2) * child_size;
        if log2 == 5 {
            read_internal(s, child, 4, codec, background, leaves, sink)?;
        } else {
            s.words(8)?; // the leaf's value mask, read again with its buffer
            leaves.push(child);
        }
    }
    Ok(())
}
