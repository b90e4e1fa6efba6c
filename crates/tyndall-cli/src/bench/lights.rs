//! `tyndall bench --only lights`: many lights (issue 23). The stage rig
//! (scenes/stage-rig.toml, written by scenes/rig/make_stage_rig.py) with
//! 1, 64 and 1024 gobo spots: the time per sample of `single` and
//! `volpath` when every estimate visits every light and when the light
//! tree chooses one; then, on the 64-spot rig, the time to relative MSE
//! of both against a long render that visits every light (the tree's
//! image is tested unbiased against that sampling in
//! crates/tyndall-tests/tests/many_lights.rs).

use super::{
    BenchArgs, Method, long_render, measure, median, print_curve, report_time_to_error, settings,
};
use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::process::Command;
use tyndall::SceneDesc;
use tyndall::lights::LightSampling;
use tyndall_load::native;

pub fn run(args: &BenchArgs) -> Result<()> {
    let (w, h) = if args.quick { (64, 36) } else { (160, 90) };
    let spp = if args.quick { 2 } else { 8 };
    println!("## Many lights: the stage rig at {w}×{h}, {spp} spp\n");
    println!(
        "Time per camera sample (µs, wall clock × threads / samples) with every light \
         visited at every estimate (`all`) and with the light tree choosing point and \
         spot lights (`tree`; up to 4 per estimate, splitting where a cluster looms).\n"
    );
    println!(
        "| spots | integrator | all (µs) | tree (µs) | all / tree |\n|---:|---|---:|---:|---:|"
    );
    let threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        as f64;
    let mut per_sample = Vec::new();
    for spots in [1usize, 64, 1024] {
        let desc = rig(args, spots)?;
        for method in [
            Method::single(tyndall::settings::DEFAULT_VOLUME_SAMPLES),
            Method::volpath(),
        ] {
            let mut micros = [0.0; 2];
            for (slot, sampling) in [LightSampling::All, LightSampling::Tree]
                .into_iter()
                .enumerate()
            {
                let desc = SceneDesc {
                    light_sampling: sampling,
                    ..desc.clone()
                };
                let scene = crate::build_scene(&desc)?;
                let s = settings(&desc, args, w, h, method, spp, 1);
                let mut times = Vec::new();
                for _ in 0..args.runs.max(1) {
                    times.push(tyndall::render(&scene, &s, &|_| {})?.stats.elapsed);
                }
                let samples = f64::from(w * h * spp);
                micros[slot] = median(&mut times).as_secs_f64() * threads / samples * 1e6;
            }
            println!(
                "| {spots} | {} | {:.2} | {:.2} | {:.1} |",
                method.kind.name(),
                micros[0],
                micros[1],
                micros[0] / micros[1]
            );
            per_sample.push((spots, method.kind.name(), micros[1]));
        }
    }
    println!();
    for kind in ["single", "volpath"] {
        let of = |n: usize| {
            per_sample
                .iter()
                .find(|p| p.0 == n && p.1 == kind)
                .map(|p| p.2)
        };
        if let (Some(one), Some(many), Some(most)) = (of(1), of(64), of(1024)) {
            println!(
                "`{kind}` with the tree: 64 spots cost {:.1}× a sample of 1 spot, 1024 spots {:.1}×.\n",
                many / one,
                most / one
            );
        }
    }

    let desc = rig(args, 64)?;
    let reference_spp = if args.quick { 32 } else { 1024 };
    let method = Method::volpath();
    let every = SceneDesc {
        light_sampling: LightSampling::All,
        ..desc.clone()
    };
    let reference = long_render(&every, args, "stage-rig-all", w, h, reference_spp, method)?;
    println!(
        "### Time to error on the 64-spot rig, `volpath`\n\nReference: `volpath` visiting every \
         light, {reference_spp} spp, seed 1000 (independent of the seeds below).\n"
    );
    let ladder: &[u32] = if args.quick {
        &[2, 4]
    } else {
        &[4, 8, 16, 32, 64, 128]
    };
    for sampling in [LightSampling::All, LightSampling::Tree] {
        println!("Light sampling `{}`:\n", sampling.name());
        let desc = SceneDesc {
            light_sampling: sampling,
            ..desc.clone()
        };
        let curve = measure(&desc, args, w, h, method, ladder, &reference)?;
        print_curve(&method, &curve);
        report_time_to_error(&[(method, curve)], &[1e-2, 1e-3]);
    }
    Ok(())
}

/// The stage rig with `spots` spots: the repository's 64-spot scene, or
/// one written by its generator into the cache.
fn rig(args: &BenchArgs, spots: usize) -> Result<SceneDesc> {
    if spots == 64 {
        return Ok(native::load(&args.scenes.join("stage-rig.toml"))?);
    }
    let path: PathBuf = args.cache.join(format!("stage-rig-{spots}.toml"));
    if !path.exists() {
        std::fs::create_dir_all(&args.cache)
            .with_context(|| format!("creating {}", args.cache.display()))?;
        generate(&args.scenes.join("rig/make_stage_rig.py"), spots, &path)?;
    }
    Ok(native::load(&path)?)
}

/// Runs the rig's generator (pure Python) for `spots` spots into `out`.
fn generate(script: &Path, spots: usize, out: &Path) -> Result<()> {
    let status = Command::new("python3")
        .arg(script)
        .arg(spots.to_string())
        .arg(out)
        .stdout(std::process::Stdio::null())
        .status()
        .with_context(|| format!("running python3 {}", script.display()))?;
    if !status.success() {
        bail!(
            "{} {spots} {} failed: {status}",
            script.display(),
            out.display()
        );
    }
    Ok(())
}
