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
mod accumulation;
mod checks;
mod error;
mod light_images;

pub use accumulation::{Accumulation, Kept, light_share};
pub use checks::{LOSSLESS_FOG_DEPTH, MAX_RENDER_BYTES, traces_light_paths};
pub use error::RenderError;
pub use light_images::{FOCUS_SHARE, LightImages};

use crate::aov::ComponentSum;
use crate::camera::Camera;
use crate::exact_sum::ExactRgb;
use crate::film::Image;
use crate::footprint::camera_spread_scale;
use crate::guides::{GuideSum, first_surface};
use crate::integrators::light_tracer::{self, LightPaths};
use crate::integrators::path_radiance::{Keep, Split, Whole};
use crate::integrators::{Integrator, LightSubpaths, PixelPosition};
use crate::light_groups::LightGroupSums;
use crate::region::{PixelRect, RegionError, RenderRegion};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::settings::RenderSettings;
use crate::visibility::{RayCounts, Visibility};
use glam::DVec3;
use rayon::prelude::*;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

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
    if light && (settings.components || settings.light_groups) {
        return Err(RenderError::ComponentsWithLightPaths);
    }
    let kept = Kept::by(settings, scene);
    let mut accumulation = match resume {
        None => Accumulation::new(size, region.rect, region.samples.start, light, kept),
        Some(saved) => checks::check_resume(saved, size, region, light, kept)?,
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
    let light_images = LightImages::new(scene, &camera);
    let rect = region.rect;
    let full_width = settings.width as u64;
    let counters = PassCounters::default();
    let mut passes = 0u64;
    for s in accumulation.region.samples.end..region.samples.end {
        let pass_start = Instant::now();
        let mut subpath_counts = RayCounts::default();
        let pixels = full_width * settings.height as u64;
        let light_subpaths = pool
            .install(|| LightSubpaths::for_pass(scene, settings, pixels, s, &mut subpath_counts));
        counters
            .camera_rays
            .fetch_add(subpath_counts.camera, Ordering::Relaxed);
        let integrator = Integrator::new(settings, &visibility, &light_subpaths);
        pool.install(|| {
            camera_pass(
                scene,
                settings,
                &camera,
                &light_images,
                &integrator,
                rect,
                s,
                PixelSums {
                    radiance: &mut accumulation.camera,
                    guides: accumulation.guides.as_deref_mut(),
                    components: accumulation.components.as_deref_mut(),
                    light_groups: accumulation.light_groups.as_mut(),
                },
                &counters,
                progress,
            )
        });
        if let Some(sums) = &mut accumulation.light {
            pool.install(|| light_pass(scene, settings, &camera, rect, s, sums, &counters));
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
            camera: counters.camera_rays.into_inner(),
            shadow: counters.shadow_rays.into_inner(),
            map_lookups: counters.lookups.into_inner(),
        },
        invalid_samples: counters.invalid.into_inner(),
    };
    Ok((accumulation, stats))
}

/// What the passes of a render counted, added to from worker threads.
#[derive(Default)]
struct PassCounters {
    rows_done: AtomicU64,
    camera_rays: AtomicU64,
    shadow_rays: AtomicU64,
    lookups: AtomicU64,
    invalid: AtomicU64,
}

impl PassCounters {
    /// Adds the rays and map lookups of `counts`.
    fn add(&self, counts: &RayCounts) {
        self.camera_rays.fetch_add(counts.camera, Ordering::Relaxed);
        self.shadow_rays.fetch_add(counts.shadow, Ordering::Relaxed);
        self.lookups
            .fetch_add(counts.map_lookups, Ordering::Relaxed);
    }
}

/// The per-pixel sums a camera pass adds to (row-major over its
/// rectangle): the radiance, and the guides, the components and the light
/// groups if the render keeps them.
struct PixelSums<'a> {
    radiance: &'a mut [DVec3],
    guides: Option<&'a mut [GuideSum]>,
    components: Option<&'a mut [ComponentSum]>,
    light_groups: Option<&'a mut LightGroupSums>,
}

/// `sums` (if kept) cut into rows of `width`, or a `None` per row.
fn rows_of<T>(sums: Option<&mut [T]>, width: usize, rows: u32) -> Vec<Option<&mut [T]>> {
    match sums {
        Some(sums) => sums.chunks_mut(width).map(Some).collect(),
        None => (0..rows).map(|_| None).collect(),
    }
}

/// Pass `s` of the camera paths: sample `s` of every pixel of `rect`,
/// rows in parallel on the current pool, each pixel's estimate added to
/// its sum in `sums` (non-finite estimates counted as invalid and
/// dropped), and the guides of the same camera ray to theirs.
#[allow(clippy::too_many_arguments)]
fn camera_pass(
    scene: &Scene,
    settings: &RenderSettings,
    camera: &Camera,
    light_images: &LightImages,
    integrator: &Integrator,
    rect: PixelRect,
    s: u32,
    sums: PixelSums,
    counters: &PassCounters,
    progress: &(dyn Fn(u64) + Sync),
) {
    let width = rect.width() as usize;
    let mut guide_rows = rows_of(sums.guides, width, rect.height());
    let mut component_rows = rows_of(sums.components, width, rect.height());
    let groups = sums.light_groups.as_ref().map_or(0, |g| g.groups());
    let mut group_rows = rows_of(
        sums.light_groups.map(LightGroupSums::sums_mut),
        width * groups.max(1),
        rect.height(),
    );
    let split = component_rows.first().is_some_and(Option::is_some)
        || group_rows.first().is_some_and(Option::is_some);
    let pass = CameraPass {
        scene,
        settings,
        camera,
        light_images,
        integrator,
        rect,
        s,
        cone_scale: camera_spread_scale(settings.footprint_spp.unwrap_or(settings.spp)),
    };
    sums.radiance
        .par_chunks_mut(width)
        .zip(guide_rows.par_iter_mut())
        .zip(component_rows.par_iter_mut())
        .zip(group_rows.par_iter_mut())
        .enumerate()
        .for_each(|(row, (((radiance, guides), components), light_groups))| {
            let row = RowSums {
                y: rect.y0 + row as u32,
                radiance,
                guides: guides.as_deref_mut(),
                components: components.as_deref_mut(),
                light_groups: light_groups.as_deref_mut().map(|g| (groups, g)),
            };
            // Each integrator is compiled with and without the split.
            let (counts, bad) = match split {
                true => pass.row::<Split>(row),
                false => pass.row::<Whole>(row),
            };
            counters.add(&counts);
            counters.invalid.fetch_add(bad, Ordering::Relaxed);
            progress(counters.rows_done.fetch_add(1, Ordering::Relaxed) + 1);
        });
}

/// What every row of a camera pass shares.
struct CameraPass<'a> {
    scene: &'a Scene,
    settings: &'a RenderSettings,
    camera: &'a Camera,
    /// Where pixels draw their samples around lights' images.
    light_images: &'a LightImages,
    integrator: &'a Integrator<'a>,
    rect: PixelRect,
    s: u32,
    /// The share of a pixel a camera ray's cone spreads over
    /// ([`crate::footprint::camera_spread_scale`] of the render's spp).
    cone_scale: f32,
}

/// One row's sums (see [`PixelSums`]).
struct RowSums<'a> {
    y: u32,
    radiance: &'a mut [DVec3],
    guides: Option<&'a mut [GuideSum]>,
    components: Option<&'a mut [ComponentSum]>,
    /// The number of groups and the row's sums, `groups` per pixel.
    light_groups: Option<(usize, &'a mut [DVec3])>,
}

impl CameraPass<'_> {
    /// Sample `s` of every pixel of row `sums.y`, added to its sums
    /// (the components if `K` keeps them); the rays it traced and the
    /// number of non-finite estimates it dropped.
    fn row<K: Keep>(&self, mut sums: RowSums) -> (RayCounts, u64) {
        let (scene, y) = (self.scene, sums.y);
        let full_width = self.settings.width as u64;
        let mut counts = RayCounts::default();
        let mut bad = 0u64;
        let mut images = self.light_images.row(y);
        for (i, sum) in sums.radiance.iter_mut().enumerate() {
            let x = self.rect.x0 + i as u32;
            let index = y as u64 * full_width + x as u64;
            let mut sampler = PixelSampler::new(self.settings.seed, index, self.s);
            let (film, weight) = images.sample(x, y, sampler.next_2d());
            let weight = f64::from(weight);
            let lens = self.camera.lens_sample(&mut sampler);
            let ray = self.camera.ray(film, lens);
            let cone = Some(self.camera.cone(ray.direction, self.cone_scale));
            let pixel = PixelPosition { x, y };
            let l = self
                .integrator
                .sample::<K>(scene, ray, cone, pixel, &mut sampler, &mut counts);
            if l.total().is_finite() {
                *sum += l.total().as_dvec3() * weight;
                if let (Some(sums), Some(parts)) = (sums.components.as_deref_mut(), l.components())
                {
                    for (s, c) in sums[i].iter_mut().zip(parts) {
                        *s += c.as_dvec3() * weight;
                    }
                }
                if let (Some((groups, sums)), Some(parts)) = (&mut sums.light_groups, l.groups()) {
                    let pixel = &mut sums[i * *groups..(i + 1) * *groups];
                    for (s, c) in pixel.iter_mut().zip(parts) {
                        *s += c.as_dvec3() * weight;
                    }
                }
            } else {
                bad += 1;
            }
            // Guides are the pixel's features, plain means of its
            // samples' (not weighed: docs/physics.md §5.5).
            if let Some(guides) = sums.guides.as_deref_mut() {
                guides[i].add(&first_surface(scene, ray, cone));
            }
        }
        (counts, bad)
    }
}

/// Pass `s` of the light tracer: light focused by dielectrics from point
/// and spot lights, one light path per pixel per pass (see
/// [`light_tracer`]), of which the band `rect` traces its share, splatted
/// into `sums` (the full image).
fn light_pass(
    scene: &Scene,
    settings: &RenderSettings,
    camera: &Camera,
    rect: PixelRect,
    s: u32,
    sums: &mut [ExactRgb],
    counters: &PassCounters,
) {
    let first = s as u64 * settings.width as u64 * settings.height as u64;
    let share = light_share(settings.width, rect);
    let (counts, dropped) = light_tracer::trace_paths(
        scene,
        camera,
        settings.width,
        first + share.start..first + share.end,
        settings.seed,
        settings.max_depth,
        LightPaths::Caustic,
        sums,
    );
    counters.add(&counts);
    counters.invalid.fetch_add(dropped, Ordering::Relaxed);
}
