//! `tyndall bench --gpu`: frames per second of the GPU march (crate
//! `tyndall-gpu`) at 1280×720 and 1920×1080 on the demo and the fig. 7
//! scene, for march steps giving about 32, 64 and 128 steps along the
//! central camera ray's fog segment.
//!
//! A frame is one sample per pixel: camera ray, march with a shadow-map
//! lookup per step and light (512² texels per face, the CPU's default),
//! direct light. Each point times `args.runs` frames after one untimed
//! warm-up frame and reports the median; the time to build every light's
//! maps (both passes and the offsets between them) is the median of as
//! many rebuilds.

use super::BenchArgs;
use anyhow::{Context, Result};
use std::time::{Duration, Instant};
use tyndall::camera::Camera;
use tyndall::settings::DEFAULT_MAP_RESOLUTION;
use tyndall::{Scene, SceneDesc};
use tyndall_gpu::{Gpu, GpuMarch, GpuVisibility, MarchSettings};
use tyndall_load::{demo, native};

/// The fog segment's length along the central camera ray (to its first
/// hit), which the step count divides; `None` without fog there.
fn central_fog_length(scene: &Scene) -> Option<f32> {
    let camera = Camera::new(scene.camera(), 2, 2);
    let ray = camera.ray(glam::Vec2::ONE);
    let t_hit = scene
        .geometry()
        .intersect(&ray, f32::INFINITY)
        .map_or(f32::INFINITY, |h| h.t);
    let fog = scene.fog()?;
    let (a, b) = fog.interval(&ray, 0.0, t_hit)?;
    let b = b.min(a + 9.21 / fog.sigma_t.max(1e-6));
    Some(b - a)
}

pub fn run(args: &BenchArgs) -> Result<()> {
    let gpu = Gpu::new()?;
    println!("## GPU march\n\nAdapter: {}\n", gpu.adapter);
    let fig07 = args.scenes.join("fig07-spot-sphere.toml");
    let cases: [(&str, SceneDesc); 2] = [
        ("demo", demo::load()?),
        (
            "fig07-spot-sphere",
            native::load(&fig07).with_context(|| fig07.display().to_string())?,
        ),
    ];
    let sizes: &[(u32, u32)] = if args.quick {
        &[(160, 90)]
    } else {
        &[(1280, 720), (1920, 1080)]
    };
    println!("| scene | size | steps (step) | frame time | frames/s | maps built in |");
    println!("|---|---|---|---|---|---|");
    for (name, desc) in &cases {
        let scene = Scene::build(desc)?;
        let length = central_fog_length(&scene).context("the scene has no fog in view")?;
        for &(width, height) in sizes {
            for steps in [32u32, 64, 128] {
                let settings = MarchSettings {
                    width,
                    height,
                    step: length / steps as f32,
                    interleave: desc.settings.interleave,
                    max_bounces: desc.settings.max_bounces,
                    seed: 1,
                    visibility: GpuVisibility::Maps {
                        resolution: DEFAULT_MAP_RESOLUTION,
                    },
                };
                let mut march = GpuMarch::new(&gpu, &scene, &settings)?;
                march.submit_frames(&gpu, 1);
                march.wait(&gpu)?;
                let mut times: Vec<Duration> = (0..args.runs.max(1))
                    .map(|_| {
                        let start = Instant::now();
                        march.submit_frames(&gpu, 1);
                        march.wait(&gpu).map(|()| start.elapsed())
                    })
                    .collect::<Result<_, _>>()?;
                let frame = super::median(&mut times).as_secs_f64();
                let mut builds: Vec<Duration> = (0..args.runs.max(1))
                    .map(|_| {
                        let start = Instant::now();
                        march.build_maps(&gpu).map(|()| start.elapsed())
                    })
                    .collect::<Result<_, _>>()?;
                let build = super::median(&mut builds).as_secs_f64();
                println!(
                    "| {name} | {width}×{height} | {steps} ({:.4}) | {:.1} ms | {:.2} | {:.1} ms |",
                    settings.step,
                    frame * 1e3,
                    1.0 / frame,
                    build * 1e3
                );
            }
        }
    }
    Ok(())
}
