//! Light tracing against camera paths.
//!
//! Images are compared over blocks of 8×8 pixels: each block's mean over
//! six independent renders (seeds) has a standard error estimated from
//! their spread, and two estimators must agree within 5 combined standard
//! errors in every block. With 6 renders the spread is itself uncertain
//! (a t-statistic with 5 degrees of freedom), so 5σ is a loose but not
//! vacuous bound: each test also checks that the blocks see light.
mod common;

use common::Loaded;
use common::scene;
use tyndall::camera::Camera;
use tyndall::testing::{LightPaths, light_tracer};
use tyndall::{IntegratorKind, Rgb};

const W: u32 = 32;
const H: u32 = 24;
const BLOCK: u32 = 8;
const SEEDS: u64 = 6;

/// A spot shining down through where a sphere may be, onto a box of fog
/// below it and a floor. The sphere (if any) is outside the fog.
fn spot_scene(sphere: &str) -> Loaded {
    spot_scene_seen_by(sphere, "")
}

/// [`spot_scene`] with `lens` added to its camera table.
fn spot_scene_seen_by(sphere: &str, lens: &str) -> Loaded {
    scene(&format!(
        r#"
        [camera]
        position = [0, 1.2, 4]
        look_at = [0, 0.8, 0]
        fov_y_deg = 45
        {lens}
        [render]
        integrator = "volpath"
        [fog]
        sigma_t = 0.8
        albedo = 0.9
        g = 0.2
        box = {{ min = [-1.5, 0, -1.5], max = [1.5, 1.4, 1.5] }}
        [materials.floor]
        type = "diffuse"
        reflectance = 0.5
        [[shapes]]
        type = "quad"
        corners = [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]]
        material = "floor"
        [[lights]]
        type = "spot"
        position = [0, 3, 0]
        direction = [0, -1, 0]
        cutoff_deg = 25
        intensity = 30
        {sphere}
        "#
    ))
}

fn sphere(ior: f32) -> String {
    format!(
        "[materials.glass]\ntype = \"dielectric\"\nior = {ior}\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 2, 0]\nradius = 0.4\nmaterial = \"glass\"\n"
    )
}

/// Per block, the mean and standard error over seeds of `render(seed)`.
fn block_stats(render: impl Fn(u64) -> Vec<Rgb>) -> Vec<(f64, f64)> {
    let blocks = ((W / BLOCK) * (H / BLOCK)) as usize;
    let mut samples = vec![Vec::new(); blocks];
    for seed in 1..=SEEDS {
        let image = render(seed);
        let mut sums = vec![0.0f64; blocks];
        for y in 0..H {
            for x in 0..W {
                let b = ((y / BLOCK) * (W / BLOCK) + x / BLOCK) as usize;
                let p = image[(y * W + x) as usize];
                sums[b] += (p.x + p.y + p.z) as f64 / (BLOCK * BLOCK) as f64;
            }
        }
        for (b, s) in sums.into_iter().enumerate() {
            samples[b].push(s);
        }
    }
    samples
        .iter()
        .map(|s| {
            let n = s.len() as f64;
            let mean = s.iter().sum::<f64>() / n;
            let var = s.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
            (mean, (var / n).sqrt())
        })
        .collect()
}

fn volpath(desc: &Loaded, spp: u32) -> impl Fn(u64) -> Vec<Rgb> + '_ {
    move |seed| {
        let settings = tyndall::RenderSettings {
            width: W,
            height: H,
            spp,
            seed,
            integrator: IntegratorKind::Volpath,
            ..desc.settings
        };
        tyndall::render(&desc.scene, &settings, &|_| {})
            .expect("render")
            .image
            .pixels()
            .to_vec()
    }
}

fn assert_blocks_agree(what: &str, a: &[(f64, f64)], b: &[(f64, f64)]) {
    let mut lit = 0;
    for (i, ((ma, sa), (mb, sb))) in a.iter().zip(b).enumerate() {
        let tol = 5.0 * (sa * sa + sb * sb).sqrt() + 1e-6;
        assert!(
            (ma - mb).abs() <= tol,
            "{what}, block {i}: {ma:.5} ± {sa:.5} vs {mb:.5} ± {sb:.5}"
        );
        if *ma > 10.0 * sa {
            lit += 1;
        }
    }
    assert!(lit >= a.len() / 2, "{what}: only {lit} blocks see light");
}

/// Every path traced from the light and connected to the camera estimates
/// the same image as the camera paths (no sphere): the camera importance,
/// the connections and the light's emission are measured consistently.
#[test]
fn light_tracing_all_paths_matches_volpath() {
    light_tracing_matches_volpath(&spot_scene(""));
}

/// The same through a thin lens focused in front of the fog: the
/// connections' lens points and film positions (`Camera::project`) and
/// the importance the derivation there keeps must measure what the camera
/// rays through the lens measure, blur included.
#[test]
fn light_tracing_all_paths_matches_volpath_through_a_thin_lens() {
    light_tracing_matches_volpath(&spot_scene_seen_by(
        "",
        "aperture_radius = 0.25\nfocus_distance = 2.5",
    ));
}

fn light_tracing_matches_volpath(desc: &Loaded) {
    let camera = Camera::new(desc.scene.camera(), W, H);
    let traced = block_stats(|seed| {
        let paths = (W * H) as u64 * 256;
        let (image, _) = light_tracer::trace(
            &desc.scene,
            &camera,
            (W, H),
            paths,
            seed,
            u32::MAX,
            LightPaths::All,
        );
        image
    });
    let camera_paths = block_stats(volpath(desc, 256));
    assert_blocks_agree("light tracing vs volpath", &traced, &camera_paths);
}

/// A dielectric sphere of index 1 bends nothing and reflects nothing, so
/// the image must be the one without it; but shadow rays cannot cross it,
/// so all light below it reaches the fog through the caustic light paths.
/// Camera paths plus caustic paths must rebuild the sphere-less image.
#[test]
fn index_matched_sphere_is_invisible_with_caustic_paths() {
    let without = spot_scene("");
    let with = spot_scene(&sphere(1.0));
    let reference = block_stats(volpath(&without, 128));
    let combined = block_stats(volpath(&with, 128));
    assert_blocks_agree("index-matched sphere", &combined, &reference);
    // And the caustic paths carry a real share: without them the fog
    // below the sphere would be dark.
    let camera = Camera::new(with.scene.camera(), W, H);
    let (caustic, _) = light_tracer::trace(
        &with.scene,
        &camera,
        (W, H),
        (W * H) as u64 * 64,
        1,
        u32::MAX,
        LightPaths::Caustic,
    );
    let total: f32 = caustic.iter().map(|p| p.x).sum();
    let reference_total: f64 =
        reference.iter().map(|b| b.0).sum::<f64>() / 3.0 * (BLOCK * BLOCK) as f64;
    assert!(
        total as f64 > 0.2 * reference_total,
        "caustic share {total} of {reference_total}"
    );
}
