//! What draws more random numbers than a probe can set, probed by its
//! mean over independent samples (each item its own PCG stream): single
//! scattering's estimator against a quadrature of the Rust integrand, the
//! camera path against the CPU's.

use super::*;
use tyndall::testing::{Integrator, LightSubpaths, PixelPosition, PixelSampler};

/// The mean of independent samples and the variance of that mean (the
/// samples' unbiased variance over their number).
fn mean_and_its_variance(values: impl Iterator<Item = DVec3>) -> (DVec3, DVec3) {
    let (mut sum, mut sum2, mut n) = (DVec3::ZERO, DVec3::ZERO, 0.0);
    for v in values {
        sum += v;
        sum2 += v * v;
        n += 1.0;
    }
    let mean = sum / n;
    let var = (sum2 / n - mean * mean).max(DVec3::ZERO) * (n / (n - 1.0));
    (mean, var / n)
}

/// A probe output's first vec4 as an RGB value in f64.
fn first_rgb(o: &[[f32; 4]; 2]) -> DVec3 {
    DVec3::new(f64::from(o[0][0]), f64::from(o[0][1]), f64::from(o[0][2]))
}

/// Single scattering's estimator on the GPU (`single_in_scattered`: each
/// light's equiangular samples and the ray's distance sample combined by
/// the balance heuristic) is unbiased for the single-scattering integral:
/// its mean over 4096 independent samples along each of 12 camera rays
/// against this test's midpoint quadrature of ∫_a^b T(a, t)·Σ_l
/// scattered_radiance(l, x(t)) dt with the Rust twin, for the scene's
/// delta lights. Tolerance: 5 standard errors of the mean, from the
/// samples' own spread, plus the quadrature's error at the integrand's
/// jumps (a hard spot's cone and the shadow edges: at most 2 per light
/// and per occluder, each off by at most the integrand's largest value
/// times half a step).
#[test]
fn single_in_scattered_is_unbiased_for_the_rust_integrand() {
    let Some(f) = fixture_of(
        "single_in_scattered_is_unbiased_for_the_rust_integrand",
        &scene_text(false),
    ) else {
        return;
    };
    let lights = f.scene.lights();
    let fog = f.scene.fog().expect("fog");
    let sigma_t = f64::from(fog.sigma_t);
    let samples = 4096;
    let mut rays = Vec::new();
    let mut items = Vec::new();
    for r in 0..12 {
        let target = Vec3::new(
            5.0 * spread(3 * r + 1) - 2.5,
            5.0 * spread(3 * r + 2) - 2.5,
            4.0 * spread(3 * r + 3) - 2.0,
        );
        let (ray, t_hit) = camera_ray_towards(&f, target);
        for s in 0..samples {
            items.push(ray_item(&ray, t_hit, (r * samples + s) as u32));
        }
        rays.push((ray, t_hit));
    }
    let out = evaluate_in_scene(&f.gpu, &f.march, SceneFormula::SingleInScattered, &items)
        .expect("GPU evaluation");
    let mut lit = 0;
    for (r, (ray, t_hit)) in rays.iter().enumerate() {
        let (mean, mean_var) =
            mean_and_its_variance(out[r * samples..(r + 1) * samples].iter().map(first_rgb));
        let stderr = mean_var.map(f64::sqrt);
        let (mut quadrature, mut peak) = (DVec3::ZERO, 0.0f64);
        let mut h = 0.0;
        if let Some((a, b)) = fog.interval(ray, 0.0, *t_hit) {
            let steps = 20_000;
            h = f64::from(b - a) / steps as f64;
            for k in 0..steps {
                let t = f64::from(a) + (k as f64 + 0.5) * h;
                let x = ray.at(t as f32);
                let camera_t = (-sigma_t * (t - f64::from(a))).exp();
                let mut value = DVec3::ZERO;
                for l in 0..lights.len() {
                    value += twins::scattered_radiance(
                        &f.scene,
                        &f.visibility,
                        l,
                        None,
                        x,
                        ray.direction,
                    )
                    .as_dvec3();
                }
                let value = value * camera_t;
                peak = peak.max(value.max_element());
                quadrature += value * h;
            }
        }
        // 5 lights and 3 occluders (the pane, the card and the box's
        // walls do not count: the fog box is open), 2 jumps each.
        let jumps = 2.0 * (lights.len() as f64 + 3.0);
        for c in 0..3 {
            let tolerance = 5.0 * stderr[c] + jumps * peak * 0.5 * h + 1e-6 * quadrature[c];
            assert!(
                (mean[c] - quadrature[c]).abs() <= tolerance,
                "ray {r} ({ray:?}), channel {c}: GPU mean {mean} ± {stderr} vs the quadrature \
                 {quadrature} (tolerance {tolerance:.2e})"
            );
        }
        lit += usize::from(
            quadrature.max_element() > 0.0 && stderr.max_element() < 0.05 * mean.max_element(),
        );
    }
    assert!(lit >= 8, "{lit} rays lit with an informative estimate");
}

/// The GPU's camera path (`radiance`: fog by single scattering, the glass
/// pane's filter, the card's and the quad light's surfaces) and the CPU's
/// (`CameraPath::radiance` under `single`, through
/// `tyndall::testing::Integrator`) estimate the same radiance along a
/// camera ray: their means over 4096 independent samples each, along 16
/// rays through the pane, the card, the lamp and the fog, agree within 5
/// standard errors of their difference (from each side's spread).
#[test]
fn camera_path_radiance_agrees_with_the_cpus() {
    let Some(f) = fixture("camera_path_radiance_agrees_with_the_cpus") else {
        return;
    };
    let samples = 4096u32;
    let targets: Vec<Vec3> = (0..16)
        .map(|r| match r {
            // Through the pane, at the card, at the lamp.
            0 => Vec3::new(-0.5, 1.0, -0.5),
            1 => Vec3::new(1.5, 0.6, 1.0),
            2 => Vec3::new(0.0, 3.5, 0.0),
            _ => Vec3::new(
                6.0 * spread(3 * r + 1) - 3.0,
                6.0 * spread(3 * r + 2) - 3.0,
                4.0 * spread(3 * r + 3) - 2.0,
            ),
        })
        .collect();
    let rays: Vec<_> = targets
        .iter()
        .map(|t| camera_ray_towards(&f, *t).0)
        .collect();
    let mut items = Vec::new();
    for (r, ray) in rays.iter().enumerate() {
        for s in 0..samples {
            // The kernel traces the whole path: the item's t_hit is unused.
            items.push(ray_item(ray, 0.0, r as u32 * samples + s));
        }
    }
    let out = evaluate_in_scene(&f.gpu, &f.march, SceneFormula::Radiance, &items)
        .expect("GPU evaluation");
    let settings = RenderSettings {
        visibility: VisibilityMode::ShadowRays,
        ..f.settings
    };
    let mut informative = 0;
    for (r, ray) in rays.iter().enumerate() {
        let chunk = &out[r * samples as usize..(r + 1) * samples as usize];
        let (gpu, gpu_var) = mean_and_its_variance(chunk.iter().map(first_rgb));
        let mut counts = tyndall::RayCounts::default();
        let cpu_samples: Vec<DVec3> = (0..samples)
            .map(|i| {
                let subpaths = LightSubpaths::for_pass(&f.scene, &settings, 1, i, &mut counts);
                let integrator = Integrator::new(&settings, &f.visibility, &subpaths);
                let mut sampler = PixelSampler::new(29, r as u64, i);
                let _ = sampler.next_2d();
                integrator
                    .radiance(
                        &f.scene,
                        *ray,
                        PixelPosition::default(),
                        &mut sampler,
                        &mut counts,
                    )
                    .as_dvec3()
            })
            .collect();
        let (cpu, cpu_var) = mean_and_its_variance(cpu_samples.into_iter());
        for c in 0..3 {
            let sd = (gpu_var[c] + cpu_var[c]).sqrt();
            assert!(
                (gpu[c] - cpu[c]).abs() <= 5.0 * sd + 1e-6 * cpu[c].abs(),
                "ray {r} towards {}, channel {c}: GPU {gpu} vs CPU {cpu} (5σ = {:.2e})",
                targets[r],
                5.0 * sd
            );
        }
        informative += usize::from(
            cpu.max_element() > 0.0 && gpu_var.max_element().sqrt() < 0.05 * gpu.max_element(),
        );
    }
    assert!(
        informative >= 12,
        "{informative} rays with an informative estimate"
    );
}
