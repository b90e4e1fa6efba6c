//! Voxel density grids and their file format.
//!
//! A `.tgrid` file is a one-line ASCII header followed by raw data:
//!
//! ```text
//! tyndall-grid 1 <nx> <ny> <nz>\n
//! <nx·ny·nz little-endian f32 densities, x fastest, then y, then z>
//! ```
//!
//! Densities are dimensionless, finite and non-negative; the medium's
//! `sigma_t` scales them to extinction. Values sit at voxel centres
//! (voxel `(i, j, k)` covers `[i, i+1]/nx × …` of the medium's box) and
//! are interpolated trilinearly between centres, clamped at the faces.

use glam::{IVec3, UVec3, Vec3};
use std::io::Read;
use std::path::Path;

/// Most bytes the header line may take, its newline included.
const HEADER_BYTES: u64 = 256;

/// The header's magic word and the only version this reader knows.
const MAGIC: &str = "tyndall-grid";
const VERSION: u32 = 1;

/// Most voxels a grid may hold (1 GiB of f32), so a corrupt header cannot
/// ask for absurd memory.
pub const MAX_VOXELS: u64 = 1 << 28;

/// A dense grid of densities over the unit cube.
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelGrid {
    size: UVec3,
    values: Vec<f32>,
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

    /// The file's bytes (see the module documentation).
    pub fn to_bytes(&self) -> Vec<u8> {
        let s = self.size;
        let mut bytes = format!("{MAGIC} {VERSION} {} {} {}\n", s.x, s.y, s.z).into_bytes();
        bytes.reserve(self.values.len() * 4);
        for v in &self.values {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        bytes
    }

    /// Parses a `.tgrid` file's bytes; the error says what is wrong and
    /// where (header field, or voxel index and its byte offset).
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, String> {
        let (size, count, header_end) = Self::parse_header(bytes)?;
        Self::from_data(size, count, header_end, bytes)
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
    fn from_data(size: UVec3, count: u64, header_end: usize, bytes: &[u8]) -> Result<Self, String> {
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
        Ok(Self { size, values })
    }

    /// Reads a `.tgrid` file; errors name the file.
    pub fn read(path: &Path) -> Result<Self, String> {
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
        let (size, count, header_end) = Self::parse_header(&bytes).map_err(named)?;
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
        Self::from_data(size, count, header_end, &bytes).map_err(named)
    }
}

/// `nx·ny·nz` in checked arithmetic (`None` on overflow).
fn voxel_count(size: UVec3) -> Option<u64> {
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
    fn file_round_trip() {
        let grid = ramp();
        assert_eq!(VoxelGrid::from_bytes(&grid.to_bytes()).unwrap(), grid);
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

    #[test]
    fn bad_files_are_reported() {
        let grid = ramp();
        let mut bytes = grid.to_bytes();
        bytes.truncate(bytes.len() - 3);
        assert!(VoxelGrid::from_bytes(&bytes).unwrap_err().contains("found"));
        let bad = b"tyndall-grid 1 4 0 2\n";
        assert!(
            VoxelGrid::from_bytes(bad)
                .unwrap_err()
                .contains("column 18")
        );
        let mut negative = grid.to_bytes();
        let at = negative.len() - 4;
        negative[at..].copy_from_slice(&(-1.0f32).to_le_bytes());
        assert!(
            VoxelGrid::from_bytes(&negative)
                .unwrap_err()
                .contains("voxel 23")
        );
        assert!(VoxelGrid::from_bytes(b"vdb").is_err());
    }

    /// Regression (issue 11): 2³¹·2³¹·4 wrapped to 0 voxels in u64, passed
    /// the size and length checks, and panicked indexing an empty grid.
    #[test]
    fn header_sizes_that_overflow_are_refused() {
        let header = b"tyndall-grid 1 2147483648 2147483648 4\n";
        let e = VoxelGrid::from_bytes(header).unwrap_err();
        assert!(e.contains("more than"), "{e}");
        let size = UVec3::new(1 << 31, 1 << 31, 4);
        assert!(VoxelGrid::new(size, Vec::new()).is_none());
    }
}
