//! The native half of the `tyndall` Python package (`tyndall._tyndall`):
//! scenes loaded by the Rust loaders, rendered with the GIL released, images
//! handed over as raw little-endian f32 bytes that the Python half wraps in
//! NumPy arrays (so the extension needs no NumPy C API and builds as one
//! abi3 wheel for every CPython ≥ 3.9), and render parts as the bytes of
//! their OpenEXR files, merged as `tyndall merge` does.

mod part_bytes;
mod scene;

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use std::path::PathBuf;
use tyndall_load::{LegacyOptions, LoadOptions, SourceText, native};

use scene::NativeScene;

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn os_error(e: impl std::fmt::Display) -> PyErr {
    PyOSError::new_err(e.to_string())
}

/// An image as little-endian f32 RGB bytes, row by row.
fn image_bytes(image: &tyndall::Image) -> Vec<u8> {
    image
        .pixels()
        .iter()
        .flat_map(|p| p.to_array())
        .flat_map(f32::to_le_bytes)
        .collect()
}

/// Loads a scene file by its ending: native (.toml), the paper's legacy
/// format (.obj) or glTF 2.0 (.gltf, .glb); a native scene's file
/// sequences (`fluid_data_####.vdb`) at `frame`.
#[pyfunction]
#[pyo3(signature = (path, two_sided = false, frame = None))]
fn load(path: PathBuf, two_sided: bool, frame: Option<u32>) -> PyResult<NativeScene> {
    let options = LoadOptions {
        legacy: LegacyOptions { two_sided },
        frame,
    };
    let desc = tyndall_load::load(&path, options).map_err(value_error)?;
    NativeScene::new(desc)
}

/// Parses a native scene from TOML text; `path` names it in errors and
/// anchors relative paths (its folder); file sequences at `frame`;
/// `arrays`, little-endian 32-bit numbers, are the text's `"@array:K"`
/// (`native::parse_with_arrays`).
#[pyfunction]
#[pyo3(signature = (text, path, frame = None, arrays = Vec::new()))]
fn parse_toml(
    text: String,
    path: PathBuf,
    frame: Option<u32>,
    arrays: Vec<Vec<u8>>,
) -> PyResult<NativeScene> {
    let desc = native::parse_with_arrays(&SourceText::new(path, text), frame, &arrays)
        .map_err(value_error)?;
    NativeScene::new(desc)
}

/// The built-in demo scene.
#[pyfunction]
fn demo() -> PyResult<NativeScene> {
    let desc = tyndall_load::demo::load().map_err(value_error)?;
    NativeScene::new(desc)
}

/// Writes little-endian f32 RGB bytes of a `height`×`width` image to an
/// .exr (linear) or .png (sRGB, `exposure` stops) file.
#[pyfunction]
fn write_image(path: PathBuf, data: &[u8], height: u32, width: u32, exposure: f32) -> PyResult<()> {
    let n = width as usize * height as usize;
    if data.len() != n * 12 {
        return Err(value_error(format!(
            "{} bytes do not hold a {height}×{width}×3 float32 image",
            data.len()
        )));
    }
    let pixels = data
        .chunks_exact(12)
        .map(|c| {
            let f = |i: usize| f32::from_le_bytes([c[i], c[i + 1], c[i + 2], c[i + 3]]);
            tyndall::Rgb::new(f(0), f(4), f(8))
        })
        .collect();
    let image = tyndall::Image::from_pixels(width, height, pixels);
    tyndall_image::write_image(&image, &path, exposure).map_err(os_error)
}

#[pymodule]
fn _tyndall(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeScene>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(demo, m)?)?;
    m.add_function(wrap_pyfunction!(parse_toml, m)?)?;
    m.add_function(wrap_pyfunction!(write_image, m)?)?;
    m.add_function(wrap_pyfunction!(part_bytes::merge_parts, m)?)?;
    Ok(())
}
