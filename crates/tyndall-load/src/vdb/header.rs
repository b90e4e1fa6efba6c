//! The file header, metadata and grid descriptors (OpenVDB io/Archive.cc
//! `readHeader`, io/File.cc `readGridDescriptors`, io/GridDescriptor.cc,
//! Metadata.h / MetaMap.cc).
//!
//! Header: `i64` magic 0x56444220, `u32` file format version, and from
//! version 211 the library's major and minor version (`u32` each), from
//! 212 a byte saying whether grid offsets are stored, for versions 220
//! and 221 a byte saying whether the file is zip-compressed (from 222 the
//! compression flags are stored per grid), and from 218 a 36-character
//! UUID string. The file's metadata follows, then (with offsets) an
//! `i32` grid count and, for each grid, its descriptor followed by the
//! grid itself; the descriptor's end offset is where the next one starts.
//!
//! Versions read: 222 (OpenVDB 3; per-grid compression, active-mask
//! compression), 223 (Blosc), 224 (OpenVDB 4 and later, up to 12:
//! multi-pass I/O for point grids and the `file_delayed_load` metadata,
//! which is read as ordinary, skipped metadata). Older files are refused
//! by version number.

use super::stream::Stream;

pub const MAGIC: i64 = 0x5644_4220;
/// Oldest and newest file format versions read.
pub const OLDEST: u32 = 222;
pub const NEWEST: u32 = 224;
/// OpenVDB's separator between a grid's name and the suffix that makes
/// duplicate names unique (io/GridDescriptor.cc `SEP`).
const SEP: char = '\x1e';
/// The type-name suffix of grids saved as half floats
/// (io/GridDescriptor.cc `HALF_FLOAT_TYPENAME_SUFFIX`).
const HALF_SUFFIX: &str = "_HalfFloat";

/// What the header says.
#[derive(Debug)]
pub struct Header {
    pub version: u32,
}

/// A metadata entry: name, type name and the value's bytes. Each value is
/// written with its byte size first (Metadata.h `Metadata::write`), so
/// types this reader does not know (such as `__delayedload`) are skipped
/// by that size.
#[derive(Debug)]
pub struct Meta {
    pub name: String,
    pub type_name: String,
    pub value: Vec<u8>,
}

/// A grid's descriptor.
#[derive(Debug)]
pub struct Descriptor {
    /// The name as the user gave it (the unique suffix removed).
    pub name: String,
    /// The name made unique in the file (`name`, `SEP`, a number), as
    /// instances name their parents.
    pub unique_name: String,
    /// The tree type without the half-float suffix, e.g.
    /// `Tree_float_5_4_3`.
    pub grid_type: String,
    /// Whether the type name carried the half-float suffix.
    pub half_suffix: bool,
    /// The grid this one instances (shares the tree of), if any.
    pub instance_parent: String,
    /// Where the grid (compression, metadata, transform, topology) starts.
    pub grid_pos: u64,
}

/// Reads the header; refuses anything but a VDB file of versions
/// 222–224 with grid offsets.
pub fn read_header(s: &mut Stream) -> Result<Header, String> {
    let magic = s
        .i64()
        .map_err(|_| "not an OpenVDB file (too short)".to_string())?;
    if magic != MAGIC {
        return Err("not an OpenVDB file (no VDB magic number)".into());
    }
    let version = s.u32()?;
    if !(OLDEST..=NEWEST).contains(&version) {
        return Err(format!(
            "file format version {version}: this reader reads versions {OLDEST}–{NEWEST} (OpenVDB 3 to 12)"
        ));
    }
    // The writing library's major and minor version: not needed.
    s.take(8)?;
    let has_offsets = s.u8()?;
    if has_offsets == 0 {
        return Err("the file was written as a stream without grid offsets, which this reader does not read".into());
    }
    // From version 218 the UUID is a 36-character string (not
    // length-prefixed).
    s.take(36)?;
    Ok(Header { version })
}

/// Reads a metadata map (MetaMap::readMeta): an `u32` count, then per
/// entry a name, a type name and the value (`u32` size, bytes).
pub fn read_meta(s: &mut Stream) -> Result<Vec<Meta>, String> {
    let count = s.u32()?;
    // Each entry is at least three 4-byte lengths.
    if count as usize > s.remaining() / 12 {
        return Err(format!(
            "{count} metadata entries claimed, more than the {} bytes left can hold",
            s.remaining()
        ));
    }
    let mut out = Vec::new();
    for _ in 0..count {
        let name = s.string()?;
        let type_name = s.string()?;
        let size = s.u32()? as usize;
        let value = s
            .take(size)
            .map_err(|e| format!("metadata \"{name}\" of {size} bytes: {e}"))?
            .to_vec();
        out.push(Meta {
            name,
            type_name,
            value,
        });
    }
    Ok(out)
}

/// A string-valued metadata entry.
pub fn meta_string(meta: &[Meta], name: &str) -> Option<String> {
    meta.iter()
        .find(|m| m.name == name && m.type_name == "string")
        .map(|m| String::from_utf8_lossy(&m.value).into_owned())
}

/// A bool-valued metadata entry.
pub fn meta_bool(meta: &[Meta], name: &str) -> Option<bool> {
    meta.iter()
        .find(|m| m.name == name && m.type_name == "bool")
        .and_then(|m| m.value.first().map(|&b| b != 0))
}

/// Reads the grid descriptors after the file's metadata (File.cc
/// `readGridDescriptors`). Each descriptor: the unique name, the grid
/// type, the instance parent's name (from version 216), then the `i64`
/// offsets of the grid, of its buffers and of its end.
pub fn read_descriptors(s: &mut Stream) -> Result<Vec<Descriptor>, String> {
    let count = s.i32()?;
    // Each descriptor is at least three strings and three offsets.
    if count < 0 || count as usize > s.remaining() / 36 {
        return Err(format!("{count} grids claimed in {} bytes", s.remaining()));
    }
    let mut out = Vec::new();
    for g in 0..count {
        let unique = s.string()?;
        let name = match unique.find(SEP) {
            Some(i) => unique[..i].to_string(),
            None => unique.clone(),
        };
        // The buffers' offset is not used (and is 0 for instances).
        let mut grid_type = s.string()?;
        let half_suffix = grid_type.ends_with(HALF_SUFFIX);
        if half_suffix {
            grid_type.truncate(grid_type.len() - HALF_SUFFIX.len());
        }
        let instance_parent = s.string()?;
        let (grid_pos, _block_pos, end_pos) = (s.i64()?, s.i64()?, s.i64()?);
        let here = s.pos() as i64;
        if grid_pos < here || end_pos < grid_pos || end_pos > s.len() as i64 {
            return Err(format!(
                "grid #{g} (\"{name}\"): its offsets (grid {grid_pos}, end {end_pos}) do not fit the file of {} bytes",
                s.len()
            ));
        }
        out.push(Descriptor {
            name,
            unique_name: unique,
            grid_type,
            half_suffix,
            instance_parent,
            grid_pos: grid_pos as u64,
        });
        s.seek(end_pos as u64)?;
    }
    Ok(out)
}
