//! The render settings checked against the scene before a render starts:
//! march steps, memory, the integrator and the media; the depth bound of
//! endless lossless fog; the warnings of a render; and whether saved
//! progress (a checkpoint) is a start of the render asked for.

use super::accumulation::{Accumulation, Kept};
use super::error::RenderError;
use crate::color::Rgb;
use crate::exact_sum::ExactRgb;
use crate::integrators::{light_tracer, march};
use crate::limits::describe_bytes;
use crate::media::tracking::MAX_VOLUMES;
use crate::region::RenderRegion;
use crate::scene::Scene;
use crate::settings::{
    IntegratorKind, MAX_MARCH_STEPS, RenderSettings, UNLIMITED_DEPTH, VisibilityMode,
};
use crate::shadow_maps;
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
/// 0.42 % low at 64 events, 0.17 % at 256, 0.04 % at 1024. That is a
/// comparison with a longer Tyndall render only: the light cut past 4096
/// events is not measured, and no peer renders endless lossless fog for
/// a reference. A warning names the cap, and
/// `max_depth` set in the scene or by `--max-depth` overrides it.
pub const LOSSLESS_FOG_DEPTH: u32 = 1024;

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
        if scene.has_coverage() && matches!(self.visibility, VisibilityMode::Maps { .. }) {
            return Err(RenderError::CoverageNeedsShadowRays);
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
        // The AOVs' sums, and (at most) the images resolved from them.
        let aov_bytes = |sum: usize, images: u64| {
            pixels.saturating_mul(sum as u64 + images * std::mem::size_of::<crate::Rgb>() as u64)
        };
        if self.guides {
            let guides = aov_bytes(std::mem::size_of::<crate::guides::GuideSum>(), 4);
            total = total.saturating_add(guides);
            parts.push(format!("first-surface guides: {}", describe_bytes(guides)));
        }
        if self.components {
            let components = aov_bytes(std::mem::size_of::<crate::aov::ComponentSum>(), 4);
            total = total.saturating_add(components);
            parts.push(format!(
                "radiance components: {}",
                describe_bytes(components)
            ));
        }
        if self.light_groups {
            let groups = scene.light_groups().len();
            let sums = aov_bytes(groups * std::mem::size_of::<glam::DVec3>(), groups as u64);
            total = total.saturating_add(sums);
            parts.push(format!("{groups} light groups: {}", describe_bytes(sums)));
        }
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
                "the fog fills all space and absorbs nothing (albedo 1), so no path would end: `volpath` stops each path after {LOSSLESS_FOG_DEPTH} scattering events (max_depth = {LOSSLESS_FOG_DEPTH}; on the paper's fig. 3 the light beyond it is 0.04 % of the image); set max_depth (--max-depth) to choose another limit"
            ));
        }
        warnings
    }
}

/// Threads the machine can run at once (1 if unknown).
fn available_parallelism() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Whether a render of `scene` with `settings` traces light paths (and so
/// has [`Accumulation::light`] sums).
pub fn traces_light_paths(scene: &Scene, settings: &RenderSettings) -> bool {
    settings.integrator == IntegratorKind::Volpath && light_tracer::has_caustics(scene)
}

/// Checks that `saved` (from a checkpoint) is a start of the passes
/// `region.samples` of the pixels `region.rect` of an image of `size`,
/// with light-path sums exactly when `light`; returns it to continue.
pub(super) fn check_resume(
    saved: Accumulation,
    size: (u32, u32),
    region: &RenderRegion,
    light: bool,
    kept: Kept,
) -> Result<Accumulation, RenderError> {
    let a = saved;
    let fits = (a.width, a.height) == size
        && a.region.rect == region.rect
        && a.region.samples.start == region.samples.start
        && a.region.samples.end <= region.samples.end
        && a.light.is_some() == light
        && a.kept() == kept
        && a.camera.len() == region.rect.area()
        && a.guides
            .as_ref()
            .is_none_or(|g| g.len() == region.rect.area())
        && a.components
            .as_ref()
            .is_none_or(|c| c.len() == region.rect.area())
        && a.light_groups
            .as_ref()
            .is_none_or(|g| g.sums().len() == region.rect.area() * g.groups())
        && a.light
            .as_ref()
            .is_none_or(|l| l.len() == size.0 as usize * size.1 as usize);
    if !fits {
        return Err(RenderError::Resume(format!(
            "the saved progress holds samples {:?} of pixels {} of a {}×{} image{}{}, which is not a start of samples {:?} of pixels {} of this {}×{} render{}{}",
            a.region.samples,
            a.region.rect,
            a.width,
            a.height,
            with_light_paths(a.light.is_some()),
            with_kept(&a.kept()),
            region.samples,
            region.rect,
            size.0,
            size.1,
            with_light_paths(light),
            with_kept(&kept),
        )));
    }
    Ok(a)
}

fn with_light_paths(light: bool) -> &'static str {
    if light { " with light paths" } else { "" }
}

fn with_kept(kept: &Kept) -> String {
    let mut what = Vec::new();
    if kept.guides {
        what.push("guides".to_owned());
    }
    if kept.components {
        what.push("radiance components".to_owned());
    }
    if !kept.light_groups.is_empty() {
        what.push(format!("light groups {}", kept.light_groups.join(", ")));
    }
    match what.len() {
        0 => String::new(),
        _ => format!(" with {} (AOVs)", what.join(" and ")),
    }
}
