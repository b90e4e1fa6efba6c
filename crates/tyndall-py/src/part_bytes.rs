//! Render parts as bytes: the OpenEXR part files of `tyndall_image::parts`
//! (what `tyndall render --tile` writes and `tyndall merge` reads), held in
//! memory so that Python can pickle them, send them between processes
//! (Ray tasks) or save them.
//!
//! The part writer and reader work on files (the writer atomically, by
//! rename), so a part goes through a private scratch folder: written there
//! and read back as bytes, or written there from bytes and parsed. The
//! bytes are exactly the file's, so a part from Python and one from the
//! command line are interchangeable.

use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyList};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use tyndall::parts::{self, Part};
use tyndall_image::ImageFormat;
use tyndall_image::parts::{PartCompression, read_part, write_part};

/// A folder of its own under the system's temporary folder, removed with
/// everything in it when dropped.
struct ScratchDir(PathBuf);

impl ScratchDir {
    fn new() -> Result<Self, String> {
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let base = std::env::temp_dir();
        let mut last = String::new();
        // A stale folder of an earlier process with the same id is skipped.
        for _ in 0..64 {
            let n = NEXT.fetch_add(1, Ordering::Relaxed);
            let dir = base.join(format!("tyndall-py-{}-{n}", std::process::id()));
            match std::fs::create_dir(&dir) {
                Ok(()) => return Ok(Self(dir)),
                Err(e) => last = format!("{}: {e}", dir.display()),
            }
        }
        Err(format!("no scratch folder for a render part: {last}"))
    }

    fn file(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The bytes of `part`'s OpenEXR part file (run-length encoded, as
/// `tyndall render --tile` writes it).
pub fn to_bytes(part: &Part) -> Result<Vec<u8>, String> {
    let scratch = ScratchDir::new()?;
    let path = scratch.file("part.exr");
    write_part(&path, part, PartCompression::Rle).map_err(|e| e.to_string())?;
    std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))
}

/// Parses the bytes of a part file; errors name it `part {index}`.
fn from_bytes(scratch: &ScratchDir, index: usize, bytes: &[u8]) -> Result<Part, String> {
    let path = scratch.file(&format!("part-{index}.exr"));
    std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    read_part(&path).map_err(|e| {
        // Errors name the part by its place in the list, not the scratch file.
        e.to_string()
            .replace(&path.display().to_string(), &format!("part {index}"))
    })
}

/// Merges render parts, each the bytes of a part file or the path of one,
/// with the checks of `tyndall merge` ([`tyndall::parts::merge`]: same
/// scene and settings, no gaps or overlaps). Returns (little-endian f32
/// RGB bytes, height, width) of the merged image; writes the merged part
/// (.exr, mergeable again) or its image (.png) to `output` if given.
#[pyfunction]
#[pyo3(signature = (parts, output = None))]
pub fn merge_parts<'py>(
    py: Python<'py>,
    parts: &Bound<'py, PyList>,
    output: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyBytes>, u32, u32)> {
    enum Source {
        Bytes(Vec<u8>),
        File(PathBuf),
    }
    let mut sources = Vec::with_capacity(parts.len());
    for item in parts.iter() {
        sources.push(match item.cast::<PyBytes>() {
            Ok(b) => Source::Bytes(b.as_bytes().to_vec()),
            Err(_) => Source::File(item.extract::<PathBuf>().map_err(|_| {
                pyo3::exceptions::PyTypeError::new_err(format!(
                    "merge_parts: part {} is neither bytes nor a path",
                    sources.len()
                ))
            })?),
        });
    }
    let format = match &output {
        Some(path) => Some(ImageFormat::from_path(path).map_err(crate::value_error)?),
        None => None,
    };
    let merged = py.detach(|| -> Result<Part, PyErr> {
        let scratch = ScratchDir::new().map_err(crate::os_error)?;
        let mut read = Vec::with_capacity(sources.len());
        for (i, source) in sources.iter().enumerate() {
            let (name, part) = match source {
                Source::Bytes(b) => (
                    PathBuf::from(format!("part {i}")),
                    from_bytes(&scratch, i, b).map_err(crate::value_error)?,
                ),
                Source::File(p) => (p.clone(), read_part(p).map_err(crate::value_error)?),
            };
            read.push((name, part));
        }
        let merged = parts::merge(read).map_err(crate::value_error)?;
        if let (Some(path), Some(format)) = (&output, format) {
            write_merged(path, format, &merged)?;
        }
        Ok(merged)
    })?;
    let image = merged.accumulation.resolve();
    let bytes = crate::image_bytes(&image);
    Ok((PyBytes::new(py, &bytes), image.height(), image.width()))
}

/// Writes a merged part as `tyndall merge -o` does.
fn write_merged(path: &Path, format: ImageFormat, merged: &Part) -> PyResult<()> {
    match format {
        ImageFormat::Exr => write_part(path, merged, PartCompression::Rle).map_err(crate::os_error),
        ImageFormat::Png => tyndall_image::write_image(&merged.accumulation.resolve(), path, 0.0)
            .map_err(crate::os_error),
    }
}
