//! OpenVDB float grids (`.vdb`), read with vdb-rs into Tyndall's
//! [`SparseGrid`] without densifying: each active leaf becomes a brick of
//! 8³ voxels, each active tile a constant brick (see
//! `tyndall::media::sparse`).
//!
//! What vdb-rs 0.6 cannot read is refused with an error naming the file
//! and grid, checked before reading where the reader would panic
//! (half-float grids, non-float grids, instanced grids); any other panic
//! inside the reader is caught and reported the same way. The background
//! value is taken as 0 (vdb-rs does not expose it; fog volumes use 0), and
//! active tiles at the root level (above 128³) are not read.

use glam::{IVec3, Mat4, Quat, Vec3};
use std::fs::File;
use std::io::BufReader;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use tyndall::media::sparse::SparseGrid;
use vdb_rs::{Map, VdbLevel, VdbReader};

/// The only tree configuration read: float values, OpenVDB's standard
/// 5-4-3 tree.
const FLOAT_GRID: &str = "Tree_float_5_4_3";

/// Runs `f`, turning a panic inside the reader into an error.
fn guarded<T>(f: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|panic| {
        let why = panic
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "unknown reason".into());
        Err(format!("the OpenVDB reader failed: {why}"))
    })
}

/// Reads the float grid `name` of the OpenVDB file at `path`, with its
/// index-to-world transform (voxel size and offset). Errors name the file
/// and the grid.
pub fn read_grid(path: &Path, name: &str) -> Result<SparseGrid, String> {
    let file = File::open(path).map_err(|e| format!("{}: cannot open: {e}", path.display()))?;
    let what = format!("{}: grid \"{name}\"", path.display());
    let mut reader = guarded(|| {
        VdbReader::new(BufReader::new(file))
            .map_err(|e| format!("not a readable OpenVDB file: {e}"))
    })
    .map_err(|e| format!("{}: {e}", path.display()))?;
    let Some(descriptor) = reader.grid_descriptors.get(name) else {
        let mut names = reader.available_grids();
        names.sort();
        return Err(format!(
            "{what} is not in the file; it holds {}",
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
    if descriptor.meta_data.is_half_float() || descriptor.grid_type.ends_with("_HalfFloat") {
        return Err(format!(
            "{what} is saved as half floats, which this reader cannot read; save it with full floats (pyopenvdb: grid.saveFloatAsHalf = False)"
        ));
    }
    if descriptor.grid_type != FLOAT_GRID {
        return Err(format!(
            "{what} holds {} values: only float grids ({FLOAT_GRID}) can be densities",
            descriptor.grid_type
        ));
    }
    if !descriptor.instance_parent.is_empty() {
        return Err(format!(
            "{what} is an instance of grid \"{}\", which this reader cannot read",
            descriptor.instance_parent
        ));
    }
    let grid = guarded(|| {
        reader
            .read_grid::<f32>(name)
            .map_err(|e| format!("cannot read the grid: {e}"))
    })
    .map_err(|e| format!("{what}: {e}"))?;
    // index → world: x·scale + translation (OpenVDB's ScaleTranslateMap).
    let (scale, translation) = match &grid.transform {
        Map::UniformScaleMap {
            scale_values: s, ..
        } => ([s.x, s.y, s.z], [0.0; 3]),
        Map::ScaleTranslateMap {
            scale_values: s,
            translation: t,
            ..
        } => ([s.x, s.y, s.z], [t.x, t.y, t.z]),
    };
    let to_vec3 = |v: [f64; 3]| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32);
    let index_to_world =
        Mat4::from_scale_rotation_translation(to_vec3(scale), Quat::IDENTITY, to_vec3(translation));
    if !index_to_world.is_finite() || index_to_world.determinant() == 0.0 {
        return Err(format!("{what}: the grid's transform is degenerate"));
    }
    let mut sparse = SparseGrid::new(index_to_world);
    guarded(|| {
        for (p, value, level) in grid.iter() {
            let i = IVec3::new(p.x as i32, p.y as i32, p.z as i32);
            match level {
                VdbLevel::Voxel => sparse.set_voxel(i, value),
                VdbLevel::Node3 => sparse.fill_tile(i, 8, value),
                VdbLevel::Node4 => sparse.fill_tile(i, 128, value),
            }?;
        }
        Ok(())
    })
    .map_err(|e| format!("{what}: {e}"))?;
    Ok(sparse)
}
