//! `tyndall bench`: time to equal error, per integrator.
//!
//! For each case, an integrator renders at a ladder of sample counts; each
//! point is timed (median of several runs: these machines are noisy) and
//! its relative MSE measured against a reference — an independent
//! renderer's converged image, or a long `single` render with another seed
//! cached under `target/tyndall-bench/`. The time to reach a target error
//! is interpolated log-log between the two ladder points around it
//! (Monte Carlo error falls like 1/spp, time grows like spp).

#[cfg(feature = "gpu")]
mod gpu;
mod lights;
mod load;
mod maps;
mod smoke;

use anyhow::{Context, Result, bail};
use clap::Args;
use std::path::PathBuf;
use std::time::Duration;
use tyndall::SceneDesc;
use tyndall::settings::DEFAULT_VOLUME_SAMPLES;
use tyndall::{Image, IntegratorKind, RenderSettings};
use tyndall_image::metrics::{error_concentration, relative_mse};
use tyndall_image::read_exr;
use tyndall_load::{demo, native};

#[derive(Args)]
pub struct BenchArgs {
    /// Directory holding the repository's scenes (for the reference and fig. 7 cases).
    #[arg(long, default_value = "scenes")]
    pub(crate) scenes: PathBuf,
    /// Where long reference renders (and generated scenes) are cached.
    #[arg(long, default_value = "target/tyndall-bench")]
    pub(crate) cache: PathBuf,
    /// A sparse OpenVDB cloud to time loading (`--only load`).
    #[arg(long)]
    pub(crate) vdb: Option<PathBuf>,
    /// Timed runs per point (the median is reported).
    #[arg(long, default_value_t = 3)]
    pub(crate) runs: usize,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub(crate) threads: Option<usize>,
    /// A small, fast version of every case (to check the benchmark runs).
    #[arg(long)]
    pub(crate) quick: bool,
    /// Which part to run: `equal-error` (time to equal error per integrator),
    /// `maps` (shadow maps against shadow rays), `volpath` (the path tracer
    /// against Mitsuba 3's multiple-scattering references), `smoke` (the path tracer in the voxel
    /// smoke, and its cost against homogeneous media), `lights` (the stage rig
    /// with 1, 64 and 1024 spots, every light against the light tree), `load`
    /// (loading a million-triangle glTF and, with `--vdb`, a sparse OpenVDB
    /// cloud) or `all`.
    #[arg(long, default_value = "all", value_parser = ["all", "equal-error", "maps", "volpath", "smoke", "lights", "load"])]
    only: String,
    /// Benchmark the GPU march and single scattering instead (frames per
    /// second; see bench/gpu.rs).
    #[arg(long)]
    gpu: bool,
    /// Stop a curve after a point whose render takes longer than this (seconds).
    #[arg(long, default_value_t = 20.0)]
    max_seconds: f64,
}

/// One measured point of an error curve.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Point {
    spp: u32,
    seconds: f64,
    rel_mse: f64,
    /// Share of the error in the worst 0.1% of pixels (fireflies).
    worst_share: f64,
}

/// A configuration that is benchmarked: an integrator and, for `march`, a step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Method {
    kind: IntegratorKind,
    step: f32,
    /// Equiangular samples per light per ray (`single`).
    volume_samples: u32,
}

impl Method {
    pub(crate) fn single(volume_samples: u32) -> Self {
        Self {
            kind: IntegratorKind::Single,
            step: 0.1,
            volume_samples,
        }
    }

    pub(crate) fn volpath() -> Self {
        Self {
            kind: IntegratorKind::Volpath,
            step: 0.1,
            volume_samples: DEFAULT_VOLUME_SAMPLES,
        }
    }

    pub(crate) fn march(step: f32) -> Self {
        Self {
            kind: IntegratorKind::March,
            step,
            volume_samples: 1,
        }
    }

    fn label(&self) -> String {
        match self.kind {
            IntegratorKind::March => format!("march (step {})", self.step),
            IntegratorKind::Single => format!("single ({} samples per ray)", self.volume_samples),
            IntegratorKind::Volpath => "volpath".to_string(),
        }
    }
}

pub fn run(args: BenchArgs) -> Result<()> {
    if args.gpu {
        return run_gpu(&args);
    }
    let quick = args.quick;
    println!(
        "# tyndall bench{}\n",
        if quick {
            " --quick (sizes reduced: figures are not meaningful)"
        } else {
            ""
        }
    );
    println!(
        "Times are medians of {} runs, wall clock, {} threads.\n",
        args.runs,
        args.threads.map_or("all".into(), |t| t.to_string())
    );

    let all = args.only == "all";
    if all || args.only == "equal-error" {
        equal_error(&args)?;
    }
    if all || args.only == "maps" {
        maps::run(&args)?;
    }
    if all || args.only == "volpath" {
        volpath(&args)?;
    }
    if all || args.only == "smoke" {
        smoke::run(&args)?;
    }
    if all || args.only == "lights" {
        lights::run(&args)?;
    }
    if all || args.only == "load" {
        load::run(&args)?;
    }
    Ok(())
}

#[cfg(feature = "gpu")]
fn run_gpu(args: &BenchArgs) -> Result<()> {
    gpu::run(args)
}

#[cfg(not(feature = "gpu"))]
fn run_gpu(_: &BenchArgs) -> Result<()> {
    bail!("--gpu: this tyndall was built without the `gpu` feature")
}

/// Time to relative MSE of `volpath` against the multiple-scattering
/// references of an independent renderer (Mitsuba 3, scenes/reference/):
/// the fog-filled room and the Cornell box without fog. A benchmark
/// against a longer Tyndall render could not see a bias; this one does.
fn volpath(args: &BenchArgs) -> Result<()> {
    // --quick renders at a quarter of the size against the reference's
    // 4×4 block means, which is exactly the coarser image's reference.
    let scale = if args.quick { 4 } else { 1 };
    let ladder: &[u32] = if args.quick {
        &[2, 4]
    } else {
        &[4, 8, 16, 32, 64, 128, 256]
    };
    for name in ["fog-room-multi", "cornell-surfaces"] {
        let dir = args.scenes.join("reference");
        let desc = native::load(&dir.join(format!("{name}.toml")))?;
        let reference = read_exr(&dir.join(format!("{name}.exr")))?.box_downsample(scale);
        let (w, h) = (reference.width(), reference.height());
        println!(
            "## volpath on `{name}` (scenes/reference/{name}.toml) at {w}×{h}, against Mitsuba 3\n"
        );
        println!(
            "Reference: Mitsuba 3 `volpath` (scenes/reference/{name}.exr; its own error is in {name}.ref.json).\n"
        );
        let method = Method::volpath();
        let curve = measure(&desc, args, w, h, method, ladder, &reference)?;
        print_curve(&method, &curve);
        report_time_to_error(&[(method, curve)], &[1e-2, 3e-3]);
    }
    Ok(())
}

/// Time to equal error of `single` and `march` on three scenes.
fn equal_error(args: &BenchArgs) -> Result<()> {
    let quick = args.quick;
    // 1. Against an independent renderer.
    let dir = args.scenes.join("reference");
    let desc = native::load(&dir.join("fog-spot-sphere.toml"))?;
    let reference =
        read_exr(&dir.join("fog-spot-sphere.exr")).context("reading the reference image")?;
    let (width, height) = if quick {
        (320, 240)
    } else {
        (reference.width(), reference.height())
    };
    if (width, height) != (reference.width(), reference.height()) {
        bail!(
            "the reference is {}×{}",
            reference.width(),
            reference.height()
        );
    }
    let ladder: &[u32] = if quick {
        &[1, 2, 4]
    } else {
        &[1, 2, 4, 8, 16, 32]
    };
    println!("## fog-spot-sphere 320×240 against Mitsuba 3 (shared/reference)\n");
    let mut curves = Vec::new();
    for method in [
        Method::single(DEFAULT_VOLUME_SAMPLES),
        Method::single(1),
        Method::march(0.1),
    ] {
        let curve = measure(&desc, args, width, height, method, ladder, &reference)?;
        print_curve(&method, &curve);
        curves.push((method, curve));
    }
    report_time_to_error(&curves, &[1e-3, 3e-4]);

    // 2. The paper's fig. 7: `single` against the best `march` step.
    let desc = native::load(&args.scenes.join("fig07-spot-sphere.toml"))?;
    let (w, h, ref_spp) = if quick {
        (80, 60, 64)
    } else {
        (320, 240, 2048)
    };
    equal_error_case(
        "fig. 7 (scenes/fig07-spot-sphere.toml)",
        "fig07",
        &desc,
        args,
        w,
        h,
        ref_spp,
        ladder,
    )?;

    // 3. The demo at 1280×720.
    let desc = demo::load()?;
    let (w, h, ref_spp) = if quick {
        (128, 72, 16)
    } else {
        (1280, 720, 512)
    };
    let demo_ladder: &[u32] = if quick {
        &[1, 2]
    } else {
        &[1, 2, 4, 8, 16, 32]
    };
    equal_error_case(
        "the demo (built in, scenes/stained-glass.toml)",
        "demo",
        &desc,
        args,
        w,
        h,
        ref_spp,
        demo_ladder,
    )?;
    Ok(())
}

/// Error curves of `single` and of `march` at several steps against a
/// long `single` render; prints time to `target` relMSE for each.
#[allow(clippy::too_many_arguments)]
fn equal_error_case(
    title: &str,
    key: &str,
    desc: &SceneDesc,
    args: &BenchArgs,
    width: u32,
    height: u32,
    reference_spp: u32,
    ladder: &[u32],
) -> Result<()> {
    println!("## {title} at {width}×{height}\n");
    let reference = long_render(
        desc,
        args,
        key,
        width,
        height,
        reference_spp,
        Method::single(DEFAULT_VOLUME_SAMPLES),
    )?;
    println!(
        "Reference: `single`, {reference_spp} spp, seed 1000 (independent of the seeds below).\n"
    );
    let mut curves = Vec::new();
    let steps: &[f32] = if args.quick {
        &[0.1]
    } else {
        &[0.05, 0.1, 0.2, 0.4]
    };
    let methods = [Method::single(DEFAULT_VOLUME_SAMPLES), Method::single(1)]
        .into_iter()
        .chain(steps.iter().map(|&step| Method::march(step)));
    for method in methods {
        let curve = measure(desc, args, width, height, method, ladder, &reference)?;
        print_curve(&method, &curve);
        curves.push((method, curve));
    }
    report_time_to_error(&curves, &[1e-3, 3e-4]);
    Ok(())
}

pub(crate) fn settings(
    desc: &SceneDesc,
    args: &BenchArgs,
    width: u32,
    height: u32,
    method: Method,
    spp: u32,
    seed: u64,
) -> RenderSettings {
    RenderSettings {
        width,
        height,
        spp,
        seed,
        threads: args.threads,
        integrator: method.kind,
        step: method.step,
        volume_samples: method.volume_samples,
        ..desc.settings
    }
}

pub(crate) fn measure(
    desc: &SceneDesc,
    args: &BenchArgs,
    width: u32,
    height: u32,
    method: Method,
    ladder: &[u32],
    reference: &Image,
) -> Result<Vec<Point>> {
    let mut curve: Vec<Point> = Vec::new();
    for &spp in ladder {
        // Enough once the curve is far below every target or too slow.
        if curve
            .last()
            .is_some_and(|p| p.seconds > args.max_seconds || p.rel_mse < 2e-4)
        {
            break;
        }
        let s = settings(desc, args, width, height, method, spp, 1);
        let mut times = Vec::new();
        let mut image = None;
        for _ in 0..args.runs.max(1) {
            let r = tyndall::render(&crate::build_scene(desc)?, &s, &|_| {})?;
            times.push(r.stats.elapsed);
            image = Some(r.image);
        }
        let image = image.expect("at least one run");
        curve.push(Point {
            spp,
            seconds: median(&mut times).as_secs_f64(),
            rel_mse: relative_mse(&image, reference),
            worst_share: error_concentration(&image, reference, 0.001),
        });
    }
    Ok(curve)
}

pub(crate) fn median(times: &mut [Duration]) -> Duration {
    times.sort();
    times[times.len() / 2]
}

/// A long `single` render, cached by scene text, size and sample count.
pub(crate) fn long_render(
    desc: &SceneDesc,
    args: &BenchArgs,
    key: &str,
    width: u32,
    height: u32,
    spp: u32,
    method: Method,
) -> Result<Image> {
    let path = args.cache.join(format!(
        "{key}-{}-{width}x{height}-{spp}spp-{:016x}.exr",
        method.kind.name(),
        scene_fingerprint(desc, width, height)
    ));
    if let Ok(image) = read_exr(&path) {
        return Ok(image);
    }
    eprintln!("rendering the reference {} (once; cached)…", path.display());
    let s = settings(desc, args, width, height, method, spp, 1000);
    let r = tyndall::render(&crate::build_scene(desc)?, &s, &|_| {})?;
    std::fs::create_dir_all(&args.cache)
        .with_context(|| format!("creating {}", args.cache.display()))?;
    tyndall_image::write_image(&r.image, &path, 0.0)?;
    Ok(r.image)
}

/// Identifies what a cached reference was rendered from: the scene's
/// geometry, lights and fog as printed, and the size.
fn scene_fingerprint(desc: &SceneDesc, width: u32, height: u32) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    format!(
        "{:?}{:?}{:?}{:?}{:?}{:?}",
        desc.camera.value,
        desc.materials.iter().map(|m| m.value).collect::<Vec<_>>(),
        desc.shapes
            .iter()
            .map(|s| (&s.shapes, s.material))
            .collect::<Vec<_>>(),
        desc.lights
            .iter()
            .map(|l| l.value.clone())
            .collect::<Vec<_>>(),
        desc.fog.as_ref().map(|f| f.value),
        desc.media
            .iter()
            .map(|m| (m.sigma_t, m.albedo, m.phase, &m.density, &m.region))
            .collect::<Vec<_>>(),
    )
    .hash(&mut h);
    (width, height, env!("CARGO_PKG_VERSION")).hash(&mut h);
    h.finish()
}

pub(crate) fn print_curve(method: &Method, curve: &[Point]) {
    println!(
        "{}:\n\n| spp | time (s) | relMSE | error in worst 0.1% of pixels |\n|---:|---:|---:|---:|",
        method.label()
    );
    for p in curve {
        println!(
            "| {} | {:.3} | {:.3e} | {:.1}% |",
            p.spp,
            p.seconds,
            p.rel_mse,
            100.0 * p.worst_share
        );
    }
    println!();
}

/// How long a curve takes to reach a target error.
#[derive(Clone, Copy, Debug, PartialEq)]
enum TimeToError {
    /// Interpolated log-log between the two points around the target.
    Seconds(f64),
    /// The first point (1 spp) is already below the target: at most this.
    AtMost(f64),
    /// Not reached within the curve.
    NotReached,
}

fn time_to_error(curve: &[Point], target: f64) -> TimeToError {
    let Some(first) = curve.first() else {
        return TimeToError::NotReached;
    };
    if first.rel_mse <= target {
        return TimeToError::AtMost(first.seconds);
    }
    curve
        .windows(2)
        .find(|w| w[1].rel_mse <= target)
        .map_or(TimeToError::NotReached, |w| {
            let (a, b) = (w[0], w[1]);
            let f = (target.ln() - a.rel_mse.ln()) / (b.rel_mse.ln() - a.rel_mse.ln());
            TimeToError::Seconds((a.seconds.ln() + f * (b.seconds.ln() - a.seconds.ln())).exp())
        })
}

pub(crate) fn report_time_to_error(curves: &[(Method, Vec<Point>)], targets: &[f64]) {
    for &target in targets {
        println!("Time to relMSE {target:.0e}:\n");
        let mut best_march: Option<(f64, String)> = None;
        let mut single = None;
        for (method, curve) in curves {
            let t = match time_to_error(curve, target) {
                TimeToError::Seconds(t) => {
                    println!("- {}: {t:.3} s", method.label());
                    t
                }
                TimeToError::AtMost(t) => {
                    println!("- {}: ≤ {t:.3} s (reached at 1 spp)", method.label());
                    continue;
                }
                TimeToError::NotReached => {
                    let best = curve
                        .iter()
                        .map(|p| p.rel_mse)
                        .fold(f64::INFINITY, f64::min);
                    println!("- {}: not reached (best {best:.3e})", method.label());
                    continue;
                }
            };
            match method.kind {
                IntegratorKind::Single if method.volume_samples == DEFAULT_VOLUME_SAMPLES => {
                    single = Some(t)
                }
                IntegratorKind::Single | IntegratorKind::Volpath => {}
                IntegratorKind::March => {
                    if best_march.as_ref().is_none_or(|(b, _)| t < *b) {
                        best_march = Some((t, method.label()));
                    }
                }
            }
        }
        if let (Some(s), Some((m, label))) = (single, best_march) {
            println!(
                "\n`single` (default) / best `march` ({label}): {:.2}",
                s / m
            );
        }
        println!();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_time_log_log() {
        // error ∝ 1/time: 1e-2 at 1 s, 1e-3 at 10 s → 3.16e-3 at 3.16 s.
        let curve = [
            Point {
                spp: 1,
                seconds: 1.0,
                rel_mse: 1e-2,
                worst_share: 0.0,
            },
            Point {
                spp: 10,
                seconds: 10.0,
                rel_mse: 1e-3,
                worst_share: 0.0,
            },
        ];
        let TimeToError::Seconds(t) = time_to_error(&curve, 10f64.powf(-2.5)) else {
            panic!()
        };
        assert!((t - 10f64.sqrt()).abs() < 1e-9);
        assert_eq!(time_to_error(&curve, 1e-4), TimeToError::NotReached);
        assert_eq!(time_to_error(&curve, 2e-2), TimeToError::AtMost(1.0));
    }
}
