//! The GPU path's spot cone (`spot_reach` in shaders/lights.wgsl) on
//! rays that pass a thin beam near its apex from far away, where a
//! quadric solved about the ray's origin loses the crossing in f32
//! (docs/benchmarks.md, "Pixels that hold a luminaire").
mod support;

use glam::Vec3;
use tyndall::lights::{Light, SpotLight, SpotProfile};
use tyndall::ray::Ray;
use tyndall_gpu::formula_probe::{LightFormula, evaluate_lights};
use tyndall_gpu::scene_buffers::gpu_lights;

/// A thin beam crossed near its apex by rays from 30 m away (passes of
/// 1 mm to 10 cm under a 12° spot pointing down): the GPU finds every
/// crossing, where the CPU's `clip_ray` does, to within f32's rounding
/// 30 m out. Solved about the rays' origins, both lost these crossings
/// (the discriminant cancelled below f32's rounding).
#[test]
fn spot_reach_finds_thin_beams_far_away() {
    let Some(gpu) = support::gpu_or_skip("spot_reach_finds_thin_beams_far_away") else {
        return;
    };
    let spot = SpotLight {
        gobo: None,
        luminaire: None,
        position: Vec3::new(0.0, 3.0, 0.0),
        direction: -Vec3::Y,
        cos_cutoff: 12f32.to_radians().cos(),
        profile: SpotProfile::Hard,
        intensity: Vec3::ONE,
    };
    let (gpu_lights, triangles) = gpu_lights(&[Light::Spot(spot.clone())]);
    let mut items = Vec::new();
    let mut rays = Vec::new();
    for pass in [1e-3f32, 1e-2, 3.5e-2, 1e-1] {
        for sideways in [0.0f32, 0.3, -0.45] {
            let dir = Vec3::new(1.0, 0.0, sideways).normalize();
            let origin = Vec3::new(0.0, 3.0 - pass, 0.0) - 30.0 * dir;
            items.push([
                [origin.x, origin.y, origin.z, 0.0],
                [dir.x, dir.y, dir.z, 60.0],
                [0.0; 4],
            ]);
            rays.push(Ray {
                origin,
                direction: dir,
            });
        }
    }
    let out = evaluate_lights(
        &gpu,
        LightFormula::SpotReach,
        &gpu_lights,
        &triangles,
        &items,
    )
    .expect("GPU evaluation");
    for (ray, o) in rays.iter().zip(&out) {
        let rust = spot.clip_ray(ray, 0.0, 60.0);
        let gpu = (o[0][2] == 1.0).then_some((o[0][0], o[0][1]));
        let (Some((lo, hi)), Some((glo, ghi))) = (rust, gpu) else {
            panic!("ray {ray:?}: GPU {gpu:?}, Rust {rust:?}: a crossing missed");
        };
        // Positions 30 m out in f32: about 2·10⁻⁶ apart.
        assert!(
            (glo - lo).abs() < 1e-5 && (ghi - hi).abs() < 1e-5 && hi > lo,
            "ray {ray:?}: GPU {glo}..{ghi} vs Rust {lo}..{hi}"
        );
    }
}
