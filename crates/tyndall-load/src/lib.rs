//! Scene loaders for Tyndall that need file-format crates the core keeps
//! out: glTF 2.0 (cargo feature `gltf`) and OpenVDB grids (cargo feature
//! `vdb`), both on by default.
//!
//! Every loader produces the same [`SceneDescription`] the core's native
//! TOML and legacy .obj loaders produce; [`load`] picks one by the file
//! ending.

#[cfg(feature = "gltf")]
pub mod gltf;
pub mod photometry;
#[cfg(feature = "vdb")]
pub mod vdb;

use std::path::Path;
use tyndall::media::sparse::SparseGrid;
use tyndall::scene::legacy::{self, LegacyOptions};
use tyndall::scene::native::ExternalFormats;
use tyndall::scene::{SceneBuilder, SceneDescription, SceneError, native};

/// The formats a native scene may name: glTF (`.gltf`, `.glb`) in
/// `[[include]]` with the `gltf` feature, OpenVDB grids as `[[media]]`
/// densities with the `vdb` feature.
pub struct Formats;

impl ExternalFormats for Formats {
    fn vdb_grid(&self, path: &Path, grid: &str) -> Result<SparseGrid, String> {
        #[cfg(feature = "vdb")]
        return vdb::read_grid(path, grid);
        #[cfg(not(feature = "vdb"))]
        return Err(format!(
            "{}: grid \"{grid}\": OpenVDB needs tyndall-load's `vdb` feature",
            path.display()
        ));
    }

    fn include(
        &self,
        path: &Path,
        placement: glam::Mat4,
        builder: &mut SceneBuilder,
    ) -> Result<Vec<String>, SceneError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            #[cfg(feature = "gltf")]
            Some("gltf" | "glb") => Ok(gltf::add_to_scene(path, placement, builder)?.warnings),
            _ => {
                let _ = (placement, builder);
                Err(SceneError {
                    path: path.to_owned(),
                    line: 0,
                    column: 0,
                    message: "only glTF files (.gltf, .glb) can be included".into(),
                })
            }
        }
    }
}

/// Loads a scene by its file ending: `.toml` (native), `.obj` (the
/// paper's legacy format, with `legacy` options), `.gltf`/`.glb` (glTF 2.0).
pub fn load(path: &Path, legacy: LegacyOptions) -> Result<SceneDescription, SceneError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("toml") => native::load_with(path, &Formats),
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
