//! Reading files with a size limit, so that a corrupt or hostile file (or
//! a device such as `/dev/zero`) is refused with a clear message instead
//! of exhausting memory. The limits are listed in docs/scene-format.md
//! ("Limits").

use std::cell::RefCell;
use std::collections::HashMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use tyndall::limits::describe_bytes;

/// Largest scene file read (native TOML or legacy .obj), in bytes.
pub const MAX_SCENE_FILE_BYTES: u64 = 64 << 20;

/// Largest mesh (.obj) file read, in bytes.
pub const MAX_MESH_FILE_BYTES: u64 = 256 << 20;

/// Largest image file read (a glTF `images[i].uri`, a spot's `gobo`), in
/// bytes.
pub const MAX_IMAGE_FILE_BYTES: u64 = 256 << 20;

/// Largest IES photometry file read, in bytes (real ones are a few
/// kilobytes; the angle counts bound the table to 2²⁰ values anyway).
pub const MAX_IES_FILE_BYTES: u64 = 16 << 20;

/// Largest grid (.tgrid) file read, in bytes: the most voxels a grid may
/// hold ([`tyndall::media::grid::MAX_VOXELS`], 4 bytes each) and its header.
/// The reader reads the header first and then no more than the voxels it
/// announces (and one byte to spot a longer file), so `/dev/zero` fails
/// after 256 bytes.
pub const MAX_GRID_FILE_BYTES: u64 = (tyndall::media::grid::MAX_VOXELS << 2) + 256;

/// Largest OpenVDB file read, in bytes (2 GiB: a cloud of 10⁹ half-float
/// voxels). The reader holds the whole file while it parses it.
pub const MAX_VDB_FILE_BYTES: u64 = 2 << 30;

/// Reads at most `limit` bytes of a file. A file that is longer (or a
/// device such as `/dev/zero` that never ends) is refused after reading
/// `limit + 1` bytes; the message says what the limit is. The error is
/// returned without the path: callers name the file.
pub fn read_capped(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let metadata = file.metadata().map_err(|e| e.to_string())?;
    if metadata.is_dir() {
        return Err("it is a directory".into());
    }
    if metadata.is_file() && metadata.len() > limit {
        return Err(too_large(metadata.len(), limit));
    }
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(format!(
            "it is longer than the {} this reader accepts (or never ends)",
            describe_bytes(limit)
        ));
    }
    Ok(bytes)
}

fn too_large(len: u64, limit: u64) -> String {
    format!(
        "it is {} long, more than the {} this reader accepts",
        describe_bytes(len),
        describe_bytes(limit)
    )
}

/// Files a scene names more than once, read once: a rig's heads share
/// their gobo image and their IES profile, which 1024 heads would
/// otherwise read, decode and hold 1024 times, and materials naming one
/// image share its texture. Keyed by the path as
/// resolved against the scene; a failed read is not kept (it fails the
/// load).
pub(crate) struct ReadOnce<T> {
    files: RefCell<HashMap<PathBuf, T>>,
}

impl<T: Clone> ReadOnce<T> {
    pub(crate) fn new() -> Self {
        Self {
            files: RefCell::new(HashMap::new()),
        }
    }

    /// What `read` made of `path` the first time, reading it now if this
    /// is the first time.
    pub(crate) fn get_or_read<E>(
        &self,
        path: &Path,
        read: impl FnOnce(&Path) -> Result<T, E>,
    ) -> Result<T, E> {
        if let Some(value) = self.files.borrow().get(path) {
            return Ok(value.clone());
        }
        let value = read(path)?;
        self.files
            .borrow_mut()
            .insert(path.to_path_buf(), value.clone());
        Ok(value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_is_read_once_and_a_failed_read_is_not_kept() {
        let cache = ReadOnce::new();
        let reads = std::cell::Cell::new(0);
        let read = |p: &Path| {
            reads.set(reads.get() + 1);
            Ok::<_, String>(p.display().to_string())
        };
        assert_eq!(cache.get_or_read(Path::new("a"), read).as_deref(), Ok("a"));
        assert_eq!(cache.get_or_read(Path::new("a"), read).as_deref(), Ok("a"));
        assert_eq!(cache.get_or_read(Path::new("b"), read).as_deref(), Ok("b"));
        assert_eq!(reads.get(), 2);
        let fail = |_: &Path| Err::<String, _>("unreadable");
        assert_eq!(cache.get_or_read(Path::new("c"), fail), Err("unreadable"));
        assert_eq!(cache.get_or_read(Path::new("c"), read).as_deref(), Ok("c"));
        assert_eq!(reads.get(), 3);
    }

    #[test]
    fn dev_zero_is_refused_quickly() {
        let path = Path::new("/dev/zero");
        if path.exists() {
            let e = read_capped(path, 1 << 20).unwrap_err();
            assert!(e.contains("never ends"), "{e}");
        }
    }
}
