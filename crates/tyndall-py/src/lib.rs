//! The native half of the `tyndall` Python package (`tyndall._tyndall`):
//! scenes loaded by the Rust loaders, rendered with the GIL released, images
//! handed over as raw little-endian f32 bytes that the Python half wraps in
//! NumPy arrays (so the extension needs no NumPy C API and builds as one
//! abi3 wheel for every CPython ≥ 3.9).

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use tyndall::region::{PixelRect, RenderRegion};
use tyndall::{IntegratorKind, Scene, SceneDesc};
use tyndall_load::{LegacyOptions, SceneError, SourceText, native};

/// A loaded scene: its description (with the render settings its file
/// gives) and the runtime scene built from it.
#[pyclass(frozen, module = "tyndall._tyndall")]
struct NativeScene {
    desc: SceneDesc,
    scene: Scene,
}

impl NativeScene {
    fn new(desc: SceneDesc) -> PyResult<Self> {
        let scene = Scene::build(&desc)
            .map_err(SceneError::from)
            .map_err(value_error)?;
        Ok(Self { desc, scene })
    }
}

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Loads a scene file by its ending: native (.toml), the paper's legacy
/// format (.obj) or glTF 2.0 (.gltf, .glb).
#[pyfunction]
#[pyo3(signature = (path, two_sided = false))]
fn load(path: PathBuf, two_sided: bool) -> PyResult<NativeScene> {
    let desc = tyndall_load::load(&path, LegacyOptions { two_sided }).map_err(value_error)?;
    NativeScene::new(desc)
}

/// Parses a native scene from TOML text; `path` names it in errors and
/// anchors relative paths (its folder).
#[pyfunction]
fn parse_toml(text: String, path: PathBuf) -> PyResult<NativeScene> {
    let desc = native::parse(&SourceText::new(path, text)).map_err(value_error)?;
    NativeScene::new(desc)
}

/// The built-in demo scene.
#[pyfunction]
fn demo() -> PyResult<NativeScene> {
    let desc = tyndall_load::demo::load().map_err(value_error)?;
    NativeScene::new(desc)
}

#[pymethods]
impl NativeScene {
    /// The scene's own settings: (width, height, spp, integrator, seed).
    fn settings(&self) -> (u32, u32, u32, &'static str, u64) {
        let s = &self.desc.settings;
        (s.width, s.height, s.spp, s.integrator.name(), s.seed)
    }

    /// Renders; returns (little-endian f32 RGB bytes, height, width) of the
    /// tile. `progress(done, total)` is called after each pass, with the GIL.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (spp, integrator, width, height, seed, threads, tile, samples, progress))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        spp: Option<u32>,
        integrator: Option<&str>,
        width: Option<u32>,
        height: Option<u32>,
        seed: Option<u64>,
        threads: Option<usize>,
        tile: Option<(u32, u32)>,
        samples: Option<(u32, u32)>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<(Bound<'py, PyBytes>, u32, u32)> {
        let mut settings = self.desc.settings;
        if let Some(v) = spp {
            settings.spp = v;
        }
        if let Some(name) = integrator {
            settings.integrator = IntegratorKind::from_name(name).ok_or_else(|| {
                value_error(format!(
                    "unknown integrator `{name}`: expected `march`, `single` or `volpath`"
                ))
            })?;
        }
        if let Some(v) = width {
            settings.width = v;
        }
        if let Some(v) = height {
            settings.height = v;
        }
        if let Some(v) = seed {
            settings.seed = v;
        }
        if threads.is_some() {
            settings.threads = threads;
        }
        settings.validate(&self.scene).map_err(value_error)?;
        let rect = match tile {
            Some((i, n)) => {
                PixelRect::tile(i, n, settings.width, settings.height).map_err(value_error)?
            }
            None => PixelRect::full(settings.width, settings.height),
        };
        let samples = match samples {
            Some((a, b)) => a..b,
            None => 0..settings.spp,
        };
        let region = RenderRegion { rect, samples };
        region
            .check(settings.width, settings.height)
            .map_err(value_error)?;
        let total = region.samples.len() as u64;
        let scene = &self.scene;
        // Rendering runs without the GIL; after each pass it is taken back
        // briefly to deliver Ctrl-C (KeyboardInterrupt) and progress.
        let (result, interrupted) = py.detach(|| {
            let mut interrupted: Option<PyErr> = None;
            let result = tyndall::render::render_region(
                scene,
                &settings,
                &region,
                None,
                &|_| {},
                &mut |a, _| {
                    Python::attach(|py| {
                        let step = py.check_signals().and_then(|()| match &progress {
                            Some(cb) => cb.call1(py, (a.passes() as u64, total)).map(|_| ()),
                            None => Ok(()),
                        });
                        match step {
                            Ok(()) => ControlFlow::Continue(()),
                            Err(e) => {
                                interrupted = Some(e);
                                ControlFlow::Break(())
                            }
                        }
                    })
                },
            );
            (result, interrupted)
        });
        if let Some(e) = interrupted {
            return Err(e);
        }
        let (accumulation, _) = result.map_err(value_error)?;
        let image = accumulation.resolve();
        let bytes: Vec<u8> = image
            .pixels()
            .iter()
            .flat_map(|p| p.to_array())
            .flat_map(f32::to_le_bytes)
            .collect();
        Ok((PyBytes::new(py, &bytes), image.height(), image.width()))
    }
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
    write(&image, &path, exposure)
}

fn write(image: &tyndall::Image, path: &Path, exposure: f32) -> PyResult<()> {
    tyndall_image::write_image(image, path, exposure).map_err(|e| PyOSError::new_err(e.to_string()))
}

#[pymodule]
fn _tyndall(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeScene>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(demo, m)?)?;
    m.add_function(wrap_pyfunction!(parse_toml, m)?)?;
    m.add_function(wrap_pyfunction!(write_image, m)?)?;
    Ok(())
}
