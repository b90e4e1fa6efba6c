//! Writing an image file so that it appears complete or not at all.

use crate::format::{AovLayer, ImageError, ImageFormat, encode};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use tyndall::Image;

/// Writes `image` in the format its path's ending names; `exposure`
/// (stops) applies to PNG only. The file appears complete or not at all
/// (see [`OutputFile`]).
pub fn write_image(image: &Image, path: &Path, exposure: f32) -> Result<(), ImageError> {
    OutputFile::create(path)?.finish(image, exposure)
}

/// An image file being written: a temporary file beside the target,
/// created up front (so an unwritable destination is found before a
/// render), then written, flushed, synced to disk and renamed onto the
/// target. Until [`OutputFile::finish`] succeeds the target is untouched;
/// dropped unfinished, the temporary file is removed.
pub struct OutputFile {
    target: PathBuf,
    temp: PathBuf,
    format: ImageFormat,
    file: Option<File>,
}

impl OutputFile {
    /// Checks the format and creates the temporary file
    /// (`.<name>.<pid>.tmp` in the target's directory).
    pub fn create(target: &Path) -> Result<Self, ImageError> {
        let format = ImageFormat::from_path(target)?;
        let io = |message: String| ImageError::Io {
            path: target.to_owned(),
            message,
        };
        let name = target
            .file_name()
            .ok_or_else(|| io("the output path names no file".into()))?;
        if target.is_dir() {
            return Err(io("the output path is a directory".into()));
        }
        let mut temp_name = std::ffi::OsString::from(".");
        temp_name.push(name);
        temp_name.push(format!(".{}.tmp", std::process::id()));
        let temp = target.with_file_name(temp_name);
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp)
            .map_err(|e| io(format!("cannot create the output file: {e}")))?;
        Ok(Self {
            target: target.to_owned(),
            temp,
            format,
            file: Some(file),
        })
    }

    /// The file the image will be written to.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Encodes `image`, flushes and syncs the temporary file and renames
    /// it onto the target. Any failure (a full disk, a size limit) is an
    /// error and leaves the target as it was.
    pub fn finish(self, image: &Image, exposure: f32) -> Result<(), ImageError> {
        self.finish_with_aovs(image, &[], exposure)
    }

    /// As [`OutputFile::finish`], with the layers `aovs` beside the image
    /// (OpenEXR only; an error for PNG, before anything is written).
    pub fn finish_with_aovs(
        mut self,
        image: &Image,
        aovs: &[AovLayer],
        exposure: f32,
    ) -> Result<(), ImageError> {
        let io = |message: String| ImageError::Io {
            path: self.target.clone(),
            message,
        };
        let file = self.file.take().expect("an unfinished output has its file");
        let mut out = BufWriter::new(file);
        encode(image, aovs, self.format, exposure, &mut out)
            .map_err(|e| io(format!("cannot write the image: {e}")))?;
        let file = out
            .into_inner()
            .map_err(|e| io(format!("cannot write the image: {}", e.error())))?;
        file.sync_all()
            .map_err(|e| io(format!("cannot write the image to disk: {e}")))?;
        drop(file);
        std::fs::rename(&self.temp, &self.target)
            .map_err(|e| io(format!("cannot move the finished image into place: {e}")))?;
        self.temp = PathBuf::new();
        Ok(())
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        if !self.temp.as_os_str().is_empty() {
            self.file.take();
            let _ = std::fs::remove_file(&self.temp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::format::read_exr;
    use tyndall::Rgb;

    #[test]
    fn output_appears_whole_and_leaves_no_temporary_file() {
        let dir = std::env::temp_dir().join(format!("tyndall-film-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let image = Image::from_pixels(2, 1, vec![Rgb::new(0.5, 0.25, 1.0); 2]);
        for name in ["a.png", "a.exr"] {
            let target = dir.join(name);
            let out = OutputFile::create(&target).unwrap();
            assert!(!target.exists(), "the target appears only when finished");
            out.finish(&image, 0.0).unwrap();
            assert!(target.exists());
        }
        let back = read_exr(&dir.join("a.exr")).unwrap();
        assert_eq!(back, image);
        // An abandoned output leaves nothing behind.
        drop(OutputFile::create(&dir.join("b.png")).unwrap());
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
