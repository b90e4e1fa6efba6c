//! `tyndall bench --gpu`: frames per second of the GPU's single
//! scattering (crate `tyndall-gpu`) at 1280×720 and 1920×1080 on the demo,
//! the fig. 7 scene and the foggy Cornell box (an area light, which has no
//! map and is seen through a shadow ray per step): the march, for steps giving about 32, 64 and 128
//! steps along the central camera ray's fog segment, with every pixel
//! evaluating every step and with a 4×4 interleaving tile sharing the
//! steps out (1/16 of them per pixel and frame, as the viewer runs it);
//! and interleaved equiangular single scattering (`--integrator single`)
//! with 1 and 8 equiangular samples per light on a 4×4 tile.
//!
//! A frame is one sample per pixel: camera ray, in-scattering with a
//! shadow-map lookup per march step or volume sample and light (512²
//! texels per face, the CPU's default), direct light; for the shared-out
//! march also the filter that the viewer runs on each young frame
//! (`GpuMarch::submit_resolve`). Each point times `args.runs` frames after one untimed
//! warm-up frame and reports the median; the time to build every light's
//! maps (both passes and the 4-byte layer count read back between them)
//! is the median of as many rebuilds.

use super::BenchArgs;
use anyhow::{Context, Result};
use std::time::{Duration, Instant};
use tyndall::camera::Camera;
use tyndall::ray_march::MAX_OPTICAL_DEPTH;
use tyndall::settings::{DEFAULT_MAP_RESOLUTION, DEFAULT_VOLUME_SAMPLES};
use tyndall::{Scene, SceneDesc};
use tyndall_gpu::{Gpu, GpuMarch, GpuVisibility, InScattering, MarchSettings};
use tyndall_load::{demo, native};

/// The fog segment's length along the central camera ray (to its first
/// hit), which the step count divides; `None` without fog there.
fn central_fog_length(scene: &Scene) -> Option<f32> {
    let camera = Camera::new(scene.camera(), 2, 2);
    let ray = camera.ray(glam::Vec2::ONE, glam::Vec2::ZERO);
    let t_hit = scene
        .geometry()
        .intersect(&ray, f32::INFINITY)
        .map_or(f32::INFINITY, |h| h.t);
    let fog = scene.fog()?;
    let (a, b) = fog.interval(&ray, 0.0, t_hit)?;
    let b = b.min(a + MAX_OPTICAL_DEPTH / fog.sigma_t.max(1e-6));
    Some(b - a)
}

/// Side of the interleaving tile of the single-scattering rows and the
/// shared-out march rows (the viewer's).
const TILE: u32 = 4;

/// Equiangular samples per light and segment of the single-scattering
/// rows: one, and the CPU `single`'s default.
const SINGLE_VOLUME_SAMPLES: [u32; 2] = [1, DEFAULT_VOLUME_SAMPLES];

pub fn run(args: &BenchArgs) -> Result<()> {
    let gpu = Gpu::new()?;
    println!(
        "## GPU march and single scattering\n\nAdapter: {}\n",
        gpu.adapter
    );
    let load = |file: &str| -> Result<SceneDesc> {
        let path = args.scenes.join(file);
        native::load(&path).with_context(|| path.display().to_string())
    };
    let cases: [(&str, SceneDesc); 3] = [
        ("demo", demo::load()?),
        ("fig07-spot-sphere", load("fig07-spot-sphere.toml")?),
        ("cornell-fog", load("cornell-fog.toml")?),
    ];
    let sizes: &[(u32, u32)] = if args.quick {
        &[(160, 90)]
    } else {
        &[(1280, 720), (1920, 1080)]
    };
    println!(
        "| scene | size | estimator | samples along the ray | frame time | frames/s | maps built in |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (name, desc) in &cases {
        let scene = Scene::build(desc)?;
        let length = central_fog_length(&scene).context("the scene has no fog in view")?;
        for &(width, height) in sizes {
            let base = MarchSettings {
                width,
                height,
                step: length / 64.0,
                interleave: desc.settings.interleave,
                max_bounces: desc.settings.max_bounces,
                seed: 1,
                visibility: GpuVisibility::Maps {
                    resolution: DEFAULT_MAP_RESOLUTION,
                },
                in_scattering: InScattering::March,
            };
            let mut rows: Vec<(MarchSettings, &str, String)> = Vec::new();
            for interleave in [1, TILE] {
                for steps in [32u32, 64, 128] {
                    let step = length / steps as f32;
                    let settings = MarchSettings {
                        step,
                        interleave,
                        ..base
                    };
                    let label = if interleave == 1 {
                        format!("{steps} steps ({step:.4})")
                    } else {
                        format!(
                            "{steps} steps ({step:.4}) shared out over {TILE}×{TILE}: {} a pixel",
                            steps / (TILE * TILE)
                        )
                    };
                    rows.push((settings, "march", label));
                }
            }
            for volume_samples in SINGLE_VOLUME_SAMPLES {
                let settings = MarchSettings {
                    interleave: TILE,
                    in_scattering: InScattering::Single { volume_samples },
                    ..base
                };
                let label = format!(
                    "{volume_samples} equiangular/light + 1 distance, {TILE}×{TILE} interleaved"
                );
                rows.push((settings, "single", label));
            }
            // Only point, spot and directional lights have maps.
            let has_maps = scene.lights().iter().any(|l| l.is_delta());
            for (settings, estimator, samples) in rows {
                let (frame, build) = time_frames_and_maps(&gpu, &scene, &settings, args.runs)?;
                let build = if has_maps {
                    format!("{:.1} ms", build * 1e3)
                } else {
                    "no map (area light)".to_string()
                };
                println!(
                    "| {name} | {width}×{height} | {estimator} | {samples} | {:.1} ms | {:.2} | {build} |",
                    frame * 1e3,
                    1.0 / frame,
                );
            }
        }
    }
    Ok(())
}

/// The median seconds of a frame and of building every light's maps, over
/// `runs` each, after one untimed warm-up frame.
fn time_frames_and_maps(
    gpu: &Gpu,
    scene: &Scene,
    settings: &MarchSettings,
    runs: usize,
) -> Result<(f64, f64)> {
    let mut march = GpuMarch::new(gpu, scene, settings)?;
    march.submit_frames(gpu, 1);
    march.wait(gpu)?;
    let mut times: Vec<Duration> = (0..runs.max(1))
        .map(|_| {
            let start = Instant::now();
            march.submit_frames(gpu, 1);
            march.submit_resolve(gpu);
            march.wait(gpu).map(|()| start.elapsed())
        })
        .collect::<Result<_, _>>()?;
    let frame = super::median(&mut times).as_secs_f64();
    let mut builds: Vec<Duration> = (0..runs.max(1))
        .map(|_| {
            let start = Instant::now();
            march.build_maps(gpu).map(|()| start.elapsed())
        })
        .collect::<Result<_, _>>()?;
    Ok((frame, super::median(&mut builds).as_secs_f64()))
}
