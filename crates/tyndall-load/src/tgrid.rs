//! The `.tgrid` voxel grid file: a one-line ASCII header followed by raw
//! data,
//!
//! ```text
//! tyndall-grid 1 <nx> <ny> <nz>\n
//! <nx·ny·nz little-endian f32 densities, x fastest, then y, then z>
//! ```
//!
//! read into and written from the core's [`VoxelGrid`].

use glam::UVec3;
use std::io::Read;
use std::path::Path;
use tyndall::media::grid::{MAX_VOXELS, VoxelGrid, voxel_count};

/// Most bytes the header line may take, its newline included.
const HEADER_BYTES: u64 = 256;

/// The header's magic word and the only version this reader knows.
const MAGIC: &str = "tyndall-grid";
const VERSION: u32 = 1;

/// The file's bytes (see the module documentation).
pub fn to_bytes(grid: &VoxelGrid) -> Vec<u8> {
    let s = grid.size();
    let mut bytes = format!("{MAGIC} {VERSION} {} {} {}\n", s.x, s.y, s.z).into_bytes();
    bytes.reserve(grid.values().len() * 4);
    for v in grid.values() {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    bytes
}

/// Parses a `.tgrid` file's bytes; the error says what is wrong and
/// where (header field, or voxel index and its byte offset).
pub fn from_bytes(bytes: &[u8]) -> Result<VoxelGrid, String> {
    let (size, count, header_end) = parse_header(bytes)?;
    from_data(size, count, header_end, bytes)
}

/// The grid size, voxel count and the header line's length (without
/// its newline) from the first bytes of a file (256 are enough).
fn parse_header(bytes: &[u8]) -> Result<(UVec3, u64, usize), String> {
    let header_end = bytes
        .iter()
        .take(HEADER_BYTES as usize)
        .position(|&b| b == b'\n')
        .ok_or_else(|| format!("line 1: no `{MAGIC} {VERSION} nx ny nz` header line"))?;
    let header = std::str::from_utf8(&bytes[..header_end])
        .map_err(|_| "line 1: the header is not text".to_string())?;
    // (1-based column, text) of each whitespace-separated field.
    let fields: Vec<(usize, &str)> = header
        .split(' ')
        .scan(1, |column, field| {
            let at = *column;
            *column += field.len() + 1;
            Some((at, field))
        })
        .filter(|(_, field)| !field.is_empty())
        .collect();
    let field = |i: usize| fields.get(i).map_or("", |f| f.1);
    if field(0) != MAGIC {
        return Err(format!(
            "line 1, column 1: expected `{MAGIC}`, found `{}`",
            field(0)
        ));
    }
    if field(1) != "1" {
        return Err(format!(
            "line 1: unsupported version `{}` (this reader knows version {VERSION})",
            field(1)
        ));
    }
    if fields.len() != 5 {
        return Err(format!(
            "line 1: expected `{MAGIC} {VERSION} nx ny nz`, found `{header}`"
        ));
    }
    let mut size = [0u32; 3];
    for (axis, (slot, &(column, field))) in size.iter_mut().zip(&fields[2..]).enumerate() {
        *slot = field.parse().ok().filter(|&n| n > 0).ok_or_else(|| {
            format!(
                "line 1, column {column}: size n{} must be a positive integer, found `{field}`",
                ["x", "y", "z"][axis]
            )
        })?;
    }
    let size = UVec3::from_array(size);
    let count = match voxel_count(size) {
        Some(count) if count <= MAX_VOXELS => count,
        _ => {
            return Err(format!(
                "line 1: {}×{}×{} voxels is more than the {MAX_VOXELS} this reader accepts",
                size.x, size.y, size.z
            ));
        }
    };
    Ok((size, count, header_end))
}

/// The voxels after a parsed header.
fn from_data(
    size: UVec3,
    count: u64,
    header_end: usize,
    bytes: &[u8],
) -> Result<VoxelGrid, String> {
    let data = &bytes[header_end + 1..];
    if data.len() as u64 != count * 4 {
        return Err(format!(
            "expected {count} f32 values ({} bytes) after the header, found {} bytes",
            count * 4,
            data.len()
        ));
    }
    let mut values = Vec::with_capacity(count as usize);
    for (index, chunk) in data.chunks_exact(4).enumerate() {
        let v = f32::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]);
        if !(v.is_finite() && v >= 0.0) {
            return Err(format!(
                "voxel {index} (byte {}): density must be finite and non-negative, found {v}",
                header_end + 1 + 4 * index
            ));
        }
        values.push(v);
    }
    VoxelGrid::new(size, values).ok_or_else(|| "the grid is empty".to_string())
}

/// Reads a `.tgrid` file; errors name the file.
pub fn read(path: &Path) -> Result<VoxelGrid, String> {
    let cannot = |e: String| format!("cannot read grid file `{}`: {e}", path.display());
    let named = |e: String| format!("grid file `{}`: {e}", path.display());
    let file = std::fs::File::open(path).map_err(|e| cannot(e.to_string()))?;
    if file.metadata().is_ok_and(|m| m.is_dir()) {
        return Err(cannot("it is a directory".into()));
    }
    // The header first: it says how many bytes follow, so no more
    // than that (and one to spot a longer file) is ever read, and a
    // file such as `/dev/zero` fails right after its header.
    let mut reader = std::io::BufReader::new(file);
    let mut bytes = Vec::new();
    (&mut reader)
        .take(HEADER_BYTES)
        .read_to_end(&mut bytes)
        .map_err(|e| cannot(e.to_string()))?;
    let (size, count, header_end) = parse_header(&bytes).map_err(named)?;
    let expected = (header_end + 1) as u64 + 4 * count;
    let wanted = (expected + 1).saturating_sub(bytes.len() as u64);
    reader
        .take(wanted)
        .read_to_end(&mut bytes)
        .map_err(|e| cannot(e.to_string()))?;
    if bytes.len() as u64 > expected {
        return Err(named(format!(
            "the file is longer than the {count} f32 values ({} bytes) its header announces",
            4 * count
        )));
    }
    from_data(size, count, header_end, &bytes).map_err(named)
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
    fn file_round_trip() {
        let grid = ramp();
        assert_eq!(from_bytes(&to_bytes(&grid)).unwrap(), grid);
    }

    #[test]
    fn bad_files_are_reported() {
        let grid = ramp();
        let mut bytes = to_bytes(&grid);
        bytes.truncate(bytes.len() - 3);
        assert!(from_bytes(&bytes).unwrap_err().contains("found"));
        let bad = b"tyndall-grid 1 4 0 2\n";
        assert!(from_bytes(bad).unwrap_err().contains("column 18"));
        let mut negative = to_bytes(&grid);
        let at = negative.len() - 4;
        negative[at..].copy_from_slice(&(-1.0f32).to_le_bytes());
        assert!(from_bytes(&negative).unwrap_err().contains("voxel 23"));
        assert!(from_bytes(b"vdb").is_err());
    }

    /// Regression (issue 11): 2³¹·2³¹·4 wrapped to 0 voxels in u64, passed
    /// the size and length checks, and panicked indexing an empty grid.
    #[test]
    fn header_sizes_that_overflow_are_refused() {
        let header = b"tyndall-grid 1 2147483648 2147483648 4\n";
        let e = from_bytes(header).unwrap_err();
        assert!(e.contains("more than"), "{e}");
        let size = UVec3::new(1 << 31, 1 << 31, 4);
        assert!(VoxelGrid::new(size, Vec::new()).is_none());
    }
}
