//! `tyndall render --gpu`: single scattering on the GPU (crate
//! `tyndall-gpu`) — the paper's ray march (`--integrator march`) or
//! unbiased interleaved equiangular sampling (`--integrator single`) —
//! headless, with the CPU path's flags where they apply. A flag the GPU
//! path cannot honour is an error naming it.

use crate::{Overrides, RenderArgs, load_scene, refuse_flags};
use anyhow::{Context, Result, bail};
use std::path::PathBuf;
use std::time::Instant;
use tyndall::{IntegratorKind, Scene};
use tyndall_gpu::{Gpu, MarchSettings};
use tyndall_load::SceneError;

/// The flags the CPU path has and the GPU path cannot honour, with why.
fn refuse_unsupported_flags(args: &RenderArgs) -> Result<()> {
    let o: &Overrides = &args.overrides;
    refuse_flags(
        "--gpu",
        &[
            (
                args.tile.is_some(),
                "--tile",
                "the GPU renders whole images",
            ),
            (
                args.finishing.aov.is_some(),
                "--aov",
                "the GPU path writes the radiance only",
            ),
            (
                args.finishing.denoise,
                "--denoise",
                "the GPU path keeps no denoising guides",
            ),
            (
                args.samples.is_some(),
                "--samples",
                "the GPU renders whole images",
            ),
            (
                args.checkpoint.is_some(),
                "--checkpoint",
                "GPU renders are not checkpointed",
            ),
            (
                args.time_limit.is_some(),
                "--time-limit",
                "the GPU renders --spp frames",
            ),
            (
                o.threads.is_some(),
                "--threads",
                "the GPU does not use CPU worker threads",
            ),
            (
                o.max_depth.is_some(),
                "--max-depth",
                "the GPU renders only `march` and `single`, which have no path depth",
            ),
        ],
    )?;
    if let Some(kind) = o.integrator
        && !on_gpu(kind)
    {
        bail!(
            "--integrator {}: --gpu renders only `march` and `single`",
            kind.name()
        );
    }
    Ok(())
}

/// Whether the GPU has an estimator for integrator `kind`.
fn on_gpu(kind: IntegratorKind) -> bool {
    matches!(kind, IntegratorKind::March | IntegratorKind::Single)
}

/// Renders `args.scene` on the GPU and writes the image.
pub fn render(args: RenderArgs) -> Result<()> {
    refuse_unsupported_flags(&args)?;
    let mut desc = load_scene(args.scene.as_deref(), args.two_sided, args.frame)?;
    args.overrides.apply(&mut desc)?;
    let output = args
        .output
        .clone()
        .or(desc.output.clone())
        .unwrap_or_else(|| PathBuf::from("tyndall.png"));
    desc.settings
        .check_ranges()
        .map_err(|e| anyhow::anyhow!("--{}: {e}", e.setting.replace('_', "-")))?;
    let settings = desc.settings;
    if !on_gpu(settings.integrator) {
        bail!(
            "--gpu renders only the `march` and `single` integrators; this scene asks for `{}` (add --integrator march or --integrator single)",
            settings.integrator.name()
        );
    }
    if args.overrides.volume_samples.is_some() && settings.integrator == IntegratorKind::March {
        bail!(
            "--volume-samples cannot be used with --gpu and `march`: the march takes no volume samples (they are `single`'s)"
        );
    }
    let loader_warnings = std::mem::take(&mut desc.warnings);
    let scene = Scene::from_desc(desc).map_err(SceneError::from)?;
    settings.validate(&scene)?;
    let output_file = tyndall_image::OutputFile::create(&output)?;
    for w in loader_warnings.into_iter().chain(settings.warnings(&scene)) {
        eprintln!("warning: {w}");
    }
    let gpu = Gpu::new()?;
    let march_settings = MarchSettings::from(&settings);
    let start = Instant::now();
    let image = tyndall_gpu::render(&gpu, &scene, &march_settings, settings.spp)?;
    let seconds = start.elapsed().as_secs_f64();
    output_file
        .finish(&image, settings.exposure)
        .with_context(|| format!("{}: the image could not be written", output.display()))?;
    if !args.quiet {
        eprintln!(
            "{}×{}, {} frames on {} in {:.2} s ({:.1} frames/s); wrote {}",
            settings.width,
            settings.height,
            settings.spp,
            gpu.adapter,
            seconds,
            settings.spp as f64 / seconds,
            output.display()
        );
    }
    Ok(())
}
