//! The volumetric path tracer: furnace tests, energy, and convergence.
mod common;

use common::Loaded;
use common::{
    estimate_ray, estimate_ray_with, mean_and_stderr, pixel_distances, render, repo, scene,
};
use glam::Vec3;
use tyndall::ray::Ray;
use tyndall::settings::Strategies;
use tyndall::{IntegratorKind, RenderSettings, Rgb};

/// A closed box of emitters of radiance 2 around fog of the given albedo.
/// With `sampled`, the walls are `[[lights]]` quads facing in and volpath
/// uses every strategy. Without, they are emissive quad shapes (the same
/// lights) and volpath finds them only by phase and BSDF sampling (no
/// NEE, equiangular samples or connections): every path then ends on a
/// wall with MIS weight 1 and throughput exactly 1 at albedo 1, so the
/// furnace is exact.
fn furnace(albedo: f32, sampled: bool) -> Loaded {
    furnace_with(albedo, sampled, "")
}

/// [`furnace`] with more scene text (shapes inside the box).
fn furnace_with(albedo: f32, sampled: bool, extra: &str) -> Loaded {
    let (lo, hi) = (-2.0f32, 2.0f32);
    // Corners listed so that (c1 − c0) × (c3 − c0) points into the box.
    let faces = [
        [[lo, lo, lo], [lo, hi, lo], [lo, hi, hi], [lo, lo, hi]], // x = lo, normal +x
        [[hi, lo, lo], [hi, lo, hi], [hi, hi, hi], [hi, hi, lo]], // x = hi, normal −x
        [[lo, lo, lo], [lo, lo, hi], [hi, lo, hi], [hi, lo, lo]], // y = lo, normal +y
        [[lo, hi, lo], [hi, hi, lo], [hi, hi, hi], [lo, hi, hi]], // y = hi, normal −y
        [[lo, lo, lo], [hi, lo, lo], [hi, hi, lo], [lo, hi, lo]], // z = lo, normal +z
        [[lo, lo, hi], [lo, hi, hi], [hi, hi, hi], [hi, lo, hi]], // z = hi, normal −z
    ];
    let mut text = format!(
        "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nfov_y_deg = 60\n\
         [render]\nintegrator = \"volpath\"\n\
         [fog]\nsigma_t = 0.8\nalbedo = {albedo}\ng = 0.5\nbox = {{ min = [-2, -2, -2], max = [2, 2, 2] }}\n\
         [materials.wall]\ntype = \"emissive\"\nradiance = 2.0\n"
    );
    for f in faces {
        let corners = format!("{:?}", f.map(|c| c.map(|v| v as f64)));
        if sampled {
            text += &format!("[[lights]]\ntype = \"quad\"\ncorners = {corners}\nradiance = 2.0\n");
        } else {
            text +=
                &format!("[[shapes]]\ntype = \"quad\"\ncorners = {corners}\nmaterial = \"wall\"\n");
        }
    }
    let mut desc = scene(&(text + extra));
    if !sampled {
        desc.settings.strategies = Strategies {
            surface_hits: true,
            medium_hits: true,
            ..Strategies::NONE
        };
    }
    desc
}

/// Albedo-1 fog inside a uniform emitter: every path keeps throughput 1
/// (free-flight sampling weighs an event by the albedo) and ends on a
/// wall of radiance 2, so every pixel is exactly 2.
#[test]
fn furnace_with_emissive_walls_is_exact() {
    let desc = furnace(1.0, false);
    let image = render(&desc, |s| {
        s.width = 16;
        s.height = 16;
        s.spp = 8;
    });
    for p in image.pixels() {
        assert!((*p - Rgb::splat(2.0)).abs().max_element() < 1e-5, "{p}");
    }
}

/// A refractive glass sphere inside the albedo-1 furnace: a dielectric
/// interface only redirects light (reflection or refraction, chosen with
/// the Fresnel probabilities), so every pixel is still exactly 2 — the
/// sphere is invisible, whatever its index.
#[test]
fn furnace_with_dielectric_sphere_is_exact() {
    for ior in [1.33, 1.5, 2.4] {
        let desc = furnace_with(
            1.0,
            false,
            &format!(
                "[materials.glass]\ntype = \"dielectric\"\nior = {ior}\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, -0.6]\nradius = 0.8\nmaterial = \"glass\"\n"
            ),
        );
        let image = render(&desc, |s| {
            s.width = 12;
            s.height = 12;
            s.spp = 8;
        });
        for p in image.pixels() {
            assert!(
                (*p - Rgb::splat(2.0)).abs().max_element() < 1e-5,
                "ior {ior}: {p}"
            );
        }
    }
}

/// The same box with its walls as sampled quad lights: NEE and phase
/// sampling share the light by MIS, so single samples vary, but the mean
/// is 2 within 5 standard errors along several rays.
#[test]
fn furnace_with_light_walls_has_mean_of_emitter() {
    let desc = furnace(1.0, true);
    for dir in [
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(0.3, 0.5, -0.2),
        Vec3::new(-0.7, 0.1, 0.4),
    ] {
        let ray = Ray::new(Vec3::new(0.0, 0.0, 1.0), dir);
        let (mean, stderr) = estimate_ray(&desc, IntegratorKind::Volpath, 0.1, ray, 4096);
        for c in 0..3 {
            assert!(
                (mean[c] - 2.0).abs() <= 5.0 * stderr[c] + 1e-4,
                "{dir}: {mean} ± {stderr}"
            );
        }
        assert!(
            stderr.x > 0.0 && stderr.x < 0.05,
            "MIS keeps the variance moderate: {stderr}"
        );
    }
}

/// Energy never grows with albedo < 1: every pixel of the furnace is
/// below the emitter's radiance, and less albedo gives less light.
#[test]
fn energy_does_not_grow_with_albedo_below_one() {
    let mean_of = |albedo: f32| {
        let image = render(&furnace(albedo, false), |s| {
            s.width = 8;
            s.height = 8;
            s.spp = 32;
        });
        for p in image.pixels() {
            assert!(p.max_element() <= 2.0 + 1e-5, "albedo {albedo}: {p}");
        }
        image.pixels().iter().map(|p| p.x as f64).sum::<f64>() / image.pixels().len() as f64
    };
    let (low, mid, high) = (mean_of(0.3), mean_of(0.7), mean_of(0.95));
    assert!(low < mid && mid < high && high < 2.0, "{low} {mid} {high}");
}

/// The Monte Carlo error falls like 1/√spp: the relative MSE between two
/// independent renders (twice the variance of one) drops about 4× for 4×
/// the samples. Per-pixel terms give the standard error of each mean; the
/// ratio must be 4 within the error propagated from both (and at least
/// 2, which no 1/√spp estimator misses by chance at these sizes).
#[test]
fn error_falls_like_inverse_sqrt_spp() {
    let desc =
        common::load_native(&repo().join("scenes/reference/fog-spot-sphere.toml")).expect("scene");
    let pair = |spp: u32| {
        let shot = |seed: u64| {
            render(&desc, |s| {
                s.width = 80;
                s.height = 60;
                s.spp = spp;
                s.integrator = IntegratorKind::Volpath;
                s.seed = seed;
            })
        };
        let (a, b) = (shot(1), shot(2));
        mean_and_stderr(&pixel_distances(&a, &b, &b))
    };
    let ((low, low_se), (high, high_se)) = (pair(8), pair(32));
    let ratio = low / high;
    let ratio_se = ratio * ((low_se / low).powi(2) + (high_se / high).powi(2)).sqrt();
    assert!(
        (ratio - 4.0).abs() <= 4.0 * ratio_se && ratio > 2.0,
        "ratio {ratio:.2} ± {ratio_se:.2}"
    );
}

/// Asserts that `volpath` limited to one scattering event and `single`
/// agree along rays from `origin` to each target, within 5 combined
/// standard errors, and that each ray sees light well above its noise.
fn assert_depth_one_matches_single(
    desc: &Loaded,
    origin: Vec3,
    targets: &[Vec3],
    volpath_samples: u32,
    single_samples: u32,
) {
    let settings = RenderSettings {
        max_depth: 1,
        ..desc.settings
    };
    for &target in targets {
        let ray = Ray::new(origin, target - origin);
        let with = |integrator| RenderSettings {
            integrator,
            ..settings
        };
        let (vp, vp_se) =
            estimate_ray_with(desc, with(IntegratorKind::Volpath), ray, volpath_samples);
        let (single, single_se) =
            estimate_ray_with(desc, with(IntegratorKind::Single), ray, single_samples);
        for c in 0..3 {
            let tol = 5.0 * (vp_se[c].powi(2) + single_se[c].powi(2)).sqrt() + 1e-5;
            assert!(
                (vp[c] - single[c]).abs() <= tol,
                "{target}: volpath {vp} ± {vp_se} vs single {single} ± {single_se}"
            );
        }
        assert!(
            single.x > 20.0 * single_se.x,
            "{target}: the ray must see light, got {single} ± {single_se}"
        );
    }
}

/// Limited to one scattering event, `volpath` computes what `single`
/// does; both converge to the references (see reference.rs). Here, along
/// fixed rays through a spot's beam, their means agree.
#[test]
fn depth_one_matches_single_along_rays() {
    let desc = common::load_native(&repo().join("scenes/fig07-spot-sphere.toml")).expect("scene");
    let targets = [
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::new(0.4, 2.0, 0.1),
        Vec3::new(1.2, 0.0, 0.5),
    ];
    assert_depth_one_matches_single(&desc, Vec3::new(0.0, 2.2, 7.5), &targets, 16384, 4096);
}

/// An area light in fog, limited to one scattering event: `volpath`
/// (free flights, equiangular segments, NEE and phase sampling with MIS)
/// and `single` (equiangular towards an area-sampled point, MIS with
/// distance sampling) are independent estimators of the same
/// in-scattering; their means along rays through the glow agree.
#[test]
fn area_light_in_fog_depth_one_matches_single() {
    let desc = scene(
        r#"
        [camera]
        position = [0, 1, 4]
        look_at = [0, 1, 0]
        fov_y_deg = 40
        [fog]
        sigma_t = 0.6
        albedo = 0.9
        g = 0.3
        [materials.floor]
        type = "diffuse"
        reflectance = 0.5
        [[shapes]]
        type = "quad"
        corners = [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]]
        material = "floor"
        [[lights]]
        type = "quad"
        corners = [[-0.3, 2, -0.3], [0.3, 2, -0.3], [0.3, 2, 0.3], [-0.3, 2, 0.3]]
        radiance = 10
        "#,
    );
    let targets = [
        Vec3::new(0.0, 1.9, 0.0),
        Vec3::new(0.2, 1.0, 0.0),
        Vec3::new(0.1, 0.0, 0.0),
    ];
    assert_depth_one_matches_single(&desc, Vec3::new(0.0, 1.0, 4.0), &targets, 32768, 8192);
}

/// The furnace filled by the `[[media]]` volume `medium` (TOML) instead
/// of its fog.
fn volume_furnace(sampled: bool, medium: &str) -> Loaded {
    let mut loaded = furnace_with(1.0, sampled, medium);
    loaded.desc.fog = None;
    let settings = loaded.settings;
    let mut without_fog = common::Loaded::new(loaded.desc).expect("builds");
    without_fog.settings = settings;
    without_fog
}

/// Grey smoke of albedo 1 from procedural noise inside the uniform
/// emitter, tracked by delta tracking: every path keeps throughput 1 and
/// ends on a wall, so every pixel is exactly 2.
#[test]
fn furnace_with_noise_volume_is_exact() {
    let desc = volume_furnace(
        false,
        "[[media]]\nsigma_t = 3.0\nalbedo = 1.0\ng = 0.4\n\
         box = { min = [-1.5, -1.5, -1.5], max = [1.5, 1.5, 1.5] }\n\
         density = \"noise\"\nfrequency = 4\nbias = 0.3\n",
    );
    let image = render(&desc, |s| {
        s.width = 12;
        s.height = 12;
        s.spp = 8;
    });
    for p in image.pixels() {
        assert!((*p - Rgb::splat(2.0)).abs().max_element() < 1e-5, "{p}");
    }
}

/// RGB extinction: a volume whose σt differs per channel, albedo 1,
/// inside the furnace of sampled light walls. Spectral tracking reweights
/// each channel, so single paths differ from 2, but every channel's mean
/// is 2 within 5 standard errors.
#[test]
fn furnace_with_rgb_extinction_has_mean_of_emitter() {
    let desc = volume_furnace(
        true,
        "[[media]]\nsigma_t = [0.3, 1.0, 2.5]\nalbedo = 1.0\ng = 0.2\n",
    );
    for dir in [Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.5, -0.3, 0.4)] {
        let ray = Ray::new(Vec3::new(0.0, 0.0, 1.0), dir);
        let (mean, stderr) = estimate_ray(&desc, IntegratorKind::Volpath, 0.1, ray, 8192);
        for c in 0..3 {
            assert!(
                (mean[c] - 2.0).abs() <= 5.0 * stderr[c] + 1e-4,
                "{dir}: {mean} ± {stderr}"
            );
        }
    }
}

/// Asserts that `base` (a scene without media) filled with the medium
/// `medium` (TOML keys) as `[fog]` and as a uniform `[[media]]` volume
/// renders the same along rays from `origin` to each target: the two are
/// independent estimators (closed-form flights, equiangular sampling and
/// light-vertex connections against delta and ratio tracking). Means of
/// `n` samples must agree within 5 combined standard errors, and the fog
/// estimate must see light.
fn assert_fog_matches_volume(base: &str, medium: &str, origin: Vec3, targets: &[Vec3], n: u32) {
    let fog = scene(&format!("{base}\n[fog]\n{medium}"));
    let volume = scene(&format!("{base}\n[[media]]\n{medium}"));
    for &target in targets {
        let ray = Ray::new(origin, target - origin);
        let (a, a_se) = estimate_ray(&fog, IntegratorKind::Volpath, 0.1, ray, n);
        let (b, b_se) = estimate_ray(&volume, IntegratorKind::Volpath, 0.1, ray, n);
        for c in 0..3 {
            let tol = 5.0 * (a_se[c].powi(2) + b_se[c].powi(2)).sqrt() + 1e-5;
            assert!(
                (a[c] - b[c]).abs() <= tol,
                "{target}: fog {a} ± {a_se} vs volume {b} ± {b_se}"
            );
        }
        assert!(a.x > 20.0 * a_se.x, "{target}: {a} ± {a_se}");
    }
}

/// The same homogeneous medium as `[fog]` and as a uniform `[[media]]`
/// volume, with multiple scattering, a spot and an area light: the means
/// along rays through the fog and onto the floor agree.
#[test]
fn fog_and_uniform_volume_agree() {
    let base = r#"
        [camera]
        position = [0, 1, 4]
        look_at = [0, 1, 0]
        fov_y_deg = 40
        [materials.floor]
        type = "diffuse"
        reflectance = 0.6
        [[shapes]]
        type = "quad"
        corners = [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]]
        material = "floor"
        [[lights]]
        type = "quad"
        corners = [[-1, 2.4, -1], [1, 2.4, -1], [1, 2.4, 1], [-1, 2.4, 1]]
        radiance = 3
        [[lights]]
        type = "spot"
        position = [-1.5, 1.8, 0]
        look_at = [0.5, 0.5, 0]
        cutoff_deg = 20
        intensity = 20
        "#;
    let medium =
        "sigma_t = 0.7\nalbedo = 0.9\ng = 0.3\nbox = { min = [-2, 0, -2], max = [2, 2.5, 2] }\n";
    let targets = [
        Vec3::new(0.0, 1.5, 0.0),
        Vec3::new(0.3, 0.7, 0.0),
        Vec3::new(-0.5, 0.0, 0.5),
        Vec3::new(0.1, 0.0, -0.2),
    ];
    assert_fog_matches_volume(base, medium, Vec3::new(0.0, 1.0, 4.0), &targets, 16384);
}

/// Light-vertex connections from a diffuse floor: dense fog around a
/// small bright lamp, where the glow under the lamp lights the floor
/// mostly through one more scattering. The fog (connections, four-way
/// MIS) and the equal uniform volume (no connections) must agree on the
/// floor's radiance.
#[test]
fn floor_lit_through_the_glow_agrees_with_volume() {
    let base = r#"
        [camera]
        position = [0, 1, 3]
        look_at = [0, 0, 0]
        fov_y_deg = 40
        [materials.floor]
        type = "diffuse"
        reflectance = 0.8
        [[shapes]]
        type = "quad"
        corners = [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]]
        material = "floor"
        [[lights]]
        type = "quad"
        corners = [[-0.2, 1, -0.2], [0.2, 1, -0.2], [0.2, 1, 0.2], [-0.2, 1, 0.2]]
        radiance = 40
        "#;
    let medium =
        "sigma_t = 1.5\nalbedo = 0.95\ng = 0.0\nbox = { min = [-3, 0, -3], max = [3, 1.2, 3] }\n";
    let targets = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.6, 0.0, -0.3)];
    assert_fog_matches_volume(base, medium, Vec3::new(0.0, 1.0, 3.0), &targets, 32768);
}

/// A camera deep in dense fog (found by fuzzing): the room of
/// fog-room-multi seen from 255 units away through σt 0.3, an optical
/// depth of ~76. The camera path's flight densities underflow f32 there,
/// and the light-vertex connections' weights were ∞/∞: 24 of 64 samples
/// NaN at 8×8, 1 spp. No sample may be dropped.
#[test]
fn camera_deep_in_fog_gives_no_nan() {
    let path = repo().join("scenes/reference/fog-room-multi.toml");
    let text = std::fs::read_to_string(&path).expect("scene");
    let far = text.replacen(
        "position = [0.0, 1.2, 4.2]",
        "position = [255, 1.2, 4.2]",
        1,
    );
    assert_ne!(far, text, "the test needs the camera moved");
    let desc = scene(&far);
    let settings = RenderSettings {
        width: 8,
        height: 8,
        spp: 1,
        ..desc.settings
    };
    let render = tyndall::render(&desc.scene, &settings, &|_| {}).expect("render");
    assert_eq!(render.stats.invalid_samples, 0);
}
