//! One function, two languages for the march module's geometry (issue
//! 26): `camera_ray`, `fog_interval`, `nearest_hit` with
//! `geometric_normal`, and `reflect_layer`, run by compute kernels
//! appended to the march module and bound as the march binds a whole
//! scene (`formula_probe::evaluate_in_scene`), against their Rust twins
//! `tyndall::camera::Camera::ray`, `tyndall::media::Fog::interval`,
//! `tyndall::accel::Geometry::intersect` with `Shape::normal`, and
//! `tyndall::materials::Surface::reflect`.
//!
//! The nearest hits are also checked against an intersection computed
//! here in f64 from the shapes, which decides the cases that rounding may
//! decide — a ray within 10⁻⁴ of an edge, grazing a sphere, or meeting
//! two surfaces within 10⁻⁴ of each other — and leaves them out; the
//! tests assert that most cases remain. Tolerances are bounds on f32
//! rounding (ε = 2⁻²³) on each side, WGSL's accuracy where it is looser
//! (division 2.5 ULP; sin, cos 2⁻¹¹ absolute; pow through exp2 and
//! log2), each stated where it is used.

mod support;

use glam::{DVec3, Vec2, Vec3};
use tyndall::RenderSettings;
use tyndall::Scene;
use tyndall::camera::Camera;
use tyndall::materials::Surface;
use tyndall::ray::Ray;
use tyndall::shapes::Shape;
use tyndall_gpu::formula_probe::{SceneFormula, evaluate_in_scene};
use tyndall_gpu::{GpuMarch, MarchSettings};

const EPS: f64 = f32::EPSILON as f64;

/// Cases within this (relative) distance of where rounding decides the
/// answer are left out.
const MARGIN: f64 = 1e-4;

/// The scene: a fog box that clips the view, two spheres, a floor, a box
/// and a tetrahedron mesh, under one point light.
const SCENE: &str = r#"
[camera]
position = [0.5, 1.0, 9]
look_at = [0, 0, 0]
fov_y_deg = 45

[render]
width = 64
height = 48
integrator = "march"
step = 0.05

[fog]
sigma_t = 0.2
albedo = [0.8, 0.8, 0.8]
box = { min = [-3, -2, -3], max = [3, 2.5, 3] }

[materials.matte]
type = "diffuse"
reflectance = 0.6

[materials.shiny]
type = "glossy"
reflectance = 0.8
roughness = 0.2

[[shapes]]
type = "sphere"
center = [-1.2, 0.3, 0.0]
radius = 1.0
material = "matte"

[[shapes]]
type = "sphere"
center = [1.5, -0.5, 1.0]
radius = 0.6
material = "shiny"

[[shapes]]
type = "quad"
corners = [[-5, -2, -5], [-5, -2, 5], [5, -2, 5], [5, -2, -5]]
material = "matte"

[[shapes]]
type = "box"
min = [0.3, -2.0, -2.5]
max = [1.3, -0.8, -1.5]
material = "shiny"

[[shapes]]
type = "mesh"
file = "tetrahedron.obj"
translate = [-0.5, -1.2, 2.0]
material = "shiny"

[[lights]]
type = "point"
position = [0, 3, 0]
intensity = 5.0
"#;

const TETRAHEDRON: &str = "v 0 0 0\nv 1 0 0.2\nv 0.3 1 0\nv 0.2 0.3 1\n\
                           f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";

/// A deterministic spread of numbers in [0, 1): the golden-ratio sequence.
fn spread(i: usize) -> f32 {
    (i as f64 * 0.618_033_988_749_895).fract() as f32
}

fn d(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

struct Fixture {
    gpu: tyndall_gpu::Gpu,
    scene: Scene,
    settings: RenderSettings,
    march: GpuMarch,
}

fn fixture(test: &str) -> Option<Fixture> {
    let gpu = support::gpu_or_skip(test)?;
    let (desc, scene) = support::scene_in_folder(test, SCENE, &[("tetrahedron.obj", TETRAHEDRON)]);
    let settings = desc.settings;
    let march = GpuMarch::new(&gpu, &scene, &MarchSettings::from(&settings)).expect("upload");
    Some(Fixture {
        gpu,
        scene,
        settings,
        march,
    })
}

/// A unit direction from three numbers in [0, 1).
fn direction(a: f32, b: f32, c: f32) -> Vec3 {
    Vec3::new(2.0 * a - 1.0, 2.0 * b - 1.0, 2.0 * c - 1.0).normalize_or(Vec3::Z)
}

/// Rays to test: the camera's through a jittered film grid, rays from
/// points spread over the scene in spread directions, and axis-aligned
/// ones (a direction with zero components, whose slab tests meet 1/0).
fn rays(camera: &Camera, width: u32, height: u32) -> Vec<Ray> {
    let mut out = Vec::new();
    for j in 0..height {
        for i in 0..width {
            let k = (j * width + i) as usize;
            let film = Vec2::new(i as f32 + spread(2 * k), j as f32 + spread(2 * k + 1));
            out.push(camera.ray(film, Vec2::ZERO));
        }
    }
    let axes = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    for k in 0..3000 {
        let origin = Vec3::new(
            9.0 * spread(3 * k) - 4.5,
            6.0 * spread(3 * k + 1) - 2.5,
            9.0 * spread(3 * k + 2) - 4.5,
        );
        let dir = if k % 10 == 0 {
            axes[(k / 10) % 6]
        } else {
            direction(spread(5 * k + 1), spread(7 * k + 2), spread(11 * k + 3))
        };
        out.push(Ray {
            origin,
            direction: dir,
        });
    }
    out
}

fn item(ray: &Ray, a: f32, b: f32) -> [[f32; 4]; 3] {
    let (o, w) = (ray.origin, ray.direction);
    [[o.x, o.y, o.z, a], [w.x, w.y, w.z, b], [0.0; 4]]
}

#[test]
fn camera_rays_match_rust() {
    let Some(f) = fixture("camera_rays_match_rust") else {
        return;
    };
    let (width, height) = (f.settings.width, f.settings.height);
    let camera = Camera::new(f.scene.camera(), width, height);
    let films: Vec<Vec2> = (0..4000)
        .map(|k| {
            Vec2::new(
                (width as f32 + 2.0) * spread(2 * k) - 1.0,
                (height as f32 + 2.0) * spread(2 * k + 1) - 1.0,
            )
        })
        .chain([
            Vec2::ZERO,
            Vec2::new(width as f32, height as f32),
            Vec2::new(0.5 * width as f32, 0.5 * height as f32),
        ])
        .collect();
    let items: Vec<_> = films
        .iter()
        .map(|p| [[p.x, p.y, 0.0, 0.0], [0.0; 4], [0.0; 4]])
        .collect();
    let out = evaluate_in_scene(&f.gpu, &f.march, SceneFormula::CameraRay, &items)
        .expect("GPU evaluation");
    let (_, _, _, half_extent) = camera.frame();
    for (film, o) in films.iter().zip(&out) {
        let rust = camera.ray(*film, Vec2::ZERO);
        let origin = Vec3::new(o[0][0], o[0][1], o[0][2]);
        let direction = Vec3::new(o[1][0], o[1][1], o[1][2]);
        assert_eq!(origin, rust.origin, "film {film}: the origin is copied");
        // ndc = 2p/res − 1 (3 roundings, |ndc| ≤ 1.1), scaled by the
        // half-extent and summed with the unit frame: each component
        // within 8ε·(1 + s) of the exact sum, s = |ndc|·half-extent
        // summed; normalising adds 4ε (inverseSqrt 2 ULP, products).
        let ndc = 2.0 * *film / Vec2::new(width as f32, height as f32) - Vec2::ONE;
        let s = f64::from((ndc.abs() * half_extent).element_sum());
        let tolerance = 2.0 * (8.0 * EPS * (1.0 + s) / 1.0 + 4.0 * EPS);
        let error = d(direction - rust.direction).abs().max_element();
        assert!(
            error <= tolerance,
            "film {film}: GPU direction {direction} vs Rust {} (error {error:.2e} > {tolerance:.2e})",
            rust.direction
        );
    }
}

#[test]
fn fog_intervals_match_rust() {
    let Some(f) = fixture("fog_intervals_match_rust") else {
        return;
    };
    let fog = f.scene.fog().expect("fog");
    let camera = Camera::new(f.scene.camera(), f.settings.width, f.settings.height);
    let rays = rays(&camera, 16, 12);
    // Each ray over (0, ∞), from a spread start, and over a spread span.
    let mut cases = Vec::new();
    for (k, ray) in rays.iter().enumerate() {
        let t0 = if k % 3 == 0 { 0.0 } else { 6.0 * spread(k) };
        let t1 = match k % 4 {
            0 => f32::INFINITY,
            _ => t0 + 8.0 * spread(3 * k + 1),
        };
        cases.push((*ray, t0, t1));
    }
    // f32::INFINITY travels as the WGSL's INFINITE stand-in, 3·10³⁸.
    let items: Vec<_> = cases
        .iter()
        .map(|(ray, t0, t1)| item(ray, *t0, t1.min(3.0e38)))
        .collect();
    let out = evaluate_in_scene(&f.gpu, &f.march, SceneFormula::FogInterval, &items)
        .expect("GPU evaluation");
    let (mut inside, mut outside) = (0, 0);
    for ((ray, t0, t1), o) in cases.iter().zip(&out) {
        let rust = fog.interval(ray, *t0, *t1);
        // A slab's t = (m − o)·(1/d): the subtraction and product round
        // by ε each, WGSL's 1/d by 2.5 ULP, so t is within 5ε·|t| of
        // exact on each side. Intervals within that of empty are left
        // out (either side may call them empty).
        let tol = |t: f32| 2.0 * 5.0 * EPS * f64::from(t.abs()) + 1e-30;
        match rust {
            Some((a, b)) if f64::from(b - a) > tol(a) + tol(b) => {
                assert_eq!(
                    o[0][2], 1.0,
                    "{ray:?} over ({t0}, {t1}): GPU finds no fog, Rust ({a}, {b})"
                );
                for (g, r) in [(o[0][0], a), (o[0][1], b.min(3.0e38))] {
                    assert!(
                        f64::from((g - r).abs()) <= tol(r),
                        "{ray:?} over ({t0}, {t1}): GPU ({}, {}) vs Rust ({a}, {b})",
                        o[0][0],
                        o[0][1]
                    );
                }
                inside += 1;
            }
            Some(_) => {}
            None => {
                // The GPU may find a sliver where Rust finds none, within
                // rounding of the box; but never a real interval.
                if o[0][2] != 0.0 {
                    let (a, b) = (o[0][0], o[0][1]);
                    assert!(
                        f64::from(b - a) <= tol(a) + tol(b),
                        "{ray:?} over ({t0}, {t1}): GPU finds fog ({a}, {b}), Rust none"
                    );
                }
                outside += 1;
            }
        }
    }
    assert!(
        inside > 600 && outside > 1000,
        "{inside} inside, {outside} outside"
    );
}

/// The nearest hit along `ray` computed in f64 from the scene's shapes
/// (the primitive's index, t), or `Err` where rounding may decide
/// which primitive, if any, is hit.
fn nearest_in_f64(scene: &Scene, ray: &Ray) -> Result<Option<(usize, f64)>, ()> {
    let (o, w) = (d(ray.origin), d(ray.direction));
    let mut hits = Vec::new();
    for (index, prim) in scene.geometry().primitives().iter().enumerate() {
        // Each test returns Err when the ray is within MARGIN of where it
        // would switch from hitting to missing.
        let hit = match prim.shape {
            Shape::Sphere(s) => {
                let (c, r) = (d(s.center), f64::from(s.radius));
                let oc = o - c;
                let b = oc.dot(w);
                let disc = r * r - (oc - b * w).length_squared();
                if disc.abs() < MARGIN * r * r {
                    return Err(());
                }
                if disc < 0.0 {
                    continue;
                }
                let (t0, t1) = (-b - disc.sqrt(), -b + disc.sqrt());
                if t0.abs() < MARGIN || t1.abs() < MARGIN {
                    return Err(());
                }
                [t0, t1].into_iter().find(|&t| t > 0.0)
            }
            Shape::Quad(q) => {
                let (corner, eu, ev) = (d(q.origin), d(q.edge_u), d(q.edge_v));
                planar_hit(o, w, (corner, eu, ev), q.one_sided, |u, v| {
                    vec![u, v, 1.0 - u, 1.0 - v]
                })?
            }
            Shape::Triangle(t) => {
                let (corner, e1, e2) = (d(t.v0), d(t.e1), d(t.e2));
                planar_hit(o, w, (corner, e1, e2), t.one_sided, |u, v| {
                    vec![u, v, 1.0 - u - v]
                })?
            }
        };
        if let Some(t) = hit {
            hits.push((index, t));
        }
    }
    hits.sort_by(|a, b| a.1.total_cmp(&b.1));
    if let [(_, first), (_, second), ..] = hits[..]
        && second - first < MARGIN * (1.0 + first)
    {
        return Err(());
    }
    Ok(hits.first().copied())
}

/// The hit of the plane through `corner` spanned by `a`, `b` (its front
/// facing a × b), where `inside(u, v)` (the coordinates along `a`, `b`)
/// lists quantities that are all ≥ 0 inside the shape; `Err` within
/// MARGIN of its edge or its plane, or for a ray within 10⁻⁴ of parallel
/// to it that may meet it.
fn planar_hit(
    o: DVec3,
    w: DVec3,
    (corner, a, b): (DVec3, DVec3, DVec3),
    one_sided: bool,
    inside: impl Fn(f64, f64) -> Vec<f64>,
) -> Result<Option<f64>, ()> {
    let n = a.cross(b);
    let denom = n.dot(w);
    let height = n.dot(corner - o);
    if height.abs() < MARGIN * n.length() {
        return Err(());
    }
    if denom == 0.0 || (one_sided && denom > 0.0) {
        return Ok(None);
    }
    let t = height / denom;
    if t < 0.0 {
        return Ok(None);
    }
    let p = o + w * t - corner;
    // p = u·a + v·b: solve by the cross products.
    let (u, v) = (
        p.cross(b).dot(n) / n.length_squared(),
        a.cross(p).dot(n) / n.length_squared(),
    );
    let sides = inside(u, v);
    let hit = sides.iter().all(|&s| s > 0.0);
    if sides.iter().any(|s| s.abs() < MARGIN) || (hit && denom.abs() < MARGIN * n.length()) {
        return Err(());
    }
    Ok(hit.then_some(t))
}

#[test]
fn nearest_hits_match_rust() {
    let Some(f) = fixture("nearest_hits_match_rust") else {
        return;
    };
    let camera = Camera::new(f.scene.camera(), f.settings.width, f.settings.height);
    let rays = rays(&camera, 64, 48);
    let items: Vec<_> = rays.iter().map(|r| item(r, 0.0, 0.0)).collect();
    let out = evaluate_in_scene(&f.gpu, &f.march, SceneFormula::NearestHit, &items)
        .expect("GPU evaluation");
    let geometry = f.scene.geometry();
    let (mut hit, mut missed, mut left_out) = (0, 0, 0);
    for (ray, o) in rays.iter().zip(&out) {
        let Ok(expected) = nearest_in_f64(&f.scene, ray) else {
            left_out += 1;
            continue;
        };
        let rust = geometry.intersect(ray, f32::INFINITY);
        let what = format!("{ray:?}");
        let Some((index, t64)) = expected else {
            assert!(rust.is_none(), "{what}: Rust hits {rust:?}, f64 nothing");
            assert_eq!(
                o[0][1], 0.0,
                "{what}: the GPU hits at t = {}, f64 nothing",
                o[0][0]
            );
            missed += 1;
            continue;
        };
        let rust =
            rust.unwrap_or_else(|| panic!("{what}: Rust misses, f64 hits #{index} at {t64}"));
        assert_eq!(rust.primitive as usize, index, "{what}: Rust's primitive");
        assert_eq!(
            o[0][1], 1.0,
            "{what}: the GPU misses, Rust hits at {}",
            rust.t
        );
        let prim = geometry.primitive(rust.primitive);
        assert_eq!(o[0][2], prim.material as f32, "{what}: the GPU's material");
        // t from quantities no larger than |o| + the scene's size (8) +
        // t: within 16ε of that on each side, over 2.5 ULP for WGSL's
        // division; a sphere's √disc moves t by Δdisc/(2√disc), Δdisc
        // within 8ε·|o − c|².
        let scale = d(ray.origin).length() + 8.0 + f64::from(rust.t);
        let mut tolerance = 2.0 * 16.0 * EPS * scale;
        if let Shape::Sphere(s) = prim.shape {
            let oc = d(ray.origin - s.center);
            let w = d(ray.direction);
            let r = f64::from(s.radius);
            let disc = r * r - (oc - oc.dot(w) * w).length_squared();
            tolerance += 2.0 * 8.0 * EPS * oc.length_squared() / (2.0 * disc.sqrt());
        }
        let gpu_t = f64::from(o[0][0]);
        assert!(
            (gpu_t - f64::from(rust.t)).abs() <= tolerance,
            "{what}: GPU t = {gpu_t} vs Rust {} (tolerance {tolerance:.2e})",
            rust.t
        );
        assert!(
            (f64::from(rust.t) - t64).abs() <= tolerance,
            "{what}: Rust t = {} vs f64 {t64}",
            rust.t
        );
        let gpu_normal = Vec3::new(o[1][0], o[1][1], o[1][2]);
        let rust_normal = prim.shape.normal(ray.at(rust.t));
        let normal_tolerance = match prim.shape {
            // normalize(x − c): x moves by Δt and rounds by 4ε·|x|.
            Shape::Sphere(s) => {
                (tolerance + 8.0 * EPS * d(ray.at(rust.t)).length()) / f64::from(s.radius)
                    + 8.0 * EPS
            }
            // Both read the normal the shape stores.
            _ => 0.0,
        };
        let error = d(gpu_normal - rust_normal).abs().max_element();
        assert!(
            error <= normal_tolerance,
            "{what}: GPU normal {gpu_normal} vs Rust {rust_normal}"
        );
        hit += 1;
    }
    assert!(
        hit > 1500 && missed > 1500 && left_out < rays.len() / 50,
        "{hit} hit, {missed} missed, {left_out} left out"
    );
}

#[test]
fn reflections_match_rust() {
    let Some(f) = fixture("reflections_match_rust") else {
        return;
    };
    let roughnesses = [0.0f32, 0.02, 0.2, 0.6, 1.0];
    let mut cases = Vec::new();
    for k in 0..4000 {
        let normal = direction(spread(3 * k), spread(3 * k + 1), spread(3 * k + 2));
        let mut incoming = direction(spread(5 * k + 1), spread(7 * k + 2), spread(11 * k + 3));
        if incoming.dot(normal) > 0.0 {
            incoming = -incoming;
        }
        let keys = [
            (spread(13 * k + 4) * 16_777_216.0) as u32,
            (spread(17 * k + 5) * 16_777_216.0) as u32,
        ];
        cases.push((roughnesses[k % roughnesses.len()], incoming, normal, keys));
    }
    let items: Vec<_> = cases
        .iter()
        .map(|&(r, i, n, k)| {
            [
                [i.x, i.y, i.z, r],
                [n.x, n.y, n.z, 0.0],
                [k[0] as f32, k[1] as f32, 0.0, 0.0],
            ]
        })
        .collect();
    let out =
        evaluate_in_scene(&f.gpu, &f.march, SceneFormula::Reflect, &items).expect("GPU evaluation");
    let (mut reflected, mut below, mut left_out) = (0, 0, 0);
    for (&(roughness, incoming, normal, keys), o) in cases.iter().zip(&out) {
        let u = Vec2::new(keys[0] as f32, keys[1] as f32) / 16_777_216.0;
        let surface = Surface {
            roughness,
            ..Surface::diffuse(tyndall::color::Rgb::splat(0.5))
        };
        let rust = surface.reflect(incoming, normal, u);
        let gpu = Vec3::new(o[0][0], o[0][1], o[0][2]);
        let what = format!("roughness {roughness}, incoming {incoming}, normal {normal}, u {u}");
        // The mirror direction i − 2(i·n)n: 8ε a component. The GGX
        // sample: WGSL's sin and cos of φ = 2πu.x are within 2⁻¹¹
        // absolute, as if φ moved by 2·2⁻¹¹; the cap's z by a few ε, as
        // if u.y moved by 8ε: the bound is the Rust sample's own change
        // under those moves (each way), plus the rounding of the frames,
        // the warp and the reflection, 64ε over the warped half vector's
        // length before it is normalised (small where the cap's point
        // nearly cancels the view: the direction is ill-conditioned there).
        let mirror = d(incoming - 2.0 * incoming.dot(normal) * normal);
        let tolerance = if roughness <= 0.0 {
            2.0 * 8.0 * EPS
        } else {
            let du = Vec2::new(
                2.0 * 2f32.powi(-11) / std::f32::consts::TAU,
                8.0 * f32::EPSILON,
            );
            let moved = [
                Vec2::new(du.x, 0.0),
                Vec2::new(-du.x, 0.0),
                Vec2::new(0.0, du.y),
                Vec2::new(0.0, -du.y),
            ]
            .into_iter()
            .filter_map(|m| surface.reflect(incoming, normal, u + m))
            .zip(std::iter::repeat(rust))
            .filter_map(|(a, b)| b.map(|b| d(a - b).length()))
            .fold(0.0f64, f64::max);
            // The warped half vector's length, in f64.
            let (t, b) = normal.any_orthonormal_pair();
            let o = -incoming;
            let a = f64::from(roughness);
            let o_std = glam::DVec3::new(
                a * f64::from(o.dot(t)),
                a * f64::from(o.dot(b)),
                f64::from(o.dot(normal)),
            )
            .normalize();
            let phi = std::f64::consts::TAU * f64::from(u.x);
            let z = (1.0 - f64::from(u.y)) * (1.0 + o_std.z) - o_std.z;
            let s = (1.0 - z * z).max(0.0).sqrt();
            let h_std = glam::DVec3::new(s * phi.cos(), s * phi.sin(), z) + o_std;
            let h_raw = glam::DVec3::new(a * h_std.x, a * h_std.y, h_std.z.max(0.0)).length();
            moved + 64.0 * EPS / h_raw.max(1e-30) + 2.0 * 16.0 * EPS
        };
        match rust {
            Some(r) => {
                // Within the tolerance of the surface, the two sides may
                // disagree on which side of it the direction lies.
                if d(r).dot(d(normal)).abs() <= 2.0 * tolerance {
                    left_out += 1;
                    continue;
                }
                let error = d(gpu - r).abs().max_element();
                assert!(
                    error <= tolerance,
                    "{what}: GPU {gpu} vs Rust {r} (error {error:.2e} > {tolerance:.2e}; mirror {mirror})"
                );
                reflected += 1;
            }
            None => {
                if gpu != Vec3::ZERO {
                    assert!(
                        d(gpu).dot(d(normal)) <= 2.0 * tolerance,
                        "{what}: GPU {gpu} above the surface, Rust below"
                    );
                    left_out += 1;
                } else {
                    below += 1;
                }
            }
        }
    }
    assert!(
        reflected > 3000 && below > 50 && left_out < cases.len() / 50,
        "{reflected} reflected, {below} below the surface, {left_out} left out"
    );
}
