//! The render loop: whole passes of samples, pixels in parallel.
//!
//! A render is a sequence of passes; pass `s` computes sample `s` of every
//! pixel (rows distributed over a rayon pool of the requested size) and,
//! for `volpath` in a scene with caustics, the light paths
//! `s·W·H .. (s+1)·W·H` of [`light_tracer`]. Each pixel's sample `s` comes
//! from its own sequence (`sampler`) keyed by (seed, pixel, `s`)
//! alone, and every pixel adds its samples to f64 sums in increasing
//! order; light-path splats, which land anywhere in the image, add to exact
//! fixed-point sums ([`ExactRgb`]) that no order or grouping changes. Hence:
//! - the image is the same, bit for bit, for any thread count and
//!   scheduling;
//! - a tile ([`RenderRegion::rect`], a band of rows `y0..y1`) computes
//!   exactly the single render's camera sums for its pixels, and traces
//!   its share of each pass's light paths — in-pass indices `y0·W .. y1·W`,
//!   as many as it has pixels — whose splats it keeps for the whole image;
//!   the tiles' shares partition the paths, so merged tiles (camera sums
//!   placed, light sums added exactly) are bit-identical to the single
//!   render;
//! - a sample range ([`RenderRegion::samples`]) computes the sums of its
//!   indices; adding the sums of consecutive ranges differs from the single
//!   render only by f64 rounding;
//! - a render stopped after any pass and resumed from its sums
//!   ([`Accumulation`], a checkpoint) continues the same additions, so the
//!   final image is bit-identical to an uninterrupted render's.

use crate::camera::Camera;
use crate::color::Rgb;
use crate::exact_sum::ExactRgb;
use crate::film::Image;
use crate::integrators::light_tracer::{self, LightPaths};
use crate::integrators::march;
use crate::integrators::{Integrator, LightSubpaths, PixelPosition};
use crate::limits::describe_bytes;
use crate::media::tracking::MAX_VOLUMES;
use crate::region::{PixelRect, RegionError, RenderRegion};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::settings::{
    IntegratorKind, MAX_MARCH_STEPS, RenderSettings, SettingError, UNLIMITED_DEPTH, VisibilityMode,
};
use crate::shadow_maps;
use crate::visibility::{RayCounts, Visibility};
use glam::{DVec3, Vec2};
use rayon::prelude::*;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Most memory a render may plan for its images and maps (4 GiB): the
/// film and the image written, the light tracer's films, shadow maps.
/// Settings estimated above it are refused with the amount they need.
pub const MAX_RENDER_BYTES: u64 = 4 << 30;

/// Bytes per pixel of the film (the f64 RGB sums of [`Accumulation`]),
/// the image resolved from it (f32 RGB) and the file written from that
/// (f32 RGB for OpenEXR, less for PNG; counted at the larger).
const FILM_BYTES_PER_PIXEL: u64 = 24 + 12 + 12;

/// Bytes per texel of a shadow-map face, counted at the build's peak:
/// the rows (depth and layer count) and the face they are copied into
/// (depth and layer offset), 4 bytes each. Glass layers (16 bytes per
/// pane a texel sees) come on top.
const MAP_BYTES_PER_TEXEL: u64 = 16;

/// Most scattering events of a path when `max_depth` is unlimited and the
/// fog is endless and lossless ([`crate::media::Fog::is_endless_and_lossless`]),
/// where roulette never ends a path: such paths ran to `volpath`'s hard
/// limit of 65,536 events, and fig. 3 at 32×32, 4 spp took 36 s. With
/// this cap it takes 0.2 s. Measured on fig. 3 (albedo 1, σt = 0.1) at
/// 32×32, 64 spp, same seed, against 4096 events: the image mean is
/// 0.42 % low at 64 events, 0.17 % at 256, 0.04 % at 1024 — below the
/// noise of any render a user waits for. A warning names the cap, and
/// `max_depth` set in the scene or by `--max-depth` overrides it.
pub const LOSSLESS_FOG_DEPTH: u32 = 1024;

/// Why a render could not start.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum RenderError {
    #[error(transparent)]
    Setting(#[from] SettingError),
    #[error(
        "fog albedo {0} exceeds 1 in some channel: that is not physical, and the `{1}` integrator only accepts physical media (the `march` integrator accepts it)"
    )]
    NonPhysicalAlbedo(String, &'static str),
    #[error(
        "the scene has {0} volume(s) ([[media]]), which only the `volpath` integrator renders; `{1}` estimates homogeneous [fog] only: use --integrator volpath"
    )]
    VolumesNeedVolpath(usize, &'static str),
    #[error(
        "medium #{0} (in [[media]] order, counted from 0) emits light (`emission` or `temperature_grid`), which only the `volpath` integrator renders; `{1}` cannot: use --integrator volpath"
    )]
    EmissiveMediumNeedsVolpath(usize, &'static str),
    #[error("the scene has {0} volumes; at most {MAX_VOLUMES} are supported")]
    TooManyVolumes(usize),
    #[error(
        "march step {step} would take up to {steps:.3e} steps per ray over the longest fog segment ({length:.3e} units), each visiting {lights} light(s): at most {MAX_MARCH_STEPS} steps × lights are allowed, so use a step of at least {min_step:.3e}"
    )]
    MarchSteps {
        step: f32,
        length: f64,
        steps: f64,
        lights: usize,
        min_step: f64,
    },
    #[error(
        "the render would need about {needed} for its images and maps ({what}), more than the {limit} limit: lower the image size or the shadow-map resolution"
    )]
    Memory {
        needed: String,
        what: String,
        limit: String,
    },
    #[error("could not start the worker threads: {0}")]
    ThreadPool(String),
    #[error(transparent)]
    Region(#[from] RegionError),
    #[error("cannot resume: {0}")]
    Resume(String),
}

impl RenderSettings {
    /// Checks the settings against the scene and the chosen integrator.
    pub fn validate(&self, scene: &Scene) -> Result<(), RenderError> {
        self.check_ranges()?;
        self.check_march_steps(scene)?;
        self.check_memory(scene)?;
        if let Some(fog) = &scene.fog
            && fog.albedo.max_element() > 1.0
            && !self.integrator.accepts_non_physical_albedo()
        {
            return Err(RenderError::NonPhysicalAlbedo(
                format!("{:?}", fog.albedo.to_array()),
                self.integrator.name(),
            ));
        }
        if scene.volumes.len() > MAX_VOLUMES {
            return Err(RenderError::TooManyVolumes(scene.volumes.len()));
        }
        if self.integrator != IntegratorKind::Volpath
            && let Some(index) = scene.volumes.iter().position(|v| v.is_emissive())
        {
            return Err(RenderError::EmissiveMediumNeedsVolpath(
                index,
                self.integrator.name(),
            ));
        }
        if !scene.volumes.is_empty() && self.integrator != IntegratorKind::Volpath {
            return Err(RenderError::VolumesNeedVolpath(
                scene.volumes.len(),
                self.integrator.name(),
            ));
        }
        Ok(())
    }
}

impl RenderSettings {
    /// The most scattering events of a path (`volpath`, light tracing):
    /// `max_depth`, or [`LOSSLESS_FOG_DEPTH`] where it is unlimited and
    /// the fog would never end a path.
    pub fn path_depth(&self, scene: &Scene) -> u32 {
        let endless = scene
            .fog
            .as_ref()
            .is_some_and(|fog| fog.is_endless_and_lossless());
        if self.max_depth == UNLIMITED_DEPTH && endless {
            LOSSLESS_FOG_DEPTH
        } else {
            self.max_depth
        }
    }

    /// The longest fog segment a `march` ray may cover: the fog box's
    /// diagonal, or the distance to optical depth
    /// [`march::MAX_OPTICAL_DEPTH`] where the march stops, whichever is
    /// shorter; `None` if the march has nothing to do.
    fn longest_march(scene: &Scene) -> Option<f64> {
        let fog = scene.fog.as_ref()?;
        if fog.sigma_t <= 0.0 || fog.sigma_s() == Rgb::ZERO || scene.lights.is_empty() {
            return None;
        }
        let to_depth = march::MAX_OPTICAL_DEPTH as f64 / fog.sigma_t as f64;
        let diagonal = fog
            .bounds
            .map_or(f64::INFINITY, |b| b.extent().as_dvec3().length());
        Some(to_depth.min(diagonal))
    }

    /// Refuses a `march` step that would take more than
    /// [`MAX_MARCH_STEPS`] steps on some ray (issue 11: a step of 3e-7
    /// never finished; 1e-45 silently rendered no fog).
    fn check_march_steps(&self, scene: &Scene) -> Result<(), RenderError> {
        if self.integrator != IntegratorKind::March {
            return Ok(());
        }
        let Some(length) = Self::longest_march(scene) else {
            return Ok(());
        };
        let steps = length / self.step as f64;
        let lights = scene.lights.len();
        let budget = MAX_MARCH_STEPS as f64 / lights as f64;
        if steps > budget {
            return Err(RenderError::MarchSteps {
                step: self.step,
                length,
                steps,
                lights,
                min_step: length / budget,
            });
        }
        Ok(())
    }

    /// Estimated bytes of the images and maps this render allocates, with
    /// a description of the parts (for the error message).
    pub fn memory_estimate(&self, scene: &Scene) -> (u64, String) {
        let pixels = self.width as u64 * self.height as u64;
        let mut total = pixels.saturating_mul(FILM_BYTES_PER_PIXEL);
        let mut parts = vec![format!(
            "{}×{} film and image: {}",
            self.width,
            self.height,
            describe_bytes(total)
        )];
        if traces_light_paths(scene, self) {
            // The light paths' exact fixed-point sums, for the full image.
            let film = pixels.saturating_mul(std::mem::size_of::<ExactRgb>() as u64);
            total = total.saturating_add(film);
            parts.push(format!("light-path sums: {}", describe_bytes(film)));
        }
        if let VisibilityMode::Maps { resolution } = self.visibility {
            let faces: u64 = scene.lights.iter().map(shadow_maps::face_count).sum();
            let texels = (resolution as u64).pow(2);
            let maps = faces
                .saturating_mul(texels)
                .saturating_mul(MAP_BYTES_PER_TEXEL);
            total = total.saturating_add(maps);
            parts.push(format!(
                "{faces} shadow-map faces of {resolution}² texels: {}",
                describe_bytes(maps)
            ));
        }
        (total, parts.join(", "))
    }

    /// Refuses a render whose [`RenderSettings::memory_estimate`] is above
    /// [`MAX_RENDER_BYTES`].
    fn check_memory(&self, scene: &Scene) -> Result<(), RenderError> {
        let (needed, what) = self.memory_estimate(scene);
        if needed > MAX_RENDER_BYTES {
            return Err(RenderError::Memory {
                needed: describe_bytes(needed),
                what,
                limit: describe_bytes(MAX_RENDER_BYTES),
            });
        }
        Ok(())
    }

    /// The worker threads to start: the requested count, capped at the
    /// machine's available parallelism (more threads only cost memory;
    /// `--threads 100000` exhausted the PID space). `None`: every core.
    pub fn worker_threads(&self) -> Option<usize> {
        self.threads.map(|n| n.min(available_parallelism()))
    }

    /// Things about to be rendered that are allowed but worth a warning:
    /// non-physical fog albedo under `march` (the paper's figures), more
    /// threads than the machine runs at once.
    pub fn warnings(&self, scene: &Scene) -> Vec<String> {
        let mut warnings = Vec::new();
        if let Some(n) = self.threads
            && n > available_parallelism()
        {
            warnings.push(format!(
                "{n} threads requested; this machine runs {} at once, so {} are used",
                available_parallelism(),
                available_parallelism()
            ));
        }
        if let Some(fog) = &scene.fog
            && fog.albedo.max_element() > 1.0
            && self.integrator.accepts_non_physical_albedo()
        {
            warnings.push(format!(
                "fog albedo {:?} is above 1, which is not physical; `{}` renders it anyway, as the paper did",
                fog.albedo.to_array(),
                self.integrator.name()
            ));
        }
        if self.integrator == IntegratorKind::Volpath && self.path_depth(scene) != self.max_depth {
            warnings.push(format!(
                "the fog fills all space and absorbs nothing (albedo 1), so no path would end: `volpath` stops each path after {LOSSLESS_FOG_DEPTH} scattering events (max_depth = {LOSSLESS_FOG_DEPTH}; the light beyond is about 0.04 % of the image); set max_depth (--max-depth) to choose another limit"
            ));
        }
        warnings
    }
}

/// Threads the machine can run at once (1 if unknown).
fn available_parallelism() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// What a render did, for the end-of-run report.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Wall time of the whole render, shadow maps included.
    pub elapsed: Duration,
    /// Wall time spent rendering shadow maps (zero with shadow rays).
    pub maps: Duration,
    pub samples: u64,
    pub rays: RayCounts,
    /// Samples whose radiance was NaN or infinite and were dropped, camera
    /// samples and light-path connections alike (a bug if ever non-zero;
    /// reported, never hidden).
    pub invalid_samples: u64,
}

impl RenderStats {
    /// Rays (camera and shadow) per second of wall time.
    pub fn rays_per_second(&self) -> f64 {
        self.rays.total() as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }
}

/// A finished render.
pub struct Render {
    pub image: Image,
    pub stats: RenderStats,
}

/// The unnormalised per-pixel sums of a part of a render: what a tile, a
/// sample range or a checkpoint holds. [`Accumulation::resolve`] turns it
/// into an image.
#[derive(Clone, Debug, PartialEq)]
pub struct Accumulation {
    /// Width of the full image, in pixels.
    pub width: u32,
    /// Height of the full image, in pixels.
    pub height: u32,
    /// The pixels held, and the sample indices summed so far.
    pub region: RenderRegion,
    /// Per pixel of `region.rect` (row-major), the sum of the camera-path
    /// radiance estimates of samples `region.samples` (non-finite
    /// estimates count as zero and are reported in [`RenderStats`]).
    pub camera: Vec<DVec3>,
    /// Per pixel of the *full* image (row-major), the exact sum of the
    /// light-path splats (radiance times the number of paths) of this
    /// part's share of each pass's light paths (see the module docs), for
    /// renders that trace them (`volpath` with caustics); `None` otherwise.
    pub light: Option<Vec<ExactRgb>>,
}

impl Accumulation {
    /// No samples yet of `rect`, starting at sample index `first_sample`.
    pub fn new(
        (width, height): (u32, u32),
        rect: PixelRect,
        first_sample: u32,
        light: bool,
    ) -> Self {
        Self {
            width,
            height,
            region: RenderRegion {
                rect,
                samples: first_sample..first_sample,
            },
            camera: vec![DVec3::ZERO; rect.area()],
            light: light.then(|| vec![ExactRgb::ZERO; width as usize * height as usize]),
        }
    }

    /// Samples per pixel summed.
    pub fn passes(&self) -> u32 {
        self.region.samples.len() as u32
    }

    /// This part's light paths per pass: one per pixel of its rows.
    pub fn light_paths_per_pass(&self) -> u64 {
        let share = light_share(self.width, self.region.rect);
        share.end - share.start
    }

    /// The image of the rectangle: each pixel the mean of its camera
    /// samples plus its light splats over the light paths this part traced
    /// (for a tile, an estimate from its share of the paths; for the whole
    /// image, the render); black before the first pass.
    pub fn resolve(&self) -> Image {
        let n = self.passes();
        let rect = self.region.rect;
        if n == 0 {
            return Image::from_pixels(rect.width(), rect.height(), vec![Rgb::ZERO; rect.area()]);
        }
        let light_scale = 1.0 / (self.light_paths_per_pass() as f64 * n as f64);
        let width = rect.width() as usize;
        let pixels = self
            .camera
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let mut p = (*c / n as f64).as_vec3();
                if let Some(light) = &self.light {
                    let (x, y) = (rect.x0 as usize + i % width, rect.y0 as usize + i / width);
                    let full = y * self.width as usize + x;
                    p += (light[full].to_dvec3() * light_scale).as_vec3();
                }
                p
            })
            .collect();
        Image::from_pixels(rect.width(), rect.height(), pixels)
    }

    /// Adds the sums of `next`, the same pixels for the sample indices
    /// that follow this one's.
    pub fn append(&mut self, next: &Accumulation) -> Result<(), String> {
        if (self.width, self.height) != (next.width, next.height)
            || self.region.rect != next.region.rect
            || self.light.is_some() != next.light.is_some()
        {
            return Err("the parts hold different images or pixels".into());
        }
        if next.region.samples.start != self.region.samples.end {
            return Err(format!(
                "samples {:?} do not follow samples {:?}",
                next.region.samples, self.region.samples
            ));
        }
        for (a, b) in self.camera.iter_mut().zip(&next.camera) {
            *a += *b;
        }
        if let (Some(a), Some(b)) = (&mut self.light, &next.light) {
            for (a, b) in a.iter_mut().zip(b) {
                a.add_exact(b);
            }
        }
        self.region.samples.end = next.region.samples.end;
        Ok(())
    }
}

/// The in-pass indices of the light paths that a band of whole rows
/// (`rect`, in an image `width` wide) traces: one per pixel of its rows,
/// `y0·W .. y1·W`. Bands that partition the image partition the paths.
pub fn light_share(width: u32, rect: PixelRect) -> std::ops::Range<u64> {
    rect.y0 as u64 * width as u64..rect.y1 as u64 * width as u64
}

/// Renders `scene`. `progress` is called with the number of rows finished
/// so far, counting each row once per pass (from worker threads, in no
/// particular order; `height·spp` in all).
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Render, RenderError> {
    let region = RenderRegion::full(settings.width, settings.height, settings.spp);
    let (accumulation, stats) =
        render_region(scene, settings, &region, None, progress, &mut |_, _| {
            ControlFlow::Continue(())
        })?;
    Ok(Render {
        image: accumulation.resolve(),
        stats,
    })
}

/// Whether a render of `scene` with `settings` traces light paths (and so
/// has [`Accumulation::light`] sums).
pub fn traces_light_paths(scene: &Scene, settings: &RenderSettings) -> bool {
    settings.integrator == IntegratorKind::Volpath && light_tracer::has_caustics(scene)
}

/// Renders the passes `region.samples` of the pixels `region.rect` (its
/// `settings.spp` is not used), continuing `resume` if given (the sums of
/// the passes `region.samples.start .. resume.region.samples.end`, from a
/// checkpoint). After each pass, `after_pass` gets the sums so far and the
/// pass's wall time; it may write a checkpoint, or stop the render after
/// that pass by returning `Break` (a time limit). `progress` counts rows
/// finished, each once per pass, this run's passes only.
pub fn render_region(
    scene: &Scene,
    settings: &RenderSettings,
    region: &RenderRegion,
    resume: Option<Accumulation>,
    progress: &(dyn Fn(u64) + Sync),
    after_pass: &mut dyn FnMut(&Accumulation, Duration) -> ControlFlow<()>,
) -> Result<(Accumulation, RenderStats), RenderError> {
    settings.validate(scene)?;
    region.check(settings.width, settings.height)?;
    // An unlimited depth in endless lossless fog is bounded here, once,
    // for every integrator and pass (see `path_depth`).
    let settings = &RenderSettings {
        max_depth: settings.path_depth(scene),
        ..*settings
    };
    let size = (settings.width, settings.height);
    let light = traces_light_paths(scene, settings);
    if light && (region.rect.x0, region.rect.x1) != (0, settings.width) {
        return Err(RenderError::Region(RegionError::NotBand(region.rect)));
    }
    let mut accumulation = match resume {
        None => Accumulation::new(size, region.rect, region.samples.start, light),
        Some(a) => {
            let fits = (a.width, a.height) == size
                && a.region.rect == region.rect
                && a.region.samples.start == region.samples.start
                && a.region.samples.end <= region.samples.end
                && a.light.is_some() == light
                && a.camera.len() == region.rect.area()
                && a.light
                    .as_ref()
                    .is_none_or(|l| l.len() == size.0 as usize * size.1 as usize);
            if !fits {
                return Err(RenderError::Resume(format!(
                    "the saved progress holds samples {:?} of pixels {} of a {}×{} image{}, which is not a start of samples {:?} of pixels {} of this {}×{} render{}",
                    a.region.samples,
                    a.region.rect,
                    a.width,
                    a.height,
                    if a.light.is_some() {
                        " with light paths"
                    } else {
                        ""
                    },
                    region.samples,
                    region.rect,
                    size.0,
                    size.1,
                    if light { " with light paths" } else { "" },
                )));
            }
            a
        }
    };
    let pool = {
        let mut builder = rayon::ThreadPoolBuilder::new();
        if let Some(n) = settings.worker_threads() {
            builder = builder.num_threads(n);
        }
        builder
            .build()
            .map_err(|e| RenderError::ThreadPool(e.to_string()))?
    };
    let start = Instant::now();
    let visibility = pool.install(|| Visibility::new(scene, settings.visibility));
    let maps = start.elapsed();
    let camera = Camera::new(&scene.camera, settings.width, settings.height);
    let rect = region.rect;
    let full_width = settings.width as u64;
    let rows_done = AtomicU64::new(0);
    let (camera_rays, shadow_rays, lookups, invalid) = (
        AtomicU64::new(0),
        AtomicU64::new(0),
        AtomicU64::new(0),
        AtomicU64::new(0),
    );
    let mut passes = 0u64;
    for s in accumulation.region.samples.end..region.samples.end {
        let pass_start = Instant::now();
        let mut subpath_counts = RayCounts::default();
        let pixels = full_width * settings.height as u64;
        let light_subpaths = pool
            .install(|| LightSubpaths::for_pass(scene, settings, pixels, s, &mut subpath_counts));
        camera_rays.fetch_add(subpath_counts.camera, Ordering::Relaxed);
        let integrator = Integrator::new(settings, &visibility, &light_subpaths);
        pool.install(|| {
            accumulation
                .camera
                .par_chunks_mut(rect.width() as usize)
                .enumerate()
                .for_each(|(row, sums)| {
                    let y = rect.y0 + row as u32;
                    let mut counts = RayCounts::default();
                    let mut bad = 0u64;
                    for (i, sum) in sums.iter_mut().enumerate() {
                        let x = rect.x0 + i as u32;
                        let index = y as u64 * full_width + x as u64;
                        let mut sampler = PixelSampler::new(settings.seed, index, s);
                        let film = Vec2::new(x as f32, y as f32) + sampler.next_2d();
                        let ray = camera.ray(film);
                        let pixel = PixelPosition { x, y };
                        let l = integrator.radiance(scene, ray, pixel, &mut sampler, &mut counts);
                        if l.is_finite() {
                            *sum += l.as_dvec3();
                        } else {
                            bad += 1;
                        }
                    }
                    camera_rays.fetch_add(counts.camera, Ordering::Relaxed);
                    shadow_rays.fetch_add(counts.shadow, Ordering::Relaxed);
                    lookups.fetch_add(counts.map_lookups, Ordering::Relaxed);
                    invalid.fetch_add(bad, Ordering::Relaxed);
                    progress(rows_done.fetch_add(1, Ordering::Relaxed) + 1);
                });
        });
        if let Some(sums) = &mut accumulation.light {
            // Light focused by dielectrics from point and spot lights:
            // one light path per pixel per pass (see `light_tracer`); a
            // tile traces its share.
            let first = s as u64 * full_width * settings.height as u64;
            let share = light_share(settings.width, rect);
            let (counts, dropped) = pool.install(|| {
                light_tracer::trace_paths(
                    scene,
                    &camera,
                    settings.width,
                    first + share.start..first + share.end,
                    settings.seed,
                    settings.max_depth,
                    LightPaths::Caustic,
                    sums,
                )
            });
            camera_rays.fetch_add(counts.camera, Ordering::Relaxed);
            shadow_rays.fetch_add(counts.shadow, Ordering::Relaxed);
            invalid.fetch_add(dropped, Ordering::Relaxed);
        }
        accumulation.region.samples.end = s + 1;
        passes += 1;
        if after_pass(&accumulation, pass_start.elapsed()).is_break() {
            break;
        }
    }
    let stats = RenderStats {
        elapsed: start.elapsed(),
        maps,
        samples: rect.area() as u64 * passes,
        rays: RayCounts {
            camera: camera_rays.into_inner(),
            shadow: shadow_rays.into_inner(),
            map_lookups: lookups.into_inner(),
        },
        invalid_samples: invalid.into_inner(),
    };
    Ok((accumulation, stats))
}
