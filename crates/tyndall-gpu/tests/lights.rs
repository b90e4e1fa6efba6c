//! One formula, two languages for the scene-dependent light functions
//! of `shaders/lights.wgsl` (issue 26): each is run by a compute shader,
//! appended to the march module itself, on lights uploaded as the march
//! uploads them (`scene_buffers::gpu_lights`), for thousands of inputs,
//! and compared with the Rust function it names as its twin.
//!
//! Tolerances follow from f32 rounding (ε = 2⁻²³) of the operations
//! involved, both sides counted (WGSL may fuse a multiply-add and allows
//! 2.5 ULP for a division, 2⁻¹¹ absolute for sin and cos), stated per
//! test; where a result is ill-conditioned (a cut where a ray grazes the
//! cone, a receiver on a spot's edge) the tolerance grows by the
//! condition number, computed in f64 from the inputs.

mod support;

use glam::{DVec3, Vec3};
use tyndall::lights::{Light, SpotLight, SpotProfile};
use tyndall::ray::Ray;
use tyndall_gpu::formula_probe::{LightFormula, evaluate_lights};
use tyndall_gpu::scene_buffers::gpu_lights;

const EPS: f64 = f32::EPSILON as f64;

/// The stand-in for an infinite distance on the GPU (`INFINITE` of
/// `scene.wgsl`).
const INFINITE: f32 = 3.0e38;

/// A deterministic spread of numbers in [0, 1): the golden-ratio sequence.
fn spread(i: usize) -> f32 {
    (i as f64 * 0.618_033_988_749_895).fract() as f32
}

/// The `i`-th of a spread of unit directions.
fn direction(i: usize) -> Vec3 {
    let z = 1.0 - 2.0 * spread(i);
    let phi = 2.0 * std::f32::consts::PI * (i as f64 * 0.754_877_666_246_693).fract() as f32;
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(r * phi.cos(), r * phi.sin(), z).normalize()
}

fn d(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

fn spots() -> Vec<SpotLight> {
    let mut spots = Vec::new();
    for (k, cutoff) in [5.0f32, 20.0, 45.0, 70.0, 89.0, 90.0]
        .into_iter()
        .enumerate()
    {
        let profile = [
            SpotProfile::Linear,
            SpotProfile::Hard,
            SpotProfile::Smooth {
                cos_inner: (0.6 * cutoff).to_radians().cos(),
            },
        ][k % 3];
        spots.push(SpotLight {
            position: Vec3::new(0.5 - 0.3 * k as f32, 1.5 + 0.2 * k as f32, -0.4),
            direction: direction(7 * k + 3),
            cos_cutoff: cutoff.to_radians().cos(),
            profile,
            intensity: Vec3::new(1.0, 2.0, 0.5),
        });
    }
    spots
}

/// How far the f32 root `t` of `h(t) = h0 + h1·t + h2·t²` may move when
/// the terms, of magnitudes `m0 + m1·|t| + m2·t²`, are each rounded with
/// relative error `k·ε`: k·ε·M / |h'(t)|, plus 8ε|t| for the root formula
/// (a square root, a division and a sum on each side); `None` if `t` is
/// no root to within twice that rounding.
fn root_tolerance(t: f64, h: [f64; 3], m: [f64; 3], k: f64) -> Option<f64> {
    let value = h[0] + h[1] * t + h[2] * t * t;
    let magnitude = m[0] + m[1] * t.abs() + m[2] * t * t;
    let slope = (h[1] + 2.0 * h[2] * t).abs();
    (value.abs() <= 2.0 * k * EPS * magnitude)
        .then(|| k * EPS * magnitude / slope + 8.0 * EPS * t.abs())
}

/// The tolerance on an end `t` of a spot's reach along `ray`: exact for
/// the segment's own ends, else that of the cut it is a root of — the
/// cone's quadric (a = (ω·d)² − cos², b = 2(v·d ω·d − cos² v·ω), c =
/// (v·d)² − cos²|v|², each from dot products of three terms: 8ε of the
/// magnitudes per side, 16ε both) or the apex plane v·d + t ω·d = 0.
fn reach_end_tolerance(spot: &SpotLight, ray: &Ray, t: f32, t0: f32, t1: f32) -> f64 {
    if t == t0 || t == t1 {
        return 0.0;
    }
    let (v, w, axis) = (
        d(ray.origin - spot.position),
        d(ray.direction),
        d(spot.direction),
    );
    let c2 = f64::from(spot.cos_cutoff).powi(2);
    let (vd, wd) = (v.dot(axis), w.dot(axis));
    let quadric = [
        vd * vd - c2 * v.length_squared(),
        2.0 * (vd * wd - c2 * v.dot(w)),
        wd * wd - c2,
    ];
    let abs_dot = |a: DVec3, b: DVec3| (a * b).abs().element_sum();
    let (avd, awd) = (abs_dot(v, axis), abs_dot(w, axis));
    let magnitudes = [
        avd * avd + c2 * v.length_squared(),
        2.0 * (avd * awd + c2 * abs_dot(v, w)),
        awd * awd + c2,
    ];
    let t = f64::from(t);
    let q = root_tolerance(t, quadric, magnitudes, 16.0);
    let p = root_tolerance(t, [vd, wd, 0.0], [avd, awd, 0.0], 8.0);
    q.into_iter().chain(p).fold(0.0, f64::max)
}

#[test]
fn spot_reach_matches_clip_ray() {
    let Some(gpu) = support::gpu_or_skip("spot_reach_matches_clip_ray") else {
        return;
    };
    let spots = spots();
    let lights: Vec<Light> = spots.iter().copied().map(Light::Spot).collect();
    let (gpu_lights, triangles) = gpu_lights(&lights);
    let mut items = Vec::new();
    let mut cases = Vec::new();
    for (s, spot) in spots.iter().enumerate() {
        for i in 0..1500 {
            // Origins in a box around the spot (some behind it), rays in
            // every direction, segments from 0 or further to a finite end
            // or ∞.
            let origin = spot.position
                + 4.0
                    * Vec3::new(
                        spread(3 * i) - 0.5,
                        spread(3 * i + 1) - 0.5,
                        spread(3 * i + 2) - 0.5,
                    );
            let dir = direction(i + 17 * s);
            let t0 = if i % 3 == 0 {
                0.0
            } else {
                2.0 * spread(5 * i + 1)
            };
            let t1 = if i % 4 == 0 {
                f32::INFINITY
            } else {
                t0 + 0.1 + 6.0 * spread(7 * i + 2)
            };
            let ray = Ray {
                origin,
                direction: dir,
            };
            items.push([
                [origin.x, origin.y, origin.z, t0],
                [dir.x, dir.y, dir.z, t1.min(INFINITE)],
                [s as f32, 0.0, 0.0, 0.0],
            ]);
            cases.push((s, ray, t0, t1));
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
    let (mut inside, mut outside) = (0, 0);
    for ((s, ray, t0, t1), o) in cases.iter().zip(&out) {
        let spot = &spots[*s];
        let rust = spot.clip_ray(ray, *t0, *t1);
        let end = |t: f32| if t >= INFINITE { f32::INFINITY } else { t };
        let gpu = (o[0][2] == 1.0).then(|| (o[0][0], end(o[0][1])));
        let tol = |t: f32| reach_end_tolerance(spot, ray, t, *t0, *t1);
        let close = |a: f32, b: f32, tolerance: f64| {
            a == b || (f64::from(a) - f64::from(b)).abs() <= tolerance
        };
        let ok = match (rust, gpu) {
            (Some((lo, hi)), Some((glo, ghi))) => {
                inside += 1;
                close(glo, lo, tol(lo)) && close(ghi, hi, tol(hi))
            }
            (None, None) => {
                outside += 1;
                true
            }
            // One side finds a piece the other does not: only a piece
            // within rounding of a cut at both ends.
            (Some((lo, hi)), None) | (None, Some((lo, hi))) => {
                f64::from(hi) - f64::from(lo) <= tol(lo) + tol(hi)
            }
        };
        assert!(
            ok,
            "spot #{s} {spot:?}, ray {ray:?} on [{t0}, {t1}]: GPU {gpu:?} vs Rust {rust:?}"
        );
    }
    // Both outcomes are exercised.
    assert!(
        inside > 1000 && outside > 1000,
        "{inside} inside, {outside} outside"
    );
}
