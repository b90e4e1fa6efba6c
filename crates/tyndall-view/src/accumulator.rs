//! The GPU side of the viewer: the scene as the description now says,
//! uploaded into a [`GpuMarch`], one frame added per displayed frame and
//! the running mean read back (its in-scattered light filtered over the
//! interleaving tile while the image is young:
//! `GpuMarch::display_image`). Any change to the scene restarts it: the
//! `GpuMarch` is updated in place (changed uniforms and arrays written,
//! the maps of a moved light rendered again, the sum cleared), whose cost
//! is measured and reported as the restart time.

use anyhow::{Context, Result};
use std::time::{Duration, Instant};
use tyndall::{Image, Scene, SceneDesc};
use tyndall_gpu::{Gpu, GpuMarch, MarchSettings};

/// The runtime scene of a description, its settings checked.
pub fn build_scene(desc: &SceneDesc) -> Result<Scene> {
    desc.settings
        .check_ranges()
        .map_err(|e| anyhow::anyhow!("{}: {e}", e.setting))?;
    let scene = Scene::build(desc).map_err(|e| anyhow::anyhow!("{e}"))?;
    desc.settings.validate(&scene)?;
    Ok(scene)
}

/// Frames accumulated on the GPU for the current view.
pub struct Accumulator {
    gpu: Gpu,
    march: GpuMarch,
    /// How long the last (re)start took: scene build and upload (at the
    /// start also pipelines), shadow maps.
    pub restart_time: Duration,
}

/// Timings of one displayed frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameTimes {
    /// Submitting the frame and waiting for the GPU.
    pub render: Duration,
    /// Filtering the young image over the interleaving tile (on the GPU),
    /// copying it to the host and dividing by the frame count.
    pub readback: Duration,
}

impl Accumulator {
    /// Opens the GPU and uploads `desc`.
    pub fn new(desc: &SceneDesc) -> Result<Self> {
        let gpu = Gpu::new()?;
        let start = Instant::now();
        let march = Self::upload(&gpu, desc)?;
        Ok(Self {
            gpu,
            march,
            restart_time: start.elapsed(),
        })
    }

    fn upload(gpu: &Gpu, desc: &SceneDesc) -> Result<GpuMarch> {
        let scene = build_scene(desc)?;
        GpuMarch::new(gpu, &scene, &MarchSettings::from(&desc.settings))
            .context("the GPU cannot render this view")
    }

    /// The GPU the march runs on (the control panel draws with it too).
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// The adapter in words.
    pub fn adapter(&self) -> String {
        self.gpu.adapter.to_string()
    }

    /// Whether the adapter is a software renderer (lavapipe), on which
    /// the CPU renderer is faster than the GPU path.
    pub fn is_software(&self) -> bool {
        self.gpu.adapter.device_type == format!("{:?}", wgpu::DeviceType::Cpu)
    }

    /// Starts accumulating anew for `desc`. On an error (a setting the GPU
    /// refuses) the previous view stays.
    ///
    /// The march is updated in place ([`GpuMarch::update`]): only the
    /// uniforms and arrays that changed are written and only the shadow
    /// maps of a light that moved are rendered again; pipelines are kept.
    pub fn restart(&mut self, desc: &SceneDesc) -> Result<()> {
        let start = Instant::now();
        let scene = build_scene(desc)?;
        self.march
            .update(&self.gpu, &scene, &MarchSettings::from(&desc.settings))
            .context("the GPU cannot render this view")?;
        self.restart_time = start.elapsed();
        Ok(())
    }

    /// Frames in the current mean.
    pub fn frames(&self) -> u32 {
        self.march.frames()
    }

    /// Adds one frame and returns the mean so far, with its timings.
    pub fn next_frame(&mut self) -> Result<(Image, FrameTimes)> {
        let start = Instant::now();
        self.march.submit_frames(&self.gpu, 1);
        self.march.wait(&self.gpu)?;
        let rendered = Instant::now();
        let image = self.march.display_image(&self.gpu)?;
        Ok((
            image,
            FrameTimes {
                render: rendered - start,
                readback: rendered.elapsed(),
            },
        ))
    }
}
