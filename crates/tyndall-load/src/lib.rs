//! Scene loaders for Tyndall: every file format the core keeps out.
//!
//! - the native TOML format ([`native`], docs/scene-format.md), with
//!   Wavefront .obj meshes ([`mesh`]) and `.tgrid` voxel grids
//!   ([`tgrid`]), every file read with a size limit ([`files`]);
//! - the paper's legacy .obj format ([`legacy`], docs/scene-format.md);
//! - glTF 2.0 ([`gltf`], cargo feature `gltf`) and OpenVDB grids ([`vdb`],
//!   cargo feature `vdb`), both on by default;
//! - the built-in [`demo`].
//!
//! Every loader produces a [`SceneDesc`] (plain data, each item with its
//! origin), validated, with errors placed at the file, line and column
//! ([`SceneError`]); [`tyndall::Scene::build`] makes the runtime scene.
//! [`load`] picks a loader by the file ending.

pub mod demo;
pub mod files;
#[cfg(feature = "gltf")]
pub mod gltf;
pub mod ies;
pub mod images;
pub mod legacy;
pub mod mesh;
pub mod native;
pub mod photometry;
pub mod sequence;
mod source;
pub mod tgrid;
#[cfg(feature = "vdb")]
pub mod vdb;

pub use legacy::LegacyOptions;
pub use source::{SceneError, SourceText};

use std::path::Path;
use tyndall::SceneDesc;
use tyndall::media::sparse::SparseGrid;

/// The float grid named `grid` of the OpenVDB file at `path`, with its
/// index-to-world transform; the error names the file and grid.
fn vdb_grid(path: &Path, grid: &str) -> Result<SparseGrid, String> {
    #[cfg(feature = "vdb")]
    return vdb::read_grid(path, grid);
    #[cfg(not(feature = "vdb"))]
    return Err(format!(
        "{}: grid \"{grid}\": OpenVDB needs tyndall-load's `vdb` feature",
        path.display()
    ));
}

/// Adds the geometry, materials and lights of the file at `path` (an
/// `[[include]]`), placed by `placement` after the file's own transforms,
/// to `scene`; returns the loader's warnings. Errors name the included
/// file and the element in it.
fn include(
    path: &Path,
    placement: glam::Mat4,
    scene: &mut SceneDesc,
) -> Result<Vec<String>, SceneError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        #[cfg(feature = "gltf")]
        Some("gltf" | "glb") => Ok(gltf::add_to_scene(path, placement, scene)?.warnings),
        _ => {
            let _ = (placement, scene);
            Err(SceneError {
                path: path.to_owned(),
                line: 0,
                column: 0,
                message: "only glTF files (.gltf, .glb) can be included".into(),
            })
        }
    }
}

/// How to load a scene file, beyond what the file says.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// The paper's legacy format's options.
    pub legacy: LegacyOptions,
    /// The frame of the file sequences a native scene names
    /// (`file = "fluid_data_####.vdb"`, see [`sequence`]).
    pub frame: Option<u32>,
}

impl From<LegacyOptions> for LoadOptions {
    fn from(legacy: LegacyOptions) -> Self {
        Self {
            legacy,
            frame: None,
        }
    }
}

/// Loads a scene by its file ending: `.toml` (native, its file sequences
/// at `options.frame`), `.obj` (the paper's legacy format, with
/// `options.legacy`), `.gltf`/`.glb` (glTF 2.0). A frame given for a
/// scene that names no file sequence is unused, with a warning.
pub fn load(path: &Path, options: LoadOptions) -> Result<SceneDesc, SceneError> {
    let LoadOptions { legacy, frame } = options;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let mut desc = match ext.as_deref() {
        Some("toml") => return native::load_frame(path, frame),
        _ => load_by_ending(path, ext.as_deref(), legacy)?,
    };
    if let Some(frame) = frame {
        desc.warnings.push(format!(
            "frame {frame} is unused: {} names no file sequence (only [[media]] files such as `fluid_data_####.vdb` do)",
            path.display()
        ));
    }
    Ok(desc)
}

fn load_by_ending(
    path: &Path,
    ext: Option<&str>,
    legacy: LegacyOptions,
) -> Result<SceneDesc, SceneError> {
    match ext {
        Some("toml") => native::load(path),
        Some("obj") => legacy::load(path, legacy),
        #[cfg(feature = "gltf")]
        Some("gltf" | "glb") => gltf::load(path),
        _ => Err(SceneError {
            path: path.to_owned(),
            line: 0,
            column: 0,
            message: format!(
                "unknown scene format: the file name must end in .toml (native), .obj (the paper's legacy format){}",
                if cfg!(feature = "gltf") {
                    " or .gltf/.glb (glTF 2.0)"
                } else {
                    " (glTF needs the `gltf` feature)"
                }
            ),
        }),
    }
}
