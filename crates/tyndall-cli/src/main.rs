//! `tyndall`: the command-line renderer.
//!
//! A thin layer over the `tyndall` library: parse flags, load the scene,
//! show progress, write the image, report statistics. The exit status is
//! 0 only when the image was written.

mod bench;
mod finish;
#[cfg(feature = "gpu")]
mod gpu;
#[cfg(feature = "view")]
mod view;

use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};
use tyndall::color::Rgb;
use tyndall::description::Origin;
use tyndall::lights::{EnvironmentLight, LightSampling};
use tyndall::parts::{self, Part, PartIdentity};
use tyndall::region::{PixelRect, RenderRegion};
use tyndall::render::Accumulation;
use tyndall::settings::{DEFAULT_MAP_RESOLUTION, VisibilityMode};
use tyndall::{IntegratorKind, RenderStats, Scene, SceneDesc};
use tyndall_image::ImageFormat;
use tyndall_image::parts::{PartCompression, read_part, write_part};
use tyndall_load::{LegacyOptions, LoadOptions, SceneError, demo};

#[derive(Parser)]
#[command(
    name = "tyndall",
    version,
    about = "Tyndall renders light in participating media: beams from spotlights in fog, volumetric shadows and light coloured by stained glass."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to an image file (PNG or OpenEXR, by the file ending).
    Render(RenderArgs),
    /// Print the relative MSE of an image against a reference (both OpenEXR),
    /// the metric of scenes/reference (docs/physics.md §6): mean of (c − r)²/(r² + 0.01).
    Compare {
        candidate: PathBuf,
        reference: PathBuf,
        /// Also list the N pixels that contribute most to the error, and the share of the error in the worst 0.1% of pixels (a firefly measure).
        #[arg(long, default_value_t = 0)]
        worst: usize,
    },
    /// Measure time to equal error for `march` and `single` (see docs/benchmarks.md).
    Bench(bench::BenchArgs),
    /// Show a scene live in a window: the GPU march accumulating while the
    /// view is still, an orbit/fly camera and keyboard controls (`tyndall view --help` lists them).
    #[cfg(feature = "view")]
    View(view::ViewArgs),
    /// Assemble render parts (`render --tile`/`--samples` outputs) into one image,
    /// after checking that they fit together: same scene and settings, tiles
    /// without gaps or overlaps, consecutive sample ranges.
    Merge {
        /// Part files (OpenEXR, as written by `render --tile` or `--samples`).
        #[arg(required = true)]
        parts: Vec<PathBuf>,
        /// Output: .exr (a part holding the merged sums, mergeable again) or .png.
        /// With --denoise or --aov, the .exr is an image (denoised, with its AOV layers), not a part.
        #[arg(short, long)]
        output: PathBuf,
        #[command(flatten)]
        finishing: finish::Finishing,
    },
}

#[derive(Args)]
struct RenderArgs {
    /// Scene file: native TOML (.toml), the paper's legacy format (.obj) or glTF 2.0 (.gltf, .glb).
    /// Without one, the built-in demo (a stained-glass window in a dusty room).
    scene: Option<PathBuf>,
    /// Output image; .png (8-bit sRGB, exposure applied) or .exr (linear float).
    /// Default: the scene's `output`, else tyndall.png.
    #[arg(short, long)]
    output: Option<PathBuf>,
    #[command(flatten)]
    overrides: Overrides,
    /// Load legacy .obj quads as two-sided (the course code makes them one-sided).
    #[arg(long)]
    two_sided: bool,
    /// The frame of the scene's file sequences: a run of `#` in a [[media]]
    /// `file` is the frame number, zero-padded (a Blender fluid cache's
    /// `cache/data/fluid_data_####.vdb` at --frame 12 reads fluid_data_0012.vdb).
    #[arg(long)]
    frame: Option<u32>,
    /// No progress bar and no statistics (errors and warnings still go to stderr).
    #[arg(short, long)]
    quiet: bool,
    /// Render tile I of N (0 ≤ I < N): horizontal bands of whole rows, tile I
    /// holding rows ⌊I·H/N⌋ to ⌊(I+1)·H/N⌋. Writes a part (.exr) for `tyndall merge`.
    #[arg(long, value_parser = parse_tile)]
    tile: Option<(u32, u32)>,
    /// Render only sample indices A..B (A included, B excluded) of each pixel.
    /// Writes a part (.exr) for `tyndall merge`.
    #[arg(long, value_parser = parse_samples)]
    samples: Option<(u32, u32)>,
    /// Save progress (per-pixel sums) to this file and resume from it if it
    /// exists; removed once the output is written.
    #[arg(long)]
    checkpoint: Option<PathBuf>,
    /// How often to save the checkpoint: after the first whole pass that ends
    /// this long after the last save (e.g. 60s, 5m; default 60s).
    #[arg(long, value_parser = parse_duration, default_value = "60s")]
    checkpoint_every: Duration,
    /// Stop after the last whole pass (one sample per pixel) that fits in this
    /// time (e.g. 30s, 2m); at least one pass. Reports the samples per pixel reached.
    #[arg(long, value_parser = parse_duration)]
    time_limit: Option<Duration>,
    /// Render on the GPU (wgpu; lavapipe without one): the `march` or the
    /// `single` integrator (interleaved over --interleave) with shadow rays
    /// or maps (--visibility), --spp frames accumulated. Flags it cannot
    /// honour are errors.
    #[arg(long)]
    gpu: bool,
    #[command(flatten)]
    finishing: finish::Finishing,
}

fn parse_tile(s: &str) -> Result<(u32, u32), String> {
    let err = || format!("`{s}` is not a tile: expected I/N, e.g. 0/4");
    let (i, n) = s.split_once('/').ok_or_else(err)?;
    let (i, n) = (
        i.trim().parse().map_err(|_| err())?,
        n.trim().parse().map_err(|_| err())?,
    );
    if n == 0 || i >= n {
        return Err(format!(
            "tile {i}/{n}: N must be at least 1 and I below N (tiles are numbered from 0)"
        ));
    }
    Ok((i, n))
}

fn parse_samples(s: &str) -> Result<(u32, u32), String> {
    let err = || format!("`{s}` is not a sample range: expected A..B, e.g. 0..16");
    let (a, b) = s.split_once("..").ok_or_else(err)?;
    let (a, b): (u32, u32) = (
        a.trim().parse().map_err(|_| err())?,
        b.trim().parse().map_err(|_| err())?,
    );
    if a >= b {
        return Err(format!("sample range {a}..{b} is empty: B must be above A"));
    }
    Ok((a, b))
}

/// A duration: a number with `ms`, `s`, `m` or `h` (seconds without one).
fn parse_duration(s: &str) -> Result<Duration, String> {
    let t = s.trim();
    let (number, unit) = match t.find(|c: char| c.is_ascii_alphabetic()) {
        Some(i) => t.split_at(i),
        None => (t, "s"),
    };
    let scale = match unit {
        "ms" => 1e-3,
        "s" => 1.0,
        "m" | "min" => 60.0,
        "h" => 3600.0,
        _ => return Err(format!("`{s}`: unknown unit `{unit}` (use ms, s, m or h)")),
    };
    let value: f64 = number
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a duration such as 30s or 5m"))?;
    let secs = value * scale;
    if !(0.0..1e9).contains(&secs) {
        return Err(format!(
            "`{s}`: a duration must be between 0 and 10⁹ seconds"
        ));
    }
    Ok(Duration::from_secs_f64(secs))
}

/// Settings that override the scene file's.
#[derive(Args, Clone, Default)]
pub struct Overrides {
    /// Image width in pixels.
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels.
    #[arg(long)]
    pub height: Option<u32>,
    /// Samples per pixel (stratified over the pixel and every sampled dimension).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Integrator: `march` (the paper's fixed-step ray march; accepts albedo > 1),
    /// `single` (unbiased single scattering, equiangular + distance sampling with MIS)
    /// or `volpath` (volumetric path tracing with multiple scattering).
    #[arg(long, value_parser = parse_integrator)]
    pub integrator: Option<IntegratorKind>,
    /// March step length in scene units (the paper used 0.1); `march` only.
    #[arg(long, allow_negative_numbers = true)]
    pub step: Option<f32>,
    /// Most scattering events per path for `volpath` (1 = single scattering;
    /// default unlimited, Russian roulette ends paths).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Equiangular samples per light per camera ray, stratified along the ray
    /// (default 8): `single` towards every light, `volpath` towards point and
    /// spot lights (towards area lights it takes one).
    #[arg(long)]
    pub volume_samples: Option<u32>,
    /// Visibility towards lights: `rays` (exact shadow rays through the BVH) or
    /// `maps` (per-light shadow and coloured transmittance maps rendered once;
    /// a lookup per march step instead of a ray; area lights keep rays).
    #[arg(long, value_parser = ["rays", "maps"])]
    pub visibility: Option<String>,
    /// How estimates choose among lights: `tree` (a few point and spot lights
    /// per estimate from a light BVH, by their importance there), `all` (every
    /// light at every estimate) or `auto` (the tree from 256 point and spot
    /// lights on; the default). Area lights and suns are always all visited.
    #[arg(long, value_parser = ["auto", "all", "tree"])]
    pub light_sampling: Option<String>,
    /// Shadow-map resolution, texels per side of each map face (default 512).
    #[arg(long)]
    pub shadow_map_resolution: Option<u32>,
    /// Interleaved sampling for `march`: pixels of an N×N tile start their
    /// march at different offsets (Keller & Heidrich 2001); 1 is off. On the
    /// GPU (`--gpu`, `view`) the tile also shares out the march's lattice:
    /// each pixel evaluates 1/N² of it per frame, the same image in the mean.
    #[arg(long)]
    pub interleave: Option<u32>,
    /// Fog extinction σt per scene unit (the paper's air density τ). Adds fog
    /// filling all space if the scene has none, as the paper's legacy scenes need.
    #[arg(long, allow_negative_numbers = true)]
    pub density: Option<f32>,
    /// Fog single-scattering albedo (grey). Values above 1 are not physical:
    /// only `march` accepts them, with a warning, as in the paper's figures.
    #[arg(long, allow_negative_numbers = true)]
    pub albedo: Option<f32>,
    /// Fog phase-function asymmetry g of Henyey–Greenstein (0 isotropic,
    /// > 0 forward scattering), in [−0.999, 0.999]; needs fog (or --density).
    #[arg(long, allow_negative_numbers = true)]
    pub g: Option<f32>,
    /// Environment light: a radiance, grey (`0.5`) or linear RGB
    /// (`0.2,0.3,0.5`, W/(m²·sr)), the same from every direction, or an
    /// equirectangular map (an OpenEXR or Radiance HDR file, y up). Replaces
    /// the scene's environment and background; lights glTF assets that
    /// have no lights of their own.
    #[arg(long, allow_hyphen_values = true)]
    pub environment: Option<String>,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Seed of the per-pixel sample sequences.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Exposure in stops for PNG output (multiplies radiance by 2^exposure).
    #[arg(long, allow_negative_numbers = true)]
    pub exposure: Option<f32>,
}

/// The environment `--environment` names: a radiance of one or three
/// comma-separated numbers, or else a map file.
fn parse_environment(value: &str) -> Result<EnvironmentLight> {
    let numbers: Result<Vec<f32>, _> = value.split(',').map(|n| n.trim().parse()).collect();
    let scale = match numbers.as_deref() {
        Ok(&[grey]) => Rgb::splat(grey),
        Ok(&[r, g, b]) => Rgb::new(r, g, b),
        Ok(_) => bail!("--environment {value}: a radiance is one number or three (r,g,b)"),
        Err(_) => {
            let map = tyndall_load::images::load_environment_map(Path::new(value))
                .map_err(|e| anyhow::anyhow!("--environment: {e}"))?;
            return Ok(EnvironmentLight::mapped(
                std::sync::Arc::new(map),
                Rgb::ONE,
                0.0,
            ));
        }
    };
    if !(scale.is_finite() && scale.min_element() >= 0.0) {
        bail!("--environment {value}: a radiance must be finite and ≥ 0 in every channel");
    }
    tyndall::limits::check_emission("--environment", scale).map_err(anyhow::Error::msg)?;
    Ok(EnvironmentLight::uniform(scale))
}

fn parse_integrator(s: &str) -> Result<IntegratorKind, String> {
    IntegratorKind::from_name(s)
        .ok_or_else(|| format!("unknown integrator `{s}`: expected `march`, `single` or `volpath`"))
}

impl Overrides {
    /// Applies the overrides to a loaded scene.
    pub fn apply(&self, desc: &mut SceneDesc) -> Result<()> {
        let s = &mut desc.settings;
        if let Some(v) = self.width {
            s.width = v;
        }
        if let Some(v) = self.height {
            s.height = v;
        }
        if let Some(v) = self.spp {
            s.spp = v;
        }
        if let Some(v) = self.integrator {
            s.integrator = v;
        }
        if let Some(v) = self.step {
            s.step = v;
        }
        if let Some(v) = self.max_depth {
            s.max_depth = v;
        }
        if let Some(v) = self.volume_samples {
            s.volume_samples = v;
        }
        if let Some(v) = self.interleave {
            s.interleave = v;
        }
        let resolution = match (self.shadow_map_resolution, s.visibility) {
            (Some(r), _) => r,
            (None, VisibilityMode::Maps { resolution }) => resolution,
            (None, VisibilityMode::ShadowRays) => DEFAULT_MAP_RESOLUTION,
        };
        s.visibility = match (self.visibility.as_deref(), s.visibility) {
            (Some("rays"), _) => VisibilityMode::ShadowRays,
            (Some(_), _) | (None, VisibilityMode::Maps { .. }) => {
                VisibilityMode::Maps { resolution }
            }
            (None, VisibilityMode::ShadowRays) => VisibilityMode::ShadowRays,
        };
        if let Some(v) = self.threads {
            s.threads = Some(v);
        }
        if let Some(v) = self.seed {
            s.seed = v;
        }
        if let Some(v) = self.exposure {
            s.exposure = v;
        }
        if let Some(name) = &self.light_sampling {
            desc.light_sampling = LightSampling::from_name(name)
                .ok_or_else(|| anyhow::anyhow!("unknown light sampling `{name}`"))?;
        }
        if let Some(value) = &self.environment {
            desc.set_environment(parse_environment(value)?, Origin::Code);
        }
        desc.override_fog(self.density, self.albedo)
            .map_err(anyhow::Error::msg)?;
        if let Some(g) = self.g {
            desc.override_fog_asymmetry(g).map_err(anyhow::Error::msg)?;
        }
        Ok(())
    }
}

/// Refuses the first flag in `refused` that was given — each a flag's
/// presence, its name and why `command` cannot honour it — with an error
/// naming the flag: a flag is never silently ignored.
#[cfg(feature = "gpu")]
fn refuse_flags(command: &str, refused: &[(bool, &str, &str)]) -> Result<()> {
    match refused.iter().find(|(given, _, _)| *given) {
        Some((_, flag, why)) => bail!("{flag} cannot be used with {command}: {why}"),
        None => Ok(()),
    }
}

/// Loads a scene by its file ending, or the demo for `None`.
pub fn load_scene(path: Option<&Path>, two_sided: bool, frame: Option<u32>) -> Result<SceneDesc> {
    Ok(match path {
        None => {
            let mut desc = demo::load()?;
            if let Some(frame) = frame {
                desc.warnings.push(format!(
                    "--frame {frame} is unused: the demo has no file sequence"
                ));
            }
            desc
        }
        Some(path) => tyndall_load::load(
            path,
            LoadOptions {
                legacy: LegacyOptions { two_sided },
                frame,
            },
        )?,
    })
}

/// The runtime scene of a description; errors name the item's origin.
pub fn build_scene(desc: &SceneDesc) -> Result<Scene> {
    Ok(Scene::build(desc).map_err(SceneError::from)?)
}

fn render(args: RenderArgs) -> Result<()> {
    if args.gpu {
        return render_on_gpu(args);
    }
    let mut desc = load_scene(args.scene.as_deref(), args.two_sided, args.frame)?;
    args.overrides.apply(&mut desc)?;
    let output = args
        .output
        .or(desc.output.clone())
        .unwrap_or_else(|| PathBuf::from("tyndall.png"));
    // Fail on a bad output name before spending time on the render.
    let format = ImageFormat::from_path(&output)?;
    if let Some(checkpoint) = &args.checkpoint
        && same_file(checkpoint, &output)
    {
        bail!(
            "{}: --checkpoint names the output file; the checkpoint is removed when the render completes, so give it a name of its own",
            checkpoint.display()
        );
    }
    let is_part = args.tile.is_some() || args.samples.is_some();
    if is_part && format != ImageFormat::Exr {
        bail!(
            "{}: --tile and --samples write a render part for `tyndall merge`, which must be an .exr file",
            output.display()
        );
    }
    if is_part && args.finishing.denoise {
        bail!(
            "--denoise cannot be used with --tile or --samples: a part is denoised after the merge (`tyndall merge --denoise`)"
        );
    }
    if is_part && args.finishing.aov.is_some() {
        bail!(
            "--aov cannot be used with --tile or --samples: a part keeps the sums of every AOV it can; name the AOVs when merging (`tyndall merge --aov ...`)"
        );
    }
    let finisher = args.finishing.prepare(&output)?;
    // Ranges were checked at load for the scene's own settings, so an
    // error here is a flag's.
    desc.settings
        .check_ranges()
        .map_err(|e| anyhow::anyhow!("--{}: {e}", e.setting.replace('_', "-")))?;
    // Parts and checkpoints always keep the guides, so that any part can
    // be merged and denoised, and a checkpoint resumed with any flags.
    let keeps_all = is_part || args.checkpoint.is_some();
    desc.settings.guides = finisher.needs_guides() || keeps_all;
    let (settings, loader_warnings) = (desc.settings, std::mem::take(&mut desc.warnings));
    // The description moves into the scene: its grids are not held twice.
    let scene = Scene::from_desc(desc).map_err(SceneError::from)?;
    // Renders with light paths cannot split their components or light
    // groups: asking for them is an error (from the render), keeping them
    // for a part is not attempted.
    // Parts and checkpoints keep the light groups of a scene that names
    // any, for the same reasons.
    let splits = !tyndall::render::traces_light_paths(&scene, &settings);
    let settings = tyndall::RenderSettings {
        components: finisher.needs_components() || (keeps_all && splits),
        light_groups: finisher.needs_light_groups()
            || (keeps_all && splits && scene.light_groups().len() > 1),
        ..settings
    };
    settings.validate(&scene)?;
    let rect = match args.tile {
        Some((i, n)) => PixelRect::tile(i, n, settings.width, settings.height)?,
        None => PixelRect::full(settings.width, settings.height),
    };
    let samples = args.samples.map_or(0..settings.spp, |(a, b)| a..b);
    let region = RenderRegion { rect, samples };
    region.check(settings.width, settings.height)?;
    // Fail on a bad output name or an unwritable destination before
    // spending time on the render: the temporary file beside the target
    // is created now and renamed onto it once the image is complete.
    let output_file = tyndall_image::OutputFile::create(&output)?;
    for w in loader_warnings.into_iter().chain(settings.warnings(&scene)) {
        eprintln!("warning: {w}");
    }
    // The render's identity hashes the whole scene (every primitive and
    // image: a fifth of a second for 200 000 triangles); only parts and
    // checkpoints carry it, and a plain render does not compute it.
    let identity = keeps_all.then(|| PartIdentity::new(&scene, &settings));
    let resume = match &args.checkpoint {
        Some(path) if path.exists() => {
            let part = read_part(path)?;
            if identity != Some(part.identity) {
                bail!(
                    "{}: this checkpoint is of another scene, settings or seed; delete it to start again",
                    path.display()
                );
            }
            if !args.quiet {
                eprintln!(
                    "resuming from {}: samples {}..{} done",
                    path.display(),
                    part.accumulation.region.samples.start,
                    part.accumulation.region.samples.end
                );
            }
            Some(part.accumulation)
        }
        _ => None,
    };
    let done = resume.as_ref().map_or(0, |a| a.passes());
    let passes = (region.samples.len() as u64).saturating_sub(done as u64);
    let bar = progress_bar(rect.height() as u64 * passes, args.quiet);
    let start = Instant::now();
    let mut last_save = Instant::now();
    let mut save_error = None;
    let mut stopped_by_limit = false;
    let mut after_pass = |a: &Accumulation, pass_time: Duration| {
        if let (Some(path), Some(identity)) = (&args.checkpoint, identity)
            && a.region.samples.end < region.samples.end
            && last_save.elapsed() >= args.checkpoint_every
        {
            let part = Part {
                identity,
                accumulation: a.clone(),
            };
            if let Err(e) = write_part(path, &part, PartCompression::None) {
                save_error = Some(e);
                return ControlFlow::Break(());
            }
            last_save = Instant::now();
        }
        match args.time_limit {
            Some(limit) if start.elapsed() + pass_time > limit => {
                stopped_by_limit = a.region.samples.end < region.samples.end;
                ControlFlow::Break(())
            }
            _ => ControlFlow::Continue(()),
        }
    };
    let (accumulation, stats) = tyndall::render::render_region(
        &scene,
        &settings,
        &region,
        resume,
        &|_| bar.inc(1),
        &mut after_pass,
    )
    .map_err(|e| match (&e, &args.checkpoint) {
        (tyndall::render::RenderError::Resume(_), Some(path)) => {
            anyhow::anyhow!("{}: {e}", path.display())
        }
        _ => e.into(),
    })?;
    bar.finish_and_clear();
    if let Some(e) = save_error {
        return Err(e).context("the checkpoint could not be saved; the render stopped");
    }
    // With an identity (a part or a checkpointed render) the sums travel
    // as a part; without one, alone.
    let finished = match identity {
        Some(identity) => Ok(Part {
            identity,
            accumulation,
        }),
        None => Err(accumulation),
    };
    let (part, accumulation) = match &finished {
        Ok(part) => (Some(part), &part.accumulation),
        Err(sums) => (None, sums),
    };
    let reached = accumulation.passes();
    match part {
        Some(part) if is_part => {
            // A part is written (atomically) by the part writer: the early
            // temporary file only proved the destination writable.
            drop(output_file);
            write_part(&output, part, PartCompression::Rle)
                .with_context(|| "the part was not written")?;
        }
        _ => finisher.write(output_file, accumulation, settings.exposure)?,
    }
    if !args.quiet {
        report(&settings, accumulation, &stats, &output);
    }
    if stats.invalid_samples > 0 {
        // Even with --quiet: the image is missing these samples.
        eprintln!(
            "warning: {} samples (of {} camera samples and the light-path connections) were NaN or infinite and were dropped (the image averages the rest)",
            stats.invalid_samples, stats.samples
        );
    }
    if stopped_by_limit {
        // Said even with --quiet: the image holds fewer samples than asked.
        eprintln!(
            "time limit reached: {reached} samples per pixel (samples {}..{}) of the {} asked for",
            region.samples.start,
            region.samples.start + reached,
            region.samples.len()
        );
    }
    if let (Some(path), Some(part)) = (&args.checkpoint, part) {
        if stopped_by_limit {
            // Keep the progress: running again continues the render.
            write_part(path, part, PartCompression::None)
                .context("the checkpoint could not be saved")?;
        } else if path.exists() {
            std::fs::remove_file(path)
                .with_context(|| format!("{}: could not remove the checkpoint", path.display()))?;
        }
    }
    Ok(())
}

/// Whether `a` and `b` name the same file, whether or not it exists yet:
/// the canonical form of each one's folder, with its file name.
fn same_file(a: &Path, b: &Path) -> bool {
    let canonical = |p: &Path| {
        let folder = match p.parent() {
            Some(f) if !f.as_os_str().is_empty() => f,
            _ => Path::new("."),
        };
        Some(std::fs::canonicalize(folder).ok()?.join(p.file_name()?))
    };
    match (canonical(a), canonical(b)) {
        (Some(a), Some(b)) => a == b,
        _ => a == b,
    }
}

#[cfg(feature = "gpu")]
fn render_on_gpu(args: RenderArgs) -> Result<()> {
    gpu::render(args)
}

#[cfg(not(feature = "gpu"))]
fn render_on_gpu(_: RenderArgs) -> Result<()> {
    bail!("--gpu: this tyndall was built without the `gpu` feature")
}

fn merge(paths: &[PathBuf], output: &Path, finishing: &finish::Finishing) -> Result<()> {
    let format = ImageFormat::from_path(output)?;
    let finisher = finishing.prepare(output)?;
    let mut read = Vec::with_capacity(paths.len());
    for path in paths {
        read.push((path.clone(), read_part(path)?));
    }
    let merged = parts::merge(read)?;
    match format {
        ImageFormat::Exr if !finisher.finishes() => {
            write_part(output, &merged, PartCompression::Rle)?;
        }
        _ => {
            let file = tyndall_image::OutputFile::create(output)?;
            finisher.write(file, &merged.accumulation, 0.0)?;
        }
    }
    let a = &merged.accumulation;
    eprintln!(
        "merged {} parts into {} (pixels {} of {}×{}, samples {}..{})",
        paths.len(),
        output.display(),
        a.region.rect,
        a.width,
        a.height,
        a.region.samples.start,
        a.region.samples.end
    );
    Ok(())
}

fn progress_bar(rows: u64, quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    // Draws only on a terminal; hidden when stderr is redirected.
    let bar = ProgressBar::with_draw_target(Some(rows), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template("{spinner} rendering [{bar:40}] {percent:>3}% rows {pos}/{len}, {elapsed} elapsed, ETA {eta}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar
}

fn report(
    settings: &tyndall::RenderSettings,
    accumulation: &Accumulation,
    stats: &RenderStats,
    output: &Path,
) {
    let secs = stats.elapsed.as_secs_f64();
    let rect = accumulation.region.rect;
    let part = if rect == PixelRect::full(settings.width, settings.height) {
        String::new()
    } else {
        format!(", pixels {rect}")
    };
    let samples = &accumulation.region.samples;
    let range = if samples.start == 0 {
        String::new()
    } else {
        format!(", samples {}..{}", samples.start, samples.end)
    };
    eprintln!(
        "wrote {} ({}×{}{part}, {} spp{range}, {}, visibility {}) in {:.2} s: {:.2} M samples, {:.2} M rays ({:.2} M camera, {:.2} M shadow), {:.2} M rays/s",
        output.display(),
        settings.width,
        settings.height,
        accumulation.passes(),
        settings.integrator.name(),
        settings.visibility.name(),
        secs,
        stats.samples as f64 * 1e-6,
        stats.rays.total() as f64 * 1e-6,
        stats.rays.camera as f64 * 1e-6,
        stats.rays.shadow as f64 * 1e-6,
        stats.rays_per_second() * 1e-6,
    );
    if let VisibilityMode::Maps { resolution } = settings.visibility {
        eprintln!(
            "shadow maps: {resolution}² texels per face, built in {:.2} s; {:.2} M lookups",
            stats.maps.as_secs_f64(),
            stats.rays.map_lookups as f64 * 1e-6
        );
    }
    eprintln!("non-finite samples dropped: {}", stats.invalid_samples);
}

fn compare(candidate: &Path, reference: &Path, worst: usize) -> Result<()> {
    print!(
        "{}",
        tyndall_image::compare_files(candidate, reference, worst)?
    );
    Ok(())
}

/// Makes a file-size limit (`ulimit -f`) an error instead of a kill:
/// by default SIGXFSZ ends the process mid-write and leaves the output's
/// temporary file behind; ignored, the write fails with EFBIG, the error
/// is reported and the temporary file removed (issue 11).
fn ignore_file_size_signal() {
    #[cfg(unix)]
    // SAFETY: `signal` with `SIG_IGN` installs no handler code, so there is
    // no async-signal-safety obligation; it runs first in `main`, before any
    // thread exists, so it races with no other signal-disposition change.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

fn main() -> ExitCode {
    ignore_file_size_signal();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render(args),
        Command::Bench(args) => bench::run(args),
        #[cfg(feature = "view")]
        Command::View(args) => view::run(args),
        Command::Merge {
            parts,
            output,
            finishing,
        } => merge(&parts, &output, &finishing),
        Command::Compare {
            candidate,
            reference,
            worst,
        } => compare(&candidate, &reference, worst),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
