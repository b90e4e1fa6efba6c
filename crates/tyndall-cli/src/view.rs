//! `tyndall view SCENE`: the scene live in a window (crate
//! `tyndall-view`): the GPU march accumulating while the view is still,
//! an orbit/fly camera and keyboard controls. `--frames N --screenshot
//! OUT.png` renders N frames, saves the window's image and exits (CI).

use crate::{Overrides, load_scene, refuse_flags};
use anyhow::{Result, bail};
use clap::Args;
use std::path::PathBuf;
use tyndall::IntegratorKind;
use tyndall_image::ImageFormat;
use tyndall_view::ViewOptions;

#[derive(Args)]
#[command(after_help = format!("Controls:\n{}", tyndall_view::keys::KEY_TABLE))]
pub struct ViewArgs {
    /// Scene file (.toml, legacy .obj, .gltf/.glb); without one, the built-in demo.
    scene: Option<PathBuf>,
    #[command(flatten)]
    overrides: Overrides,
    /// Load legacy .obj quads as two-sided.
    #[arg(long)]
    two_sided: bool,
    /// The frame of the scene's file sequences (`####` in a [[media]] `file`).
    #[arg(long)]
    frame: Option<u32>,
    /// Render this many GPU frames, then exit (with --screenshot: save first).
    #[arg(long)]
    frames: Option<u32>,
    /// With --frames: write the window's image (PNG, exposure applied) here.
    #[arg(long, requires = "frames")]
    screenshot: Option<PathBuf>,
    /// Start with the progressive CPU render (one sample per pixel per pass;
    /// after N passes the image of `tyndall render --spp N`). The default
    /// where the only GPU is a software one (lavapipe). With --frames, N counts passes.
    #[arg(long, conflicts_with = "gpu")]
    cpu: bool,
    /// Start on the GPU even where it is a software one.
    #[arg(long)]
    gpu: bool,
    /// Denoise the CPU render while it is young (Open Image Denoise, loaded at
    /// run time as for `render --denoise`): passes 1, 2, 4, …, 64, then every 32nd.
    /// The GPU view is not denoised: with a view that starts on the GPU it is an error.
    #[arg(long)]
    denoise: bool,
}

/// The interleaving tile of a view whose scene has none (interleave 1,
/// the default) and whose command line sets none: on the GPU a 4×4 tile
/// shares out the march's lattice, 1/16 of it per pixel and frame, and
/// the view filters the tile's cells back together while the image is
/// young (`GpuMarch::display_image`).
const VIEW_INTERLEAVE: u32 = 4;

/// Opens the viewer on `args.scene`.
pub fn run(args: ViewArgs) -> Result<()> {
    let o = &args.overrides;
    refuse_flags(
        "view",
        &[
            (
                o.spp.is_some(),
                "--spp",
                "the view accumulates until it changes (CI: --frames)",
            ),
            (
                o.max_depth.is_some(),
                "--max-depth",
                "the view renders `march` and `single`, which have no path depth",
            ),
            (
                o.volume_samples.is_some(),
                "--volume-samples",
                "the view starts with only `march` (`I` switches to `single` with the scene's samples)",
            ),
        ],
    )?;
    if let Some(kind) = o.integrator
        && kind != IntegratorKind::March
    {
        bail!(
            "--integrator {}: the view starts with only `march` (`I` switches to `single`)",
            kind.name()
        );
    }
    if let Some(path) = &args.screenshot
        && ImageFormat::from_path(path)? != ImageFormat::Png
    {
        bail!("{}: the screenshot is a PNG (.png)", path.display());
    }
    if args.frames == Some(0) {
        bail!("--frames must be at least 1");
    }
    let mut desc = load_scene(args.scene.as_deref(), args.two_sided, args.frame)?;
    if desc.settings.interleave == 1 {
        // What makes the march real-time: the tile shares out its lattice.
        desc.settings.interleave = VIEW_INTERLEAVE;
    }
    args.overrides.apply(&mut desc)?;
    desc.settings
        .check_ranges()
        .map_err(|e| anyhow::anyhow!("--{}: {e}", e.setting.replace('_', "-")))?;
    for w in std::mem::take(&mut desc.warnings) {
        eprintln!("warning: {w}");
    }
    tyndall_view::run(ViewOptions {
        desc,
        frames: args.frames,
        screenshot: args.screenshot,
        cpu: match (args.cpu, args.gpu) {
            (true, _) => Some(true),
            (_, true) => Some(false),
            _ => None,
        },
        denoise: args.denoise,
    })
}
