//! `tyndall bench --only maps`: shadow maps against shadow rays for the
//! ray march — time per frame, the difference between the images, and how
//! time grows with the number of march steps and of lights.

use super::{BenchArgs, Method, median, settings};
use anyhow::Result;
use glam::Vec3;
use tyndall::SceneDesc;
use tyndall::description::{LightDesc, Origin};
use tyndall::lights::SpotLight;
use tyndall::settings::{DEFAULT_MAP_RESOLUTION, VisibilityMode};
use tyndall::{Image, RenderSettings};
use tyndall_image::metrics::relative_mse;
use tyndall_load::{demo, native};

const MAPS: VisibilityMode = VisibilityMode::Maps {
    resolution: DEFAULT_MAP_RESOLUTION,
};

/// Median time (s) and the last image of `args.runs` renders.
fn timed(desc: &SceneDesc, s: &RenderSettings, runs: usize) -> Result<(f64, Image)> {
    let mut times = Vec::new();
    let mut image = None;
    for _ in 0..runs.max(1) {
        let r = tyndall::render(&crate::build_scene(desc)?, s, &|_| {})?;
        times.push(r.stats.elapsed);
        image = Some(r.image);
    }
    Ok((median(&mut times).as_secs_f64(), image.expect("one run")))
}

pub fn run(args: &BenchArgs) -> Result<()> {
    let (w, h) = if args.quick { (160, 90) } else { (1280, 720) };
    println!(
        "## Shadow maps against shadow rays (`march`, 1 spp, {w}×{h}, maps {DEFAULT_MAP_RESOLUTION}² per face)\n"
    );
    println!("Both renders use the same seed, so they differ only where map visibility does.\n");
    println!(
        "| scene | step | rays (s) | maps (s) | speed-up | relMSE maps vs rays |\n|---|---:|---:|---:|---:|---:|"
    );
    let demo = demo::load()?;
    let fig7 = native::load(&args.scenes.join("fig07-spot-sphere.toml"))?;
    let steps: &[f32] = if args.quick {
        &[0.2]
    } else {
        &[0.4, 0.2, 0.1, 0.05]
    };
    for (name, desc) in [("demo", &demo), ("fig. 7", &fig7)] {
        for &step in steps {
            let base = settings(desc, args, w, h, Method::march(step), 1, 1);
            let (t_rays, rays) = timed(desc, &base, args.runs)?;
            let (t_maps, maps) = timed(
                desc,
                &RenderSettings {
                    visibility: MAPS,
                    ..base
                },
                args.runs,
            )?;
            println!(
                "| {name} | {step} | {t_rays:.3} | {t_maps:.3} | {:.2}× | {:.3e} |",
                t_rays / t_maps,
                relative_mse(&maps, &rays)
            );
        }
    }
    println!();

    println!("### Time against the number of lights (fig. 7 with n spots, step 0.1, {w}×{h})\n");
    println!("| lights | rays (s) | maps (s) |\n|---:|---:|---:|");
    let counts: &[usize] = if args.quick { &[1, 2] } else { &[1, 2, 4, 8] };
    for &n in counts {
        let mut desc = native::load(&args.scenes.join("fig07-spot-sphere.toml"))?;
        add_spots(&mut desc, n);
        let base = settings(&desc, args, w, h, Method::march(0.1), 1, 1);
        let (t_rays, _) = timed(&desc, &base, args.runs)?;
        let (t_maps, _) = timed(
            &desc,
            &RenderSettings {
                visibility: MAPS,
                ..base
            },
            args.runs,
        )?;
        println!("| {n} | {t_rays:.3} | {t_maps:.3} |");
    }
    println!();
    Ok(())
}

/// Replaces the scene's lights by `n` spots on a circle above the
/// sphere, aimed at it, with the total intensity of the original one.
fn add_spots(desc: &mut SceneDesc, n: usize) {
    let Some(LightDesc::Spot(original)) = desc.lights.first().map(|l| l.value.clone()) else {
        return;
    };
    desc.lights.clear();
    for i in 0..n {
        let angle = std::f32::consts::TAU * i as f32 / n as f32;
        let offset = if n == 1 {
            Vec3::ZERO
        } else {
            Vec3::new(angle.cos(), 0.0, angle.sin()) * 1.2
        };
        let position = original.position + offset;
        let target = original.position + original.direction * 4.0;
        let spot = SpotLight {
            position,
            direction: (target - position).normalize(),
            intensity: original.intensity / n as f32,
            ..original.clone()
        };
        desc.add_light(LightDesc::Spot(spot), Origin::Code);
    }
}
