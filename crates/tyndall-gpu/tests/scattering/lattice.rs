//! The march's lattice (`in_scattered`) and a surface's `direct_lighting`
//! against their Rust twins, with the scene's delta lights (the tolerances
//! and exclusions of the parent file).

use super::*;

/// The march's whole lattice along camera rays (`in_scattered` with one
/// stratum), with the scene's delta lights: the sum over its points t_k
/// of T(a, t_k)·Σ_lights scattered_radiance, each term within the
/// tolerance of `scattered_radiance_matches_rust` for a receiver that may
/// lie 4ε·(|o| + t) apart on the two sides (t_k and the point on the ray
/// computed with or without fused multiply-adds), T's exponent moving
/// with it; the sums' rounding adds 2nε for n terms. A ray is left out
/// when one of its points is a case `comparable` leaves out for some
/// light, or lies within 10⁻⁴ of the fog's exit (where the last point is
/// counted or not).
#[test]
fn march_in_scattered_matches_rust() {
    let Some(f) = fixture_of("march_in_scattered_matches_rust", &scene_text(false)) else {
        return;
    };
    let lights = f.scene.lights();
    assert!(lights.iter().all(Light::is_delta), "delta lights only");
    let fog = f.scene.fog().expect("fog");
    let sigma_t = f64::from(fog.sigma_t);
    let mut cases = Vec::new();
    for i in 0..600 {
        let target = Vec3::new(
            7.0 * spread(3 * i) - 3.5,
            6.0 * spread(3 * i + 1) - 3.5,
            7.0 * spread(3 * i + 2) - 3.5,
        );
        let (ray, t_hit) = camera_ray_towards(&f, target);
        let key = (spread(7 * i + 5) * 16_777_216.0) as u32;
        cases.push((ray, t_hit, key));
    }
    let items: Vec<_> = cases
        .iter()
        .map(|(ray, t_hit, key)| ray_item(ray, *t_hit, *key))
        .collect();
    let out = evaluate_in_scene(&f.gpu, &f.march, SceneFormula::InScattered, &items)
        .expect("GPU evaluation");
    let (mut compared, mut lit) = (0, 0);
    'rays: for ((ray, t_hit, key), o) in cases.iter().zip(&out) {
        let jitter = *key as f32 / 16_777_216.0;
        let rust = twins::march_in_scattered(&f.scene, &f.visibility, *ray, *t_hit, f.step, jitter);
        let gpu = Vec3::new(o[0][0], o[0][1], o[0][2]);
        // The lattice as the Rust march walks it, for the terms' bounds.
        let mut bound = DVec3::ZERO;
        let mut terms = 0usize;
        if let Some((a, b)) = fog.interval(ray, 0.0, *t_hit) {
            let b = b.min(a + tyndall::ray_march::MAX_OPTICAL_DEPTH / fog.sigma_t);
            for k in 0.. {
                let t = a + (jitter + k as f32) * f.step;
                if (f64::from(t) - f64::from(b)).abs() < 1e-4 * (1.0 + f64::from(b)) {
                    continue 'rays;
                }
                if t >= b {
                    break;
                }
                let x = ray.at(t);
                let moved = 4.0 * EPS * (d(ray.origin).length() + f64::from(t));
                let camera_t = (-sigma_t * f64::from(t - a)).exp();
                let camera_tolerance =
                    (3.0 + 2.0 * sigma_t * f64::from(t - a)) * EPS + sigma_t * 2.0 * moved;
                for (l, light) in lights.iter().enumerate() {
                    let Some(inc) = light.incident(x, None) else {
                        // Outside a spot's cone: Rust adds nothing; the
                        // GPU nothing either unless within rounding of
                        // the edge, which `comparable` would catch.
                        if let Light::Spot(s) = light {
                            let cos = (d(x) - d(s.position)).normalize().dot(d(s.direction));
                            if (cos - f64::from(s.cos_cutoff)).abs() < 1e-3 {
                                continue 'rays;
                            }
                        }
                        continue;
                    };
                    let Some(c) = comparable(light, x, Vec2::ZERO) else {
                        continue 'rays;
                    };
                    let Some(irradiance) = irradiance_tolerance(light, x, c.point, moved) else {
                        continue 'rays;
                    };
                    let term = twins::scattered_radiance(
                        &f.scene,
                        &f.visibility,
                        l,
                        None,
                        x,
                        ray.direction,
                    );
                    let dist = f64::from(inc.distance).min(1e6);
                    let tolerance = 2.0 * (irradiance + transport_tolerance(sigma_t, x, dist))
                        + phase_tolerance(inc.direction, ray.direction, x, c.point, moved)
                        + camera_tolerance
                        + 8.0 * EPS;
                    bound += term.as_dvec3() * camera_t * tolerance;
                    terms += 1;
                }
            }
        }
        let rounding = 2.0 * (terms as f64 + 4.0) * EPS;
        for ch in 0..3 {
            let (g, r) = (f64::from(gpu[ch]), f64::from(rust[ch]));
            let tolerance = bound[ch] * f64::from(f.step) + rounding * r.abs() + 1e-30;
            assert!(
                (g - r).abs() <= tolerance,
                "{ray:?} to {t_hit}, jitter {jitter}, channel {ch}: GPU {gpu} vs Rust {rust} \
                 (tolerance {tolerance:.2e}, {terms} terms)"
            );
        }
        compared += 1;
        lit += usize::from(rust.max_element() > 0.0);
    }
    assert!(
        compared > 300 && lit > 250,
        "{compared} rays compared, {lit} lit"
    );
}

/// `direct_lighting` (Σ (ρ/π·cos θ + f_layer)·light_arriving over the
/// lights, one sample each) on surfaces facing up, down and sideways, a
/// third of them with a glossy layer (grey 0.4, roughness 0.2 to 0.9)
/// seen from a tilted direction, with the scene's delta lights: each
/// light's term within `light_arriving`'s tolerance plus cos θ's error
/// over the direction's rounding δ (δ/cos θ relative) and, for the
/// layer, the GGX lobe's change over that rounding (measured: the Rust
/// lobe at the light's direction turned by δ + 8ε each way) plus its own
/// rounding (as `formulas.rs` bounds it); the sum's rounding 2nε for n
/// terms. A receiver is left out when `comparable` leaves it out for some
/// light, or a light lies within 10⁻³ in cosine of its surface's plane.
#[test]
fn direct_lighting_matches_rust() {
    let Some(f) = fixture_of("direct_lighting_matches_rust", &scene_text(false)) else {
        return;
    };
    let lights = f.scene.lights();
    let sigma_t = f64::from(f.scene.fog().expect("fog").sigma_t);
    let diffuse = Vec3::new(0.5, 0.7, 0.9);
    let normals = [Vec3::Y, -Vec3::Y, Vec3::new(0.6, 0.0, 0.8)];
    // (x, normal, (specular, roughness), n: the arriving ray's tilt
    // 0.2 + 0.5·n, as the probe makes it)
    type Receiver = (Vec3, Vec3, (f32, f32), u32);
    let receivers: Vec<Receiver> = cases(1, 3000)
        .into_iter()
        .map(|(_, x, _, i)| {
            let layer = match i % 3 {
                0 => (0.4, 0.2 + 0.7 * ((i * 37 % 100) as f32 / 100.0)),
                _ => (0.0, 0.0),
            };
            (x, normals[i % normals.len()], layer, (i * 53 % 4) as u32)
        })
        .collect();
    let incoming_of = |normal: Vec3, n: u32| {
        (normal.any_orthonormal_pair().0 * (0.2 + 0.5 * n as f32) - normal).normalize()
    };
    let albedo_of = |roughness: f32, incoming: Vec3, normal: Vec3| {
        tyndall::materials::Ggx::new(roughness).map_or(1.0, |g| g.albedo(-incoming.dot(normal)))
    };
    let items: Vec<_> = receivers
        .iter()
        .map(|(x, normal, (specular, roughness), n)| {
            let albedo = albedo_of(*roughness, incoming_of(*normal, *n), *normal);
            [
                [x.x, x.y, x.z, *roughness],
                [normal.x, normal.y, normal.z, *n as f32 + *specular],
                [diffuse.x, diffuse.y, diffuse.z, albedo],
            ]
        })
        .collect();
    let out = evaluate_in_scene(&f.gpu, &f.march, SceneFormula::DirectLighting, &items)
        .expect("GPU evaluation");
    let (mut compared, mut lit, mut glossy) = (0, 0, 0);
    'receivers: for ((x, normal, (specular, roughness), n), o) in receivers.iter().zip(&out) {
        let incoming = incoming_of(*normal, *n);
        let mut bound = DVec3::ZERO;
        let mut terms = 0usize;
        for (l, light) in lights.iter().enumerate() {
            let Some(inc) = light.incident(*x, None) else {
                if let Light::Spot(s) = light {
                    let cos = (d(*x) - d(s.position)).normalize().dot(d(s.direction));
                    if (cos - f64::from(s.cos_cutoff)).abs() < 1e-3 {
                        continue 'receivers;
                    }
                }
                continue;
            };
            let cos = d(*normal).dot(d(inc.direction));
            if cos.abs() < 1e-3 {
                continue 'receivers;
            }
            if cos < 0.0 {
                continue;
            }
            let Some(c) = comparable(light, *x, Vec2::ZERO) else {
                continue 'receivers;
            };
            let arriving =
                twins::light_arriving(&f.scene, &f.visibility, l, *x, Some(*normal), &inc);
            let dist = f64::from(inc.distance).min(1e6);
            let delta =
                16.0 * EPS * (d(*x).length() + d(c.point).length()) / dist.max(1.0) + 8.0 * EPS;
            let tolerance = 2.0 * (c.irradiance + transport_tolerance(sigma_t, *x, dist))
                + delta / cos
                + 8.0 * EPS;
            bound += (arriving * diffuse / std::f32::consts::PI).as_dvec3() * cos * tolerance;
            if *specular > 0.0 {
                let layer = (Vec3::splat(*specular), *roughness);
                let f = |w: Vec3| {
                    f64::from(tyndall::materials::layer_eval(layer, incoming, *normal, w).x)
                };
                let value = f(inc.direction);
                // The lobe's change over the direction's rounding, each
                // way along two directions across it.
                let turn = (delta + 8.0 * EPS) as f32;
                let (a, b) = inc.direction.any_orthonormal_pair();
                let change = [a, -a, b, -b]
                    .into_iter()
                    .map(|t| (f((inc.direction + t * turn).normalize()) - value).abs())
                    .fold(0.0f64, f64::max);
                let h = (inc.direction - incoming).normalize();
                let r2 = f64::from(roughness * roughness);
                let d = f64::from(h.dot(*normal)).powi(2) * (r2 - 1.0) + 1.0;
                let own = 2.0 * (2.0 * (2.0 * 8.0 * EPS + EPS) / d + 16.0 * EPS);
                bound +=
                    (arriving.as_dvec3() * (value * (tolerance + own) + change)).max(DVec3::ZERO);
            }
            terms += 1;
        }
        let rust = twins::direct_lighting(
            &f.scene,
            &f.visibility,
            (diffuse, (Vec3::splat(*specular), *roughness)),
            (*x, incoming),
            *normal,
        );
        let gpu = Vec3::new(o[0][0], o[0][1], o[0][2]);
        let rounding = 2.0 * (terms as f64 + 4.0) * EPS;
        for ch in 0..3 {
            let (g, r) = (f64::from(gpu[ch]), f64::from(rust[ch]));
            let tolerance = bound[ch] + rounding * r.abs() + 1e-30;
            assert!(
                (g - r).abs() <= tolerance,
                "x = {x}, normal {normal}, channel {ch}: GPU {gpu} vs Rust {rust} \
                 (tolerance {tolerance:.2e}, {terms} terms)"
            );
        }
        compared += 1;
        lit += usize::from(rust.max_element() > 0.0);
        glossy += usize::from(*specular > 0.0 && rust.max_element() > 0.0);
    }
    assert!(
        compared > 2000 && lit > 1500 && glossy > 400,
        "{compared} receivers compared, {lit} lit, {glossy} of them glossy"
    );
}
