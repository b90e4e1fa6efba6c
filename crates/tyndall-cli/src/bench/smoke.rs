//! `tyndall bench --only smoke`: `volpath` on the voxel smoke scene — time
//! to relative MSE, and what the non-uniform density costs against
//! homogeneous media in the same box.

use super::{
    BenchArgs, Method, long_render, measure, median, print_curve, report_time_to_error, settings,
};
use anyhow::{Result, bail};
use glam::UVec3;
use tyndall::Rgb;
use tyndall::SceneDesc;
use tyndall::description::{MediumDesc, Origin, RegionDesc};
use tyndall::media::volume::{Density, Volume};
use tyndall_load::native;

pub fn run(args: &BenchArgs) -> Result<()> {
    let mut desc = native::load(&args.scenes.join("smoke.toml"))?;
    let (w, h, reference_spp) = if args.quick {
        (48, 54, 64)
    } else {
        (240, 270, 2048)
    };
    let ladder: &[u32] = if args.quick {
        &[4, 8]
    } else {
        &[4, 8, 16, 32, 64, 128]
    };
    println!("## volpath on the smoke scene (scenes/smoke.toml) at {w}×{h}\n");
    let method = Method::volpath();
    let reference = long_render(&desc, args, "smoke", w, h, reference_spp, method)?;
    println!(
        "Reference: `volpath`, {reference_spp} spp, seed 1000 (independent of the seeds below).\n"
    );
    let curve = measure(&desc, args, w, h, method, ladder, &reference)?;
    print_curve(&method, &curve);
    report_time_to_error(&[(method, curve)], &[1e-2, 3e-3]);

    // The cost of non-uniformity: the same box filled uniformly, at the
    // same extinction scale and at the grid's mean extinction.
    let scene = crate::build_scene(&desc)?;
    let Some(smoke) = scene.volumes().first() else {
        bail!("scenes/smoke.toml has no volume");
    };
    let (bounds, sigma_t, albedo, phase) =
        (smoke.field_box(), smoke.sigma_t, smoke.albedo, smoke.phase);
    let mean = mean_extinction(smoke);
    let spp = if args.quick { 4 } else { 32 };
    let s = settings(&desc, args, w, h, method, spp, 1);
    let time = |desc: &SceneDesc| -> Result<f64> {
        let scene = crate::build_scene(desc)?;
        let mut times = Vec::new();
        for _ in 0..args.runs.max(1) {
            times.push(tyndall::render(&scene, &s, &|_| {})?.stats.elapsed);
        }
        Ok(median(&mut times).as_secs_f64())
    };
    let grid_time = time(&desc)?;
    let mut uniform = |scale: Rgb| -> Result<f64> {
        desc.media = vec![MediumDesc {
            sigma_t: scale,
            albedo,
            phase,
            density: Density::Uniform,
            region: RegionDesc::Box(bounds),
            emission: None,
            origin: Origin::Code,
        }];
        time(&desc)
    };
    let same_scale = uniform(sigma_t)?;
    let same_mean = uniform(mean)?;
    println!(
        "Cost of the voxel grid against a homogeneous medium in the same box ({spp} spp):\n\n\
         | medium | σt (RGB) | time (s) | grid / this |\n|---|---|---:|---:|"
    );
    let row = |name: &str, sigma: Rgb, t: f64| {
        println!(
            "| {name} | {:.2}, {:.2}, {:.2} | {t:.3} | {:.2} |",
            sigma.x,
            sigma.y,
            sigma.z,
            grid_time / t
        );
    };
    row("voxel grid (density ≤ 1)", sigma_t, grid_time);
    row("uniform, same extinction scale", sigma_t, same_scale);
    row("uniform, the grid's mean extinction", mean, same_mean);
    println!();
    Ok(())
}

/// The volume's extinction averaged over its box (a 32³ lattice of cell
/// centres).
fn mean_extinction(volume: &Volume) -> Rgb {
    let b = volume.field_box();
    let n = UVec3::splat(32);
    let mut sum = Rgb::ZERO;
    for z in 0..n.z {
        for y in 0..n.y {
            for x in 0..n.x {
                let u = (UVec3::new(x, y, z).as_vec3() + 0.5) / n.as_vec3();
                sum += volume.extinction_at(b.min + u * b.extent());
            }
        }
    }
    sum / n.element_product() as f32
}
