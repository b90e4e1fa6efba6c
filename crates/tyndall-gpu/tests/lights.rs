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

use glam::{DVec3, Vec2, Vec3};
use tyndall::lights::{
    DirectionalLight, Incident, Light, MeshLight, PointLight, QuadLight, SOLID_ANGLE_REACH,
    SphereLight, SpotLight, SpotProfile,
};
use tyndall::ray::Ray;
use tyndall::shapes::{Quad, Sphere, Triangle};
use tyndall_gpu::formula_probe::{LightFormula, evaluate_lights};
use tyndall_gpu::scene_buffers::gpu_lights;

const EPS: f64 = f32::EPSILON as f64;

/// WGSL's bound on `sin` and `cos` inside [−π, π]: absolute 2⁻¹¹.
const SIN_COS_ABSOLUTE: f64 = 1.0 / 2048.0;

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
            gobo: None,
            luminaire: None,
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
    let lights: Vec<Light> = spots.iter().cloned().map(Light::Spot).collect();
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

/// One light of each kind: a point, a spot of each profile, a sun, a
/// rectangle (one-sided), a parallelogram (two-sided), a sphere of each
/// sidedness and a mesh of three triangles of unequal areas (one-sided).
fn lights_of_each_kind() -> Vec<Light> {
    let rgb = Vec3::new(1.0, 2.0, 0.5);
    let spot = |profile, position: Vec3, axis: Vec3| {
        Light::Spot(SpotLight {
            gobo: None,
            luminaire: None,
            position,
            direction: axis.normalize(),
            cos_cutoff: 40f32.to_radians().cos(),
            profile,
            intensity: rgb,
        })
    };
    let quad = |origin, u, v, two_sided| {
        let quad = Quad::new(origin, u, v, false).expect("a quad");
        Light::Quad(QuadLight::new(quad, rgb, two_sided))
    };
    let sphere = |center, radius, two_sided| {
        Light::Sphere(SphereLight {
            sphere: Sphere { center, radius },
            radiance: rgb,
            two_sided,
        })
    };
    let triangle = |a, b, c| Triangle::new(a, b, c).expect("a triangle");
    let mesh = MeshLight::new(
        vec![
            triangle(
                Vec3::new(-1.0, 2.0, -1.0),
                Vec3::new(1.0, 2.0, -1.0),
                Vec3::new(0.0, 2.2, 1.0),
            ),
            triangle(
                Vec3::new(1.0, 2.0, -1.0),
                Vec3::new(1.3, 1.5, -0.8),
                Vec3::new(0.0, 2.2, 1.0),
            ),
            triangle(
                Vec3::new(-2.0, 0.0, 2.5),
                Vec3::new(2.0, 0.3, 2.5),
                Vec3::new(0.0, 3.0, 2.0),
            ),
        ],
        rgb,
        false,
    )
    .expect("a mesh light");
    vec![
        Light::Point(PointLight {
            luminaire: None,
            position: Vec3::new(0.3, 2.0, -0.5),
            intensity: rgb,
        }),
        spot(SpotProfile::Linear, Vec3::new(0.0, 2.5, 0.0), -Vec3::Y),
        spot(
            SpotProfile::Hard,
            Vec3::new(1.0, 2.0, 0.5),
            Vec3::new(-0.3, -1.0, 0.2),
        ),
        spot(
            SpotProfile::Smooth {
                cos_inner: 25f32.to_radians().cos(),
            },
            Vec3::new(-1.0, 1.5, -1.0),
            Vec3::new(0.4, -1.0, 0.3),
        ),
        Light::Directional(DirectionalLight {
            direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
            irradiance: rgb,
        }),
        quad(
            Vec3::new(-0.5, 2.9, -0.5),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.2),
            false,
        ),
        quad(
            Vec3::new(-2.9, 0.2, -1.0),
            Vec3::new(0.0, 0.4, 1.5),
            Vec3::new(0.3, 1.0, 0.2),
            true,
        ),
        sphere(Vec3::new(1.5, 1.0, 1.5), 0.4, false),
        sphere(Vec3::new(-1.5, 0.5, 1.0), 0.3, true),
        Light::Mesh(mesh),
    ]
}

/// How far the GPU's point of `light` for `u` may lie from the Rust
/// one (m), and its normal (if any) from the Rust normal; `None` where
/// a mesh's triangle is chosen by a `u.x` within rounding of the
/// cumulative table, so the two sides may pick different triangles.
/// A quad's point o + u·eu + v·ev: three roundings of its terms on
/// each side (6ε of their norms). A sphere's: its direction from
/// `uniform_cone`, whose cos φ and sin φ WGSL may miss by 2⁻¹¹ each,
/// times r, plus the centre's rounding; its normal is that direction
/// (Rust divides y − c by r: 4ε(|y| + |c|)/r more). A mesh's: `u.x`
/// rescaled within the triangle's share `s` from the f32 table (each
/// entry off by ε/2, so the fraction w by 2ε/s + 2ε), moving the point
/// by |∂y/∂w|·Δw = (|e1| + |e2|)·min(Δw/(2√w), √Δw), plus 6ε of the
/// corner and edges.
fn point_tolerance(light: &Light, u: Vec2) -> Option<(f64, f64)> {
    Some(match light {
        Light::Quad(q) => {
            let q = &q.quad;
            (
                6.0 * EPS * (d(q.origin).length() + d(q.edge_u).length() + d(q.edge_v).length()),
                0.0,
            )
        }
        Light::Sphere(s) => {
            let n = 2.0 * SIN_COS_ABSOLUTE + 16.0 * EPS;
            let (c, r) = (d(s.sphere.center).length(), f64::from(s.sphere.radius));
            (
                r * n + 4.0 * EPS * (c + r),
                n + 4.0 * EPS * (2.0 * c + r) / r,
            )
        }
        Light::Mesh(m) => {
            let x = f64::from(u.x);
            let cdf = m.selection_cdf();
            if cdf.iter().any(|&c| (c - x).abs() <= 2.0 * EPS) {
                return None;
            }
            let k = cdf.partition_point(|&c| c <= x).min(cdf.len() - 1);
            let low = if k == 0 { 0.0 } else { cdf[k - 1] };
            let share = cdf[k] - low;
            let w = (x - low) / share;
            let dw = 2.0 * EPS / share + 2.0 * EPS;
            let t = &m.triangles()[k];
            let edges = d(t.e1).length() + d(t.e2).length();
            let moved = edges * (dw / (2.0 * w.sqrt())).min(dw.sqrt());
            (moved + 6.0 * EPS * (d(t.v0).length() + edges), 0.0)
        }
        _ => (0.0, 0.0),
    })
}

#[test]
fn incident_matches_rust_for_each_kind_of_light() {
    let Some(gpu) = support::gpu_or_skip("incident_matches_rust_for_each_kind_of_light") else {
        return;
    };
    let lights = lights_of_each_kind();
    let (gpu_lights, triangles) = gpu_lights(&lights);
    let mut items = Vec::new();
    let mut cases = Vec::new();
    for l in 0..lights.len() {
        for i in 0..1500 {
            let x =
                3.0 * Vec3::new(
                    spread(3 * i) - 0.5,
                    spread(3 * i + 1) - 0.5,
                    spread(3 * i + 2) - 0.5,
                ) * 2.0;
            let u = Vec2::new(spread(5 * i + 7 * l + 1), spread(11 * i + 3 * l + 2));
            items.push([[x.x, x.y, x.z, 0.0], [0.0; 4], [l as f32, u.x, u.y, 0.0]]);
            cases.push((l, x, u));
        }
    }
    let out = evaluate_lights(
        &gpu,
        LightFormula::Incident,
        &gpu_lights,
        &triangles,
        &items,
    )
    .expect("GPU evaluation");
    let mut compared = vec![0usize; lights.len()];
    for ((l, x, u), o) in cases.iter().zip(&out) {
        let light = &lights[*l];
        let rust = light.incident(*x, light.sample_point(*u));
        if check_incident(*l, light, x, u, rust, o) {
            compared[*l] += 1;
        }
    }
    // Every light is compared where it shines (a sixth of the receivers
    // at least).
    for (l, n) in compared.iter().enumerate() {
        assert!(*n > 250, "light #{l}: {n} receivers lit");
    }
}

/// Compares the GPU's `o` (direction and distance, irradiance and
/// validity) with Rust's `rust` for light #`l` seen from `x` through its
/// point for `u` (`Light::sample_point`); says whether it was lit and
/// compared.
fn check_incident(
    l: usize,
    light: &Light,
    x: &Vec3,
    u: &Vec2,
    rust: Option<Incident>,
    o: &[[f32; 4]; 2],
) -> bool {
    let y = light.sample_point(*u);
    let gpu_valid = o[1][3] == 1.0;
    let (gpu_dir, gpu_dist) = (Vec3::new(o[0][0], o[0][1], o[0][2]), o[0][3]);
    let gpu_irr = Vec3::new(o[1][0], o[1][1], o[1][2]);
    let context = format!("light #{l} {light:?}, x = {x}, u = {u}: GPU {o:?} vs Rust {rust:?}");
    if let Light::Directional(sun) = light {
        // Copied, not computed: exact.
        assert!(
            gpu_valid && gpu_dir == -sun.direction && gpu_dist == INFINITE,
            "{context}"
        );
        assert_eq!(gpu_irr, sun.irradiance, "{context}");
        return true;
    }
    let Some((dy, dn)) = point_tolerance(light, *u) else {
        return false;
    };
    let y = y.expect("a point").position;
    // y − x: the points' error and a rounding of each coordinate on
    // each side; its direction moves by 2δ/d, plus 6ε for the square
    // root and division; its length by δ + 4ε·d.
    let dist = d(y - *x).length();
    let dto = dy + 2.0 * EPS * (d(*x).length() + d(y).length());
    let ddir = 2.0 * dto / dist + 6.0 * EPS;
    // The cosine the emission depends on (a spot's cos θ from its
    // axis, an area light's cos θ_y), its error, and the range of the
    // emission over that uncertainty (a spot's profile, rounding
    // included as 4ε more of the cosine; |cos θ_y| itself), which also
    // says where the two sides may disagree about any light at all.
    let (scale, emission, demission) = match light {
        Light::Point(p) => (p.intensity, 1.0, 0.0),
        Light::Spot(s) => {
            let c = -((y - *x) / dist as f32).dot(s.direction);
            let dc = (ddir + 4.0 * EPS * (1.0 + f64::from(c.abs() + s.cos_cutoff.abs()))) as f32;
            let f = s.falloff(c);
            let range = [c - dc, c + dc]
                .map(|c| (s.falloff(c) - f).abs())
                .into_iter()
                .fold(0.0, f32::max);
            (s.intensity, f64::from(f), f64::from(range) + 8.0 * EPS)
        }
        _ => {
            let (radiance, normal, two_sided) = match light {
                Light::Quad(q) => (q.radiance, q.quad.normal, q.two_sided),
                Light::Sphere(s) => (
                    s.radiance,
                    (y - s.sphere.center) / s.sphere.radius,
                    s.two_sided,
                ),
                Light::Mesh(m) => (
                    m.radiance,
                    light
                        .sample_point(*u)
                        .and_then(|p| p.normal)
                        .expect("a normal"),
                    m.two_sided,
                ),
                _ => unreachable!(),
            };
            let cos_y = -d(normal).dot(d(y - *x)) / dist;
            let cos_y = if two_sided { cos_y.abs() } else { cos_y };
            // L·A/d² with A = 1/(1/A) (two divisions); a mesh's
            // density share/A_k from its f32 table: 1.5ε/share more.
            let density = match light {
                Light::Mesh(m) => {
                    let cdf = m.selection_cdf();
                    let k = cdf
                        .partition_point(|&c| c <= f64::from(u.x))
                        .min(cdf.len() - 1);
                    let share = cdf[k] - if k == 0 { 0.0 } else { cdf[k - 1] };
                    1.5 * EPS / share + 8.0 * EPS
                }
                _ => 6.0 * EPS,
            };
            let area = f64::from(light.area());
            (
                radiance * (area / (dist * dist)) as f32,
                cos_y.max(0.0),
                ddir + dn + 4.0 * EPS + cos_y.abs() * density,
            )
        }
    };
    let scale = match light {
        Light::Point(_) | Light::Spot(_) => scale / (dist * dist) as f32,
        _ => scale,
    };
    // I·e/d²: the emission's error, and e times the relative error of
    // 1/d² (2δ/d for d, 8ε for the squares and divisions).
    let dirr =
        |channel: f32| f64::from(channel) * (demission + emission * (2.0 * dto / dist + 8.0 * EPS));
    match rust {
        Some(inc) => {
            if !gpu_valid {
                // Only where the emission is within its error of 0.
                assert!(emission <= demission, "{context}");
                return false;
            }
            assert!(
                d(gpu_dir - inc.direction).length() <= ddir,
                "{context} (direction, tolerance {ddir})"
            );
            let dd = dto + 4.0 * EPS * dist;
            assert!(
                (f64::from(gpu_dist) - f64::from(inc.distance)).abs() <= dd,
                "{context} (distance, tolerance {dd})"
            );
            for c in 0..3 {
                let tol = dirr(scale[c]);
                assert!(
                    (f64::from(gpu_irr[c]) - f64::from(inc.irradiance[c])).abs() <= tol,
                    "{context} (irradiance {c}, tolerance {tol})"
                );
            }
            return true;
        }
        None => {
            if gpu_valid {
                assert!(demission >= emission, "{context}: only the GPU sees light");
                for c in 0..3 {
                    assert!(
                        f64::from(gpu_irr[c]) <= dirr(scale[c]),
                        "{context} (irradiance {c} where Rust has none)"
                    );
                }
            }
        }
    }
    false
}

/// The light of a sphere sampled in the cone it subtends from `x`
/// (`sample_incident` vs `SphereLight::sample_incident`): `None` where
/// the receiver is within rounding of the threshold between cone and
/// area sampling, or its axis of the orthonormal frame's switch (z = 0),
/// where the sides may legitimately take different branches. Else the
/// error bounds of one side, doubled: cos θmax = √(1 − r²/d²) off by
/// 2ε/cos θmax + 2ε; cos θ = 1 − u(1 − cos θmax) by that and 3ε more; sin θ
/// by min(Δ/(2 sin θ), √Δ) of Δ = 2Δcos θ + 2ε; the direction by sin θ·2⁻¹⁰
/// (WGSL's sin and cos), the frame's and the axis's rounding and Δsin θ +
/// Δcos θ, doubled by the normalisation; the distance d·cos − √(r² −
/// d² sin²) by d·Δc and the root's own min(Δ/(2√·), √Δ); the light
/// L·2π(1 − cos θmax), which the GPU forms by a difference the CPU
/// avoids, by Δcos θmax/(1 − cos θmax) + 8ε relatively.
fn sphere_cone_check(s: &SphereLight, x: Vec3, u: Vec2, o: &[[f32; 4]; 2]) -> Option<()> {
    let (c, r) = (d(s.sphere.center), f64::from(s.sphere.radius));
    let xd = d(x);
    let dist = (c - xd).length();
    let ratio = dist * dist / (r * r);
    if (ratio - (1.0 + 1e-4)).abs() <= 1e-5 || ratio < 1.0 + 1e-4 {
        return None;
    }
    let axis = (c - xd) / dist;
    let daxis = 4.0 * EPS * (xd.length() + c.length()) / dist + 4.0 * EPS;
    if axis.z.abs() <= daxis {
        return None;
    }
    let (rust, _) = s.sample_incident(x, u).expect("a sample from outside");
    let cos_max = (1.0 - 1.0 / ratio).sqrt();
    let dcos_max = 2.0 * EPS / cos_max + 2.0 * EPS;
    let cos_t = 1.0 - f64::from(u.x) * (1.0 - cos_max);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let dcos = dcos_max + 3.0 * EPS;
    let dsq = 2.0 * dcos + 2.0 * EPS;
    let dsin = (dsq / (2.0 * sin_t)).min(dsq.sqrt());
    let dframe = 4.0 * daxis;
    let ddir = 2.0
        * (2.0
            * (sin_t * 2.0 * SIN_COS_ABSOLUTE + dsin + dcos + sin_t * dframe + daxis + 6.0 * EPS)
            + 4.0 * EPS);
    let dc = ddir + daxis + 3.0 * EPS;
    let cc = d(rust.direction).dot(axis).min(1.0);
    let arg = (r * r - dist * dist * (1.0 - cc * cc)).max(0.0);
    let darg = dist * dist * 2.0 * dc + 4.0 * EPS * (r * r + dist * dist);
    let droot = if arg > 0.0 {
        (darg / (2.0 * arg.sqrt())).min(darg.sqrt())
    } else {
        darg.sqrt()
    };
    let ddist = 2.0 * (dist * dc + droot + 4.0 * EPS * dist);
    let rel = 2.0 * (dcos_max / (1.0 - cos_max) + 8.0 * EPS);
    let context = format!("sphere {s:?}, x = {x}, u = {u}: GPU {o:?} vs Rust {rust:?}");
    assert!(o[1][3] == 1.0, "{context}: no GPU sample");
    let gpu_dir = Vec3::new(o[0][0], o[0][1], o[0][2]);
    assert!(
        d(gpu_dir - rust.direction).length() <= ddir,
        "{context} (direction, tolerance {ddir})"
    );
    assert!(
        (f64::from(o[0][3]) - f64::from(rust.distance)).abs() <= ddist,
        "{context} (distance, tolerance {ddist})"
    );
    for (k, &gpu) in o[1][..3].iter().enumerate() {
        let tol = rel * f64::from(rust.irradiance[k]);
        assert!(
            (f64::from(gpu) - f64::from(rust.irradiance[k])).abs() <= tol,
            "{context} (irradiance {k}, tolerance {tol})"
        );
    }
    Some(())
}

#[test]
fn sample_incident_matches_sample_li() {
    let Some(gpu) = support::gpu_or_skip("sample_incident_matches_sample_li") else {
        return;
    };
    let lights = lights_of_each_kind();
    let (gpu_lights, triangles) = gpu_lights(&lights);
    let mut items = Vec::new();
    let mut cases = Vec::new();
    let scale = 16_777_216.0f32;
    for (l, light) in lights.iter().enumerate() {
        for i in 0..1500 {
            let mut x = 6.0
                * Vec3::new(
                    spread(3 * i) - 0.5,
                    spread(3 * i + 1) - 0.5,
                    spread(3 * i + 2) - 0.5,
                );
            // A third of a sphere's receivers near it (inside, and out to
            // 3r), where its cone is widest and area sampling takes over.
            if let Light::Sphere(s) = light
                && i % 3 == 0
            {
                x = s.sphere.center
                    + direction(i) * s.sphere.radius * (0.5 + 2.5 * spread(13 * i + 5));
            }
            let k = [spread(5 * i + 7 * l + 1), spread(11 * i + 3 * l + 2)]
                .map(|v| (v * scale).floor());
            items.push([
                [x.x, x.y, x.z, 0.0],
                [k[0], k[1], 0.0, 0.0],
                [l as f32, 0.0, 0.0, 0.0],
            ]);
            cases.push((l, x, Vec2::new(k[0] / scale, k[1] / scale)));
        }
    }
    let out = evaluate_lights(
        &gpu,
        LightFormula::SampleIncident,
        &gpu_lights,
        &triangles,
        &items,
    )
    .expect("GPU evaluation");
    let mut compared = vec![0usize; lights.len()];
    for ((l, x, u), o) in cases.iter().zip(&out) {
        let light = &lights[*l];
        let lit = match light {
            Light::Sphere(s)
                if (s.sphere.center - *x).length_squared()
                    > s.sphere.radius.powi(2) * (1.0 + 1e-4) =>
            {
                sphere_cone_check(s, *x, *u, o).is_some()
            }
            Light::Quad(q) if q.is_rectangle() => {
                // Within SOLID_ANGLE_REACH diagonals of its centre a
                // rectangle is sampled in solid angle, beyond by area;
                // receivers whose side of that sphere rounding could
                // change are left out.
                let diagonal = q.quad.edge_u + q.quad.edge_v;
                let reach = SOLID_ANGLE_REACH * diagonal.length();
                let from_centre = (*x - (q.quad.origin + 0.5 * diagonal)).length();
                if (from_centre / reach - 1.0).abs() < 1e-4 {
                    false
                } else if from_centre < reach {
                    rectangle_check(q, *x, *u, o).is_some()
                } else {
                    let sampled = light.sample_li(*x, *u).map(|(i, _)| i);
                    check_incident(*l, light, x, u, sampled, o)
                }
            }
            _ => check_incident(*l, light, x, u, light.sample_li(*x, *u).map(|(i, _)| i), o),
        };
        if lit {
            compared[*l] += 1;
        }
    }
    for (l, n) in compared.iter().enumerate() {
        assert!(*n > 250, "light #{l}: {n} receivers lit");
    }
}

/// WGSL's bound on `atan2`'s error (`acos` inherits it): 4096 ULP.
const ATAN_ULP: f64 = 4096.0;

/// A rectangle's light sampled in its solid angle (`sample_incident` vs
/// `QuadLight::sample_incident`): where the two samples may differ by
/// the acos bounds, the sample is checked to lie on the rectangle and
/// the light to be L·Ω within the solid angle's bound of
/// tests/formulas.rs (per corner angle g: 4096ε·g from acos, 16ε/sin g
/// from its argument, 2·10⁻⁸ for Rust's acos; 5 sums of 2π), plus the
/// frame's rounding on the GPU (its edges normalised there: 4ε of the
/// coordinates at each corner, moving Ω by at most 2δ/d per corner at
/// distance d); both sides agree on whether it shines, which depends
/// only on x's side of its plane. `None` below 0.05 sr, where the bound
/// grows as 1/sin g.
fn rectangle_check(q: &QuadLight, x: Vec3, u: Vec2, o: &[[f32; 4]; 2]) -> Option<()> {
    let rust = q.sample_incident(x, u);
    let context = format!("rectangle {q:?}, x = {x}, u = {u}: GPU {o:?} vs Rust {rust:?}");
    let Some((inc, pdf)) = rust else {
        assert!(o[1][3] == 0.0, "{context}: only the GPU sees light");
        return None;
    };
    let omega = 1.0 / f64::from(pdf);
    if omega < 0.05 {
        return None;
    }
    assert!(o[1][3] == 1.0, "{context}: no GPU light");
    let quad = &q.quad;
    let corners = [
        quad.origin,
        quad.origin + quad.edge_u,
        quad.origin + quad.edge_u + quad.edge_v,
        quad.origin + quad.edge_v,
    ]
    .map(|c| d(c - x));
    let normal = |k: usize| corners[k].cross(corners[(k + 1) % 4]).normalize();
    let dc = 4.0
        * EPS
        * (d(x).length()
            + d(quad.origin).length()
            + d(quad.edge_u).length()
            + d(quad.edge_v).length());
    let tolerance: f64 = (0..4)
        .map(|k| {
            let g = (-normal(k).dot(normal((k + 1) % 4)))
                .clamp(-1.0, 1.0)
                .acos();
            ATAN_ULP * EPS * g + 2.0 * 8.0 * EPS / g.sin() + 2e-8 + 2.0 * dc / corners[k].length()
        })
        .sum::<f64>()
        + 5.0 * EPS * std::f64::consts::TAU;
    for (k, &gpu) in o[1][..3].iter().enumerate() {
        let tol = f64::from(q.radiance[k]) * (tolerance + 4.0 * EPS * omega);
        assert!(
            (f64::from(gpu) - f64::from(inc.irradiance[k])).abs() <= tol,
            "{context} (irradiance {k}, tolerance {tol})"
        );
    }
    // x + direction·distance on the rectangle: the sample's own slack
    // (2ε of its coordinates) and 4ε of x and the distance.
    let (dir, dist) = (d(Vec3::new(o[0][0], o[0][1], o[0][2])), f64::from(o[0][3]));
    let p = d(x) + dir * dist - d(quad.origin);
    let slack = dc + 4.0 * EPS * dist + 2.0 * EPS * p.length();
    let (eu, ev) = (d(quad.edge_u), d(quad.edge_v));
    let (a, b) = (p.dot(eu) / eu.length(), p.dot(ev) / ev.length());
    assert!(
        a >= -slack && a <= eu.length() + slack && b >= -slack && b <= ev.length() + slack,
        "{context}: GPU sample at ({a}, {b}) off the rectangle (slack {slack})"
    );
    assert!(
        p.dot(d(quad.normal)).abs() <= slack,
        "{context}: GPU sample off the plane"
    );
    Some(())
}
