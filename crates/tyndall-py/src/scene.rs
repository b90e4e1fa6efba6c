//! A scene on the Rust side of the Python package, and its renders: the
//! whole-or-tile image (`render`) and the render part (`render_part`) that
//! `tyndall merge` and `tyndall.merge_parts` assemble.

use crate::part_bytes;
use crate::{os_error, value_error};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::ops::ControlFlow;
use std::path::PathBuf;
use tyndall::aov::Aov;
use tyndall::parts::{Part, PartIdentity};
use tyndall::region::{PixelRect, RenderRegion};
use tyndall::render::Accumulation;
use tyndall::{IntegratorKind, RenderSettings, Scene, SceneDesc};
use tyndall_denoise::{DenoiseGuides, Denoiser};
use tyndall_load::SceneError;

/// A loaded scene: its description (with the render settings its file
/// gives) and the runtime scene built from it.
#[pyclass(frozen, module = "tyndall._tyndall")]
pub struct NativeScene {
    desc: SceneDesc,
    scene: Scene,
}

impl NativeScene {
    pub fn new(desc: SceneDesc) -> PyResult<Self> {
        let scene = Scene::build(&desc)
            .map_err(SceneError::from)
            .map_err(value_error)?;
        Ok(Self { desc, scene })
    }

    /// The scene's settings with the caller's overrides, checked, and the
    /// region (pixels and sample indices) asked for.
    #[allow(clippy::too_many_arguments)]
    fn settings_and_region(
        &self,
        spp: Option<u32>,
        integrator: Option<&str>,
        width: Option<u32>,
        height: Option<u32>,
        seed: Option<u64>,
        threads: Option<usize>,
        tile: Option<(u32, u32)>,
        samples: Option<(u32, u32)>,
    ) -> PyResult<(RenderSettings, RenderRegion)> {
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
        Ok((settings, region))
    }

    /// Renders `region` without the GIL; after each pass the GIL is taken
    /// back briefly to deliver Ctrl-C (KeyboardInterrupt) and call
    /// `progress(done, total)`, whose exception stops the render.
    fn accumulate(
        &self,
        py: Python<'_>,
        settings: &RenderSettings,
        region: &RenderRegion,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Accumulation> {
        let total = region.samples.len() as u64;
        let scene = &self.scene;
        let (result, interrupted) = py.detach(|| {
            let mut interrupted: Option<PyErr> = None;
            let result = tyndall::render::render_region(
                scene,
                settings,
                region,
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
        Ok(accumulation)
    }
}

#[pymethods]
impl NativeScene {
    /// The scene's own settings: (width, height, spp, integrator, seed).
    fn settings(&self) -> (u32, u32, u32, &'static str, u64) {
        let s = &self.desc.settings;
        (s.width, s.height, s.spp, s.integrator.name(), s.seed)
    }

    /// The scene hash (`tyndall::parts::scene_hash`) a part rendered with
    /// these settings records: the same for every tile and sample range.
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (spp, integrator, width, height, seed, threads))]
    fn scene_hash(
        &self,
        spp: Option<u32>,
        integrator: Option<&str>,
        width: Option<u32>,
        height: Option<u32>,
        seed: Option<u64>,
        threads: Option<usize>,
    ) -> PyResult<u64> {
        let (settings, _) =
            self.settings_and_region(spp, integrator, width, height, seed, threads, None, None)?;
        Ok(PartIdentity::new(&self.scene, &settings).scene_hash)
    }

    /// Renders; returns (little-endian f32 RGB bytes, height, width) of the
    /// tile, and per AOV named in `aovs` (`tyndall::guides::Aov` names)
    /// `(name, bytes, channels)`: the AOV's image as f32 RGB bytes and how
    /// many of its channels are meaningful (1 for depth, else 3). With
    /// `denoise`, the radiance is denoised by Open Image Denoise, loaded
    /// from `oidn_library` (a file or folder) or else found as
    /// `tyndall_denoise::Denoiser::find` finds it; it is loaded before the
    /// render starts. `progress(done, total)` is called after each pass,
    /// with the GIL.
    #[allow(clippy::too_many_arguments, clippy::type_complexity)]
    #[pyo3(signature = (spp, integrator, width, height, seed, threads, tile, samples, progress, aovs, denoise, oidn_library))]
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
        aovs: Vec<String>,
        denoise: bool,
        oidn_library: Option<PathBuf>,
    ) -> PyResult<(
        Bound<'py, PyBytes>,
        u32,
        u32,
        Vec<(String, Bound<'py, PyBytes>, u32)>,
    )> {
        let (mut settings, region) =
            self.settings_and_region(spp, integrator, width, height, seed, threads, tile, samples)?;
        let aovs = match aovs.is_empty() {
            true => Vec::new(),
            false => Aov::parse_list(&aovs.join(",")).map_err(value_error)?,
        };
        let denoiser = match (denoise, oidn_library) {
            (false, _) => None,
            (true, Some(path)) => {
                let path = if path.is_dir() {
                    path.join(tyndall_denoise::LIBRARY_NAME)
                } else {
                    path
                };
                Some(Denoiser::load(&path).map_err(os_error)?)
            }
            (true, None) => Some(Denoiser::find().map_err(os_error)?),
        };
        settings.guides = denoiser.is_some() || aovs.iter().any(|a| a.is_guide());
        settings.components = aovs.iter().any(|a| a.is_component());
        settings.light_groups = aovs.contains(&Aov::LightGroups);
        let accumulation = self.accumulate(py, &settings, &region, progress)?;
        let mut image = accumulation.resolve();
        let guides = accumulation.resolve_guides();
        let components = accumulation.resolve_components();
        let group_images = accumulation.resolve_light_groups();
        if let (Some(denoiser), Some(g)) = (&denoiser, &guides) {
            let guides = DenoiseGuides {
                albedo: &g.albedo,
                normal: &g.normal,
                prefilter: true,
            };
            image = py
                .detach(|| denoiser.denoise(&image, Some(guides)))
                .map_err(os_error)?;
        }
        let mut layers = Vec::with_capacity(aovs.len());
        for aov in aovs {
            if aov == Aov::LightGroups {
                // Kept by the settings above when asked for.
                let (sums, images) = accumulation
                    .light_groups
                    .as_ref()
                    .zip(group_images.as_ref())
                    .expect("the render kept what was asked for");
                for (name, image) in sums.names().iter().zip(images) {
                    let bytes = crate::image_bytes(image);
                    layers.push((Aov::light_group_layer(name), PyBytes::new(py, &bytes), 3));
                }
                continue;
            }
            let image = match aov {
                Aov::Component(c) => components.as_ref().map(|k| k.get(c)),
                guide => guides.as_ref().and_then(|g| g.get(guide)),
            };
            // Kept by the settings above whenever asked for.
            let image = image.expect("the render kept what was asked for");
            let channels = if aov == Aov::Depth { 1 } else { 3 };
            let bytes = crate::image_bytes(image);
            layers.push((aov.name().to_owned(), PyBytes::new(py, &bytes), channels));
        }
        let bytes = crate::image_bytes(&image);
        Ok((
            PyBytes::new(py, &bytes),
            image.height(),
            image.width(),
            layers,
        ))
    }

    /// Renders a part: the bytes of the OpenEXR part file that
    /// `tyndall render --tile/--samples` would write for the same
    /// arguments (exact per-pixel sums, the tile's share of the light
    /// paths, the scene hash and seed; `tyndall_image::parts`).
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (spp, integrator, width, height, seed, threads, tile, samples, progress))]
    fn render_part<'py>(
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
    ) -> PyResult<Bound<'py, PyBytes>> {
        let (mut settings, region) =
            self.settings_and_region(spp, integrator, width, height, seed, threads, tile, samples)?;
        // As `tyndall render --tile` does: a part keeps the guides and
        // (without light paths) the components, so that it can be merged
        // with any other and denoised.
        settings.guides = true;
        settings.components = !tyndall::render::traces_light_paths(&self.scene, &settings);
        settings.light_groups = settings.components && self.scene.light_groups().len() > 1;
        let accumulation = self.accumulate(py, &settings, &region, progress)?;
        let part = Part {
            identity: PartIdentity::new(&self.scene, &settings),
            accumulation,
        };
        let bytes = py
            .detach(|| part_bytes::to_bytes(&part))
            .map_err(crate::os_error)?;
        Ok(PyBytes::new(py, &bytes))
    }
}
