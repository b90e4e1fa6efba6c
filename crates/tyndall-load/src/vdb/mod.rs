//! OpenVDB grids (`.vdb`) read by Tyndall's own bounded reader into
//! [`SparseGrid`] without densifying: each leaf becomes a brick of 8³
//! voxels, each active tile constant bricks (see
//! `tyndall::media::sparse`).
//!
//! The whole file is read into memory and parsed by a cursor that checks
//! every length and count against the bytes left before allocating
//! ([`stream`]); decoded node buffers have the sizes their node types fix
//! (512 values a leaf), never sizes read from the file. Any input gives
//! `Ok` or an error naming the file, the grid and what is wrong; nothing
//! in the reader panics on file data.
//!
//! Read: file formats 222–224 ([`header`]); float grids
//! (`Tree_float_5_4_3`), full or half precision (the `_HalfFloat` type
//! suffix or the `is_saved_as_half_float` metadata); zip, Blosc (LZ4,
//! zlib) and active-mask compression ([`compression`]); every linear map
//! ([`transform`]); tiles at every level ([`tree`]); vec3 grids
//! (`Tree_vec3s_5_4_3`) through [`read_vector_grid`]; instanced grids
//! (sharing another grid's tree) with their own transform. Refused with a
//! message saying what they are: level sets, point grids, frustum
//! transforms, other value types, file formats before 222 (OpenVDB 2).
//!
//! Memory: the file's bytes, plus a 2 KiB brick per leaf (a leaf takes at
//! least 130 bytes of the file: two 64-byte masks and its values), plus
//! what tiles cost, bounded by [`MAX_TILE_BRICKS`]; a vec3 grid's active
//! tiles are listed, at most one per bit of a node's mask.
//!
//! As a density: the background must be 0 (a [`SparseGrid`] is 0
//! outside its bricks), inactive voxels and tiles take the background,
//! active values must be finite and ≥ 0. An active root tile (4096³
//! voxels) with a non-zero value is refused, and all active tiles
//! together may cover at most [`MAX_TILE_BRICKS`] bricks of 8³, since a
//! [`SparseGrid`] stores a tile as one map entry per brick.
//!
//! Grids are chosen by name: `"density"` is the first grid
//! of that name, `"density[1]"` the second, `"#2"` the third grid in the
//! file whatever its name.

mod compression;
mod header;
mod stream;
mod transform;
mod tree;

use crate::files::MAX_VDB_FILE_BYTES;
use compression::{COMPRESS_ACTIVE_MASK, COMPRESS_BLOSC, COMPRESS_ZIP, Codec, bit};
use glam::{IVec3, Mat4, Vec3};
use header::{Descriptor, meta_bool, meta_string};
use std::path::Path;
use stream::Stream;
use tree::{Item, LEAF, NODE2, slot};
use tyndall::media::sparse::{Precision, SparseGrid};

/// The most 8³ bricks that active tiles may fill (2^21 bricks: 1024³
/// voxels, some 60 MB of map entries).
pub const MAX_TILE_BRICKS: u64 = 1 << 21;

/// The tree types read: OpenVDB's standard 5-4-3 tree of floats and of
/// float vectors.
const FLOAT_TREE: &str = "Tree_float_5_4_3";
const VEC3_TREE: &str = "Tree_vec3s_5_4_3";

/// A vec3 grid's active values (not used by rendering yet).
#[derive(Clone, Debug, PartialEq)]
pub struct VectorGrid {
    pub index_to_world: Mat4,
    pub background: Vec3,
    /// Active voxels: index and value.
    pub voxels: Vec<(IVec3, Vec3)>,
    /// Active tiles: origin, side in voxels, value.
    pub tiles: Vec<(IVec3, i32, Vec3)>,
}

/// A grid of a file as [`list_grids`] reports it.
#[derive(Clone, Debug, PartialEq)]
pub struct GridEntry {
    /// What selects it: its name, or `name[k]` for the k-th duplicate.
    pub selector: String,
    /// Its tree type, e.g. `Tree_float_5_4_3`, with `_HalfFloat` if
    /// saved as halves.
    pub grid_type: String,
    /// Its compression flags (OpenVDB io/Compression.h: 0x1 zip, 0x2
    /// active mask, 0x4 Blosc), `None` if they cannot be read.
    pub compression: Option<u32>,
}

/// A parsed file.
struct File {
    data: Vec<u8>,
    descriptors: Vec<Descriptor>,
    version: u32,
}

/// Reads the file at `path` (a regular file of at most
/// [`MAX_VDB_FILE_BYTES`]: `/dev/zero` is refused, not read) and parses
/// its header.
fn open(path: &Path) -> Result<File, String> {
    // A device or pipe (`/dev/zero`) would be read up to the cap first.
    if let Ok(metadata) = std::fs::metadata(path)
        && !metadata.is_file()
    {
        return Err(format!(
            "{}: cannot read: it is not a regular file",
            path.display()
        ));
    }
    let data = crate::files::read_capped(path, MAX_VDB_FILE_BYTES)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    parse(path, data)
}

/// Parses the header and grid descriptors of a file's bytes `data`;
/// errors name `path`.
fn parse(path: &Path, data: Vec<u8>) -> Result<File, String> {
    let parse = |data: &[u8]| -> Result<(Vec<Descriptor>, u32), String> {
        let mut s = Stream::new(data);
        let h = header::read_header(&mut s)?;
        header::read_meta(&mut s).map_err(|e| format!("the file's metadata: {e}"))?;
        Ok((header::read_descriptors(&mut s)?, h.version))
    };
    let (descriptors, version) = parse(&data)
        .map_err(|e| format!("{}: not a readable OpenVDB file: {e}", path.display()))?;
    Ok(File {
        data,
        descriptors,
        version,
    })
}

/// The selector of each grid: its name, with `[k]` for the k-th of a
/// repeated name.
fn selectors(descriptors: &[Descriptor]) -> Vec<String> {
    descriptors
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let k = descriptors[..i].iter().filter(|e| e.name == d.name).count();
            if k == 0 {
                d.name.clone()
            } else {
                format!("{}[{k}]", d.name)
            }
        })
        .collect()
}

/// The index of the grid `name` selects: a grid's exact name (the first
/// of that name), `name[k]` (the k-th grid of that name, from 0), or
/// `#i` (the i-th grid of the file, from 0).
fn select(descriptors: &[Descriptor], name: &str) -> Option<usize> {
    if let Some(i) = descriptors.iter().position(|d| d.name == name) {
        return Some(i);
    }
    if let Some(i) = name.strip_prefix('#').and_then(|n| n.parse::<usize>().ok()) {
        return (i < descriptors.len()).then_some(i);
    }
    selectors(descriptors).iter().position(|s| s == name)
}

/// The grids of the file at `path`, in file order.
pub fn list_grids(path: &Path) -> Result<Vec<GridEntry>, String> {
    entries(&open(path)?)
}

/// [`list_grids`] of a file held in memory (for fuzzers); errors name
/// `path`.
pub fn list_grids_from_bytes(path: &Path, bytes: &[u8]) -> Result<Vec<GridEntry>, String> {
    entries(&parse(path, bytes.to_vec())?)
}

fn entries(file: &File) -> Result<Vec<GridEntry>, String> {
    Ok(selectors(&file.descriptors)
        .into_iter()
        .zip(&file.descriptors)
        .map(|(selector, d)| {
            let mut s = Stream::new(&file.data);
            GridEntry {
                selector,
                grid_type: format!(
                    "{}{}",
                    d.grid_type,
                    if d.half_suffix { "_HalfFloat" } else { "" }
                ),
                compression: s.seek(d.grid_pos).and_then(|_| s.u32()).ok(),
            }
        })
        .collect())
}

/// What kind of values a grid holds, as needed.
#[derive(Clone, Copy, PartialEq)]
enum Want {
    Density,
    Vector,
}

/// A grid positioned at its tree, with what the reader needs.
struct Grid<'a> {
    stream: Stream<'a>,
    codec: Codec,
    index_to_world: Mat4,
}

/// Finds grid `name`, checks its type against `want`, reads its
/// compression, metadata and transform. Errors are prefixed by the caller.
fn locate<'a>(file: &'a File, name: &str, want: Want) -> Result<Grid<'a>, String> {
    let Some(index) = select(&file.descriptors, name) else {
        let names = selectors(&file.descriptors);
        return Err(format!(
            "is not in the file; it holds {} (choose one by name, `name[k]` for the k-th of a repeated name, or `#i` for the i-th grid)",
            if names.is_empty() {
                "no grids".to_string()
            } else {
                names
                    .iter()
                    .map(|n| format!("\"{n}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            }
        ));
    };
    let d = &file.descriptors[index];
    let t = d.grid_type.as_str();
    let tree_name = format!("{t}{}", if d.half_suffix { "_HalfFloat" } else { "" });
    if t.starts_with("Tree_ptdataidx") || t.starts_with("Tree_ptidx") {
        return Err(format!(
            "is a point grid ({tree_name}: OpenVDB points, particles rather than a volume), which cannot be a density"
        ));
    }
    let components = match (t, want) {
        (FLOAT_TREE, Want::Density) => 1,
        (VEC3_TREE, Want::Vector) => 3,
        (VEC3_TREE, Want::Density) => {
            return Err(format!(
                "holds vectors ({tree_name}), not densities: only float grids ({FLOAT_TREE}) can be densities"
            ));
        }
        (FLOAT_TREE, Want::Vector) => {
            return Err(format!(
                "holds floats ({tree_name}), not vectors ({VEC3_TREE})"
            ));
        }
        _ => {
            return Err(format!(
                "holds {tree_name} values, which this reader does not read: only float grids ({FLOAT_TREE}, full or half precision){} are read",
                if want == Want::Vector {
                    " and vec3s grids"
                } else {
                    ""
                }
            ));
        }
    };
    let (s, flags, half, index_to_world) = head(file, d)?;
    let (stream, flags, half) = if d.instance_parent.is_empty() {
        (s, flags, half)
    } else {
        // An instance (format 216 on) stores no tree: it shares that of
        // the grid its descriptor names by unique name (io/Archive.cc
        // `connectInstance`), read with that grid's compression; the
        // instance's own transform places it.
        let parent = file
            .descriptors
            .iter()
            .find(|p| p.unique_name == d.instance_parent && p.instance_parent.is_empty())
            .ok_or_else(|| {
                format!(
                    "is an instance of grid \"{}\", which is not in the file (or is an instance itself)",
                    d.instance_parent
                )
            })?;
        if parent.grid_type != d.grid_type {
            return Err(format!(
                "is an instance of grid \"{}\" of another type ({})",
                parent.name, parent.grid_type
            ));
        }
        let (s, flags, half, _) = head(file, parent)
            .map_err(|e| format!("instances grid \"{}\", which {e}", parent.name))?;
        (s, flags, half)
    };
    Ok(Grid {
        stream,
        codec: Codec {
            flags,
            half,
            components,
        },
        index_to_world,
    })
}

/// Reads what precedes a grid's tree: its compression flags (stored per
/// grid from format 222: io/Archive.cc `readGridCompression`), metadata
/// (refusing level sets; saying whether values are halves) and transform;
/// the stream is left at the tree.
fn head<'a>(file: &'a File, d: &Descriptor) -> Result<(Stream<'a>, u32, bool, Mat4), String> {
    let mut s = Stream::new(&file.data);
    s.seek(d.grid_pos)?;
    let flags = s.u32()?;
    if flags & !(COMPRESS_ZIP | COMPRESS_ACTIVE_MASK | COMPRESS_BLOSC) != 0 {
        return Err(format!("has unknown compression flags {flags:#x}"));
    }
    if flags & COMPRESS_BLOSC != 0 && file.version < 223 {
        return Err(format!(
            "is Blosc-compressed in a file of format {}, before Blosc (223)",
            file.version
        ));
    }
    let meta = header::read_meta(&mut s).map_err(|e| format!("its metadata: {e}"))?;
    if meta_string(&meta, "class").as_deref() == Some("level set") {
        return Err("is a level set (grid class \"level set\": signed distances to a surface, not densities); convert it to a fog volume first (e.g. OpenVDB's tools::sdfToFogVolume, Houdini's VDB Convert)".into());
    }
    let half = d.half_suffix || meta_bool(&meta, "is_saved_as_half_float") == Some(true);
    let index_to_world = transform::read_transform(&mut s)
        .map_err(|e| e.replace("the grid's transform", "its transform"))?;
    Ok((s, flags, half, index_to_world))
}

/// Reads the float grid `name` (its name, `name[k]` or `#i`: see the
/// module's doc) of the OpenVDB file at
/// `path` as a density, with its index-to-world transform. Errors name
/// the file and the grid.
pub fn read_grid(path: &Path, name: &str) -> Result<SparseGrid, String> {
    density_grid(path, &open(path)?, name)
}

/// [`read_grid`] of a file held in memory (for fuzzers); errors name
/// `path`.
pub fn read_grid_from_bytes(path: &Path, bytes: &[u8], name: &str) -> Result<SparseGrid, String> {
    density_grid(path, &parse(path, bytes.to_vec())?, name)
}

fn density_grid(path: &Path, file: &File, name: &str) -> Result<SparseGrid, String> {
    let what = format!("{}: grid \"{name}\"", path.display());
    let mut grid = locate(file, name, Want::Density).map_err(|e| format!("{what} {e}"))?;
    // Half-float grids stay half floats: 2 bytes a voxel, exact.
    let precision = if grid.codec.half {
        Precision::Half
    } else {
        Precision::Full
    };
    let mut sparse = SparseGrid::with_precision(grid.index_to_world, precision);
    let mut tile_bricks = 0u64;
    let mut sink = |item: Item| -> Result<(), String> {
        match item {
            Item::Leaf {
                origin,
                mask,
                values,
            } => {
                let (Ok(mask), Ok(values)) = (mask.try_into(), values.try_into()) else {
                    return Err(format!(
                        "the leaf at {origin} holds {} values, not {LEAF}³",
                        values.len()
                    ));
                };
                sparse.insert_leaf(origin, mask, values)?;
            }
            Item::Tile {
                origin,
                size,
                active,
                value,
            } => {
                let v = value[0];
                if !active || v == 0.0 {
                    // Inactive tiles hold the background; a 0 tile adds nothing.
                    return Ok(());
                }
                if size == NODE2 {
                    return Err(format!(
                        "has an active root tile of {NODE2}³ voxels at {origin} with value {v}, too large to store as bricks; this reader refuses it"
                    ));
                }
                tile_bricks += (size as u64 / LEAF as u64).pow(3);
                if tile_bricks > MAX_TILE_BRICKS {
                    return Err(format!(
                        "has active tiles covering more than {MAX_TILE_BRICKS} bricks of {LEAF}³ voxels (the tile at {origin}), more than this reader stores"
                    ));
                }
                sparse
                    .fill_tile(origin, size, v)
                    .map_err(|e| format!("the tile of {size}³ at {origin}: {e}"))?;
            }
        }
        Ok(())
    };
    let background = tree::read_tree(&mut grid.stream, &grid.codec, &mut sink)
        .map_err(|e| format!("{what}: {e}"))?;
    if background[0] != 0.0 {
        return Err(format!(
            "{what} has background value {}: a density grid's background (its value outside the active voxels) must be 0",
            background[0]
        ));
    }
    sparse.shrink_to_fit();
    Ok(sparse)
}

/// Reads the vec3 grid `name` (chosen as by [`read_grid`]; `Tree_vec3s_5_4_3`, full or half
/// precision) of the OpenVDB file at `path`: its active voxels and tiles.
pub fn read_vector_grid(path: &Path, name: &str) -> Result<VectorGrid, String> {
    vector_grid(path, &open(path)?, name)
}

/// [`read_vector_grid`] of a file held in memory (for fuzzers); errors
/// name `path`.
pub fn read_vector_grid_from_bytes(
    path: &Path,
    bytes: &[u8],
    name: &str,
) -> Result<VectorGrid, String> {
    vector_grid(path, &parse(path, bytes.to_vec())?, name)
}

fn vector_grid(path: &Path, file: &File, name: &str) -> Result<VectorGrid, String> {
    let what = format!("{}: grid \"{name}\"", path.display());
    let mut grid = locate(file, name, Want::Vector).map_err(|e| format!("{what} {e}"))?;
    let (mut voxels, mut tiles) = (Vec::new(), Vec::new());
    let mut sink = |item: Item| -> Result<(), String> {
        match item {
            Item::Leaf {
                origin,
                mask,
                values,
            } => {
                for n in (0..512).filter(|&n| bit(mask, n)) {
                    voxels.push((
                        origin + slot(n, 3),
                        Vec3::from_slice(&values[3 * n..3 * n + 3]),
                    ));
                }
            }
            Item::Tile {
                origin,
                size,
                active: true,
                value,
            } => tiles.push((origin, size, Vec3::from_slice(value))),
            Item::Tile { .. } => {}
        }
        Ok(())
    };
    let background = tree::read_tree(&mut grid.stream, &grid.codec, &mut sink)
        .map_err(|e| format!("{what}: {e}"))?;
    Ok(VectorGrid {
        index_to_world: grid.index_to_world,
        background: Vec3::from_slice(&background),
        voxels,
        tiles,
    })
}
