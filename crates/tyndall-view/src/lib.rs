//! `tyndall view`: the GPU ray march (`tyndall-gpu`) live in a window,
//! with an orbit/fly camera, and sliders (an egui panel) and keys for the
//! fog, the march step, the lights, the glass model and the exposure.
//!
//! # Design
//!
//! - **A CPU framebuffer, not a GPU surface.** Each frame the GPU's
//!   running mean is read back ([`tyndall_gpu::GpuMarch::display_image`]:
//!   the march's in-scattered light filtered over its interleaving tile
//!   while the image is young),
//!   tone-mapped on the CPU exactly as the PNG writer does
//!   (`2^exposure`, clamp, sRGB, 8 bits: [`framebuffer::tone_map`]) and
//!   shown through softbuffer in a winit window. This works wherever a
//!   window can be opened — on lavapipe, under Xvfb in CI, over plain X11
//!   forwarding — because it needs no Vulkan surface or present support
//!   (lavapipe under Xvfb does offer a surface, it turns out: presenting
//!   from the GPU is docs/viewer.md's next step). The cost is the readback (16 bytes
//!   a pixel copied to the host and divided by the frame count) and the
//!   display (tone map, copy, present), both measured every frame and
//!   shown in the title. Measured on lavapipe (2 shared cores, fig. 7):
//!   readback 0.1–0.3 ms at 96×54 and 160×90, 0.4–0.8 ms at 320×180,
//!   4.4–7.1 ms at 640×360 (display 1.8–2.8 ms there) — under 1 % of
//!   lavapipe's frame (0.25 s, 2.2 s and 1.0 s with step 1). Both grow
//!   with the pixel count: at 1920×1080 about 9× the 640×360 figures,
//!   ≈ 40–60 ms + 15–25 ms, which would bound a real GPU to ~15 fps;
//!   there, presenting a wgpu texture tone-mapped in a shader (a second
//!   copy of the PNG writer's tone curve) is the way past it.
//! - **Accumulate while still, update in place on change.** Every
//!   displayed frame adds one GPU frame (own film and march jitter) to
//!   the mean, so a still view converges to the CPU `march` image. Any
//!   change to the scene or camera marks the view dirty; the next redraw
//!   builds the runtime scene from the description and updates the
//!   [`tyndall_gpu::GpuMarch`] in place ([`tyndall_gpu::GpuMarch::update`]:
//!   the changed uniforms and arrays written, the sum cleared, the shadow
//!   maps of a light that moved rendered again, pipelines kept), then
//!   renders its first frame, so a change is on screen in the next frame.
//!   The restart time and the time from the input's arrival to that
//!   frame's present are printed (`input to frame`). Measured on
//!   lavapipe under Xvfb (2 shared cores, keys sent by `xdotool`, 96×54;
//!   docs/viewer.md has the table): the restart went from 52–260 ms (a
//!   new `GpuMarch`) to 0.1–0.2 ms, and input to frame on fig. 7 from
//!   0.29–0.44 s to 21–52 ms, one frame in flight plus the next at a
//!   steady 21–48 ms a frame. With `--visibility maps` a turned spot
//!   renders its one map face again (0.6–0.8 s on lavapipe at 512²)
//!   where every change rebuilt all maps before (4.7–6.1 s).
//! - **Sliders and keys over one state.** The [`panel`] (egui 0.37,
//!   egui-winit, egui-wgpu) has a slider per control; keys
//!   ([`keys::KEY_TABLE`]) step the same values. Both go through
//!   [`controls::LiveScene::set`], the one place the ranges are kept.
//!   egui draws into an offscreen texture on the march's own wgpu device,
//!   which is read back and composited over the tone-mapped framebuffer
//!   ([`framebuffer::composite_over`]): the window still needs no Vulkan
//!   surface, and screenshots (`P`, `--screenshot`) stay the render
//!   alone. `H` hides the panel. egui-wgpu needs Rust 1.95, so this crate
//!   declares `rust-version = "1.95"` (the workspace: 1.87).
//! - **`R`** shows a progressive CPU render (`tyndall::render` with the
//!   view's integrator, 1, 2, 4, … spp) of the same view, computed on a
//!   background thread ([`cpu_preview`]).
//!
//! The view starts with `march`, whatever integrator the scene names, on
//! a 4×4 interleaving tile unless the scene (interleave > 1) or `--interleave` sets one
//! (on the GPU the tile shares out the march's lattice, 1/16 of it per
//! pixel and frame: crates/tyndall-gpu/src/lib.rs); `I` (or the panel)
//! switches to the GPU's `single`, unbiased interleaved equiangular
//! single scattering, for physical albedos.

pub mod accumulator;
mod app;
pub mod controls;
pub mod cpu_preview;
pub mod framebuffer;
pub mod keys;
pub mod orbit;
pub mod panel;

use anyhow::{Context, Result};
use std::path::PathBuf;
use tyndall::SceneDesc;

/// What `tyndall view` was asked for.
pub struct ViewOptions {
    /// The scene with the command line's overrides applied.
    pub desc: SceneDesc,
    /// Stop after this many GPU frames (for CI).
    pub frames: Option<u32>,
    /// With `frames`: write the image on screen here before exiting.
    pub screenshot: Option<PathBuf>,
    /// Start with the progressive CPU render (`Some(true)`) or the GPU's
    /// (`Some(false)`); `None`: the CPU where the only adapter is a
    /// software one (on lavapipe the CPU renderer is the faster), else the
    /// GPU.
    pub cpu: Option<bool>,
    /// Denoise the CPU render while it is young (Open Image Denoise).
    pub denoise: bool,
}

/// Opens the GPU and the window and runs until the window closes (or
/// `frames` frames are done).
pub fn run(options: ViewOptions) -> Result<()> {
    let ViewOptions {
        desc,
        frames,
        screenshot,
        cpu,
        denoise,
    } = options;
    let denoiser = match denoise {
        true => Some(std::sync::Arc::new(
            tyndall_denoise::Denoiser::find().context("--denoise")?,
        )),
        false => None,
    };
    // The scene as the view renders it (the march at first), then the
    // GPU and its upload: their errors need no window.
    let live = controls::LiveScene::new(desc);
    let accumulator = accumulator::Accumulator::new(&live.desc)?;
    eprintln!(
        "GPU: {} (scene uploaded in {:.1} ms)",
        accumulator.adapter(),
        accumulator.restart_time.as_secs_f64() * 1e3
    );
    let event_loop = winit::event_loop::EventLoop::new()
        .context("cannot open a window: no display (set DISPLAY, or run under xvfb-run)")?;
    let cpu = match cpu {
        Some(cpu) => cpu,
        None => accumulator.is_software(),
    };
    if cpu {
        eprintln!("rendering on the CPU (`R` switches to the GPU)");
    } else if denoiser.is_some() {
        anyhow::bail!(
            "--denoise: only the CPU view is denoised, and this view starts on the GPU ({}): add --cpu",
            accumulator.adapter()
        );
    }
    let mut app = app::App::new(live, frames, screenshot, accumulator, cpu, denoiser);
    event_loop.run_app(&mut app)?;
    match app.error.take() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
