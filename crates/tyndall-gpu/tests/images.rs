//! `--gpu` images against CPU images of the same integrator (issue 14):
//! the GPU march and the CPU march estimate the same image, and so do the
//! GPU's interleaved equiangular single scattering and the CPU `single`
//! — with exact shadow rays, and with shadow maps of the same resolution,
//! which both sides render by the same rules — so their difference is
//! Monte Carlo noise only. Each comparison is against a CPU render with
//! the same visibility mode.
//!
//! The bound, derived rather than tuned: two independent estimates G and C
//! of the same image differ per pixel by E[(G − C)²] = Var G + Var C. The
//! noise of each side is measured from the data, by a second render of
//! that side with another seed: relMSE(G, G') ≈ 2·v_G and relMSE(C, C') ≈
//! 2·v_C (relMSE as `tyndall compare`, the mean over pixels of
//! (c − r)²/(r² + 0.01)). So with no bias, relMSE(G, C) ≈
//! (relMSE(G, G') + relMSE(C, C'))/2 =: expected. Each is a mean over W·H = 3072 pixels,
//! whose spread between runs is a few per cent; the test allows 1.5 ×
//! expected, so a systematic difference whose relMSE is half the noise's
//! fails it. Issue 14's target for converged images, relMSE ≤ 2e-3, is
//! checked too: the noise at these frame counts is below it.
//!
//! One exception to "finite variance": a camera ray passing within a step
//! or so of a point or spot light meets the 1/d² of eq. 1, whose march
//! estimate has unbounded variance (a lattice point may land arbitrarily
//! close to the light). Such pixels — the spot's apex in fig. 3 — are a
//! handful; every mean above is taken over the pixels without the worst
//! 0.1 % (4 of 3072) of that comparison, which leaves any difference
//! spread over the image in full view. `single` comparisons are trimmed
//! the same way (one helper); equiangular sampling cancels the 1/d², so
//! there the trim only drops four of the noisiest pixels.
//!
//! The GPU `single` renders here interleave over a 4×4 tile while the CPU
//! `single` does not interleave at all: the GPU must be unbiased in every
//! pixel, not only on average over a tile.

mod support;

use glam::Vec3;
use std::path::Path;
use tyndall::description::{LightDesc, Origin};
use tyndall::lights::DirectionalLight;
use tyndall::settings::VisibilityMode;
use tyndall::shapes::Bounds;
use tyndall::{Image, IntegratorKind, RenderSettings, Rgb, Scene, SceneDesc};
use tyndall_gpu::{MarchSettings, render};
use tyndall_image::metrics::pixel_errors;
/// relMSE (as `tyndall compare`) over all pixels but the worst 0.1 %
/// (see the module documentation).
fn trimmed_relative_mse(candidate: &Image, reference: &Image) -> f64 {
    let mut errors = pixel_errors(candidate, reference);
    errors.sort_by(f64::total_cmp);
    let kept = errors.len() - errors.len().div_ceil(1000);
    errors[..kept].iter().sum::<f64>() / kept as f64
}

const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;
/// Samples per pixel of each render (CPU) and frames (GPU).
const SPP: u32 = 64;

fn scenes_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// Shadow-map resolution of the map tests: small, so that a map texel
/// covers several pixels and a mismatch in the maps would show.
const MAP_RESOLUTION: u32 = 128;

/// Side of the GPU `single`'s interleaving tile in these tests (the CPU
/// `single` ignores it).
const SINGLE_INTERLEAVE: u32 = 4;

fn settings(
    desc: &SceneDesc,
    seed: u64,
    visibility: VisibilityMode,
    integrator: IntegratorKind,
) -> RenderSettings {
    let interleave = match integrator {
        IntegratorKind::Single => SINGLE_INTERLEAVE,
        _ => desc.settings.interleave,
    };
    RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        spp: SPP,
        seed,
        integrator,
        visibility,
        interleave,
        ..desc.settings
    }
}

fn cpu(scene: &Scene, settings: &RenderSettings) -> Image {
    tyndall::render(scene, settings, &|_| {})
        .expect("CPU render")
        .image
}

fn gpu(gpu: &tyndall_gpu::Gpu, scene: &Scene, settings: &RenderSettings) -> Image {
    let march = MarchSettings::from(settings);
    render(gpu, scene, &march, settings.spp).expect("GPU render")
}

/// Renders `desc` with `integrator` twice on each side, with shadow rays
/// and with maps, and checks the bound of the module documentation.
fn gpu_matches_cpu(name: &str, desc: SceneDesc, integrator: IntegratorKind) {
    let Some(device) = support::gpu_or_skip(name) else {
        return;
    };
    let scene = Scene::build(&desc).expect("scene builds");
    for visibility in [
        VisibilityMode::ShadowRays,
        VisibilityMode::Maps {
            resolution: MAP_RESOLUTION,
        },
    ] {
        let label = format!("{name}, {}, {}", integrator.name(), visibility.name());
        images_agree(&label, &device, &scene, &desc, visibility, integrator);
    }
}

fn images_agree(
    name: &str,
    device: &tyndall_gpu::Gpu,
    scene: &Scene,
    desc: &SceneDesc,
    visibility: VisibilityMode,
    integrator: IntegratorKind,
) {
    let (a, b) = (
        settings(desc, 1, visibility, integrator),
        settings(desc, 2, visibility, integrator),
    );
    let start = std::time::Instant::now();
    let (c1, c2) = (cpu(scene, &a), cpu(scene, &b));
    let cpu_seconds = start.elapsed().as_secs_f64();
    let start = std::time::Instant::now();
    let (g1, g2) = (gpu(device, scene, &a), gpu(device, scene, &b));
    let gpu_seconds = start.elapsed().as_secs_f64();
    eprintln!("{name}: two CPU renders {cpu_seconds:.1} s, two GPU renders {gpu_seconds:.1} s");
    let noise_cpu = trimmed_relative_mse(&c2, &c1);
    let noise_gpu = trimmed_relative_mse(&g2, &g1);
    let expected = 0.5 * (noise_cpu + noise_gpu);
    let measured = trimmed_relative_mse(&g1, &c1);
    eprintln!(
        "{name}: relMSE(GPU, CPU) = {measured:.3e}; noise: CPU {noise_cpu:.3e}, GPU {noise_gpu:.3e}; expected {expected:.3e}"
    );
    assert!(
        measured <= 1.5 * expected,
        "{name}: relMSE(GPU, CPU) = {measured:.3e} exceeds 1.5 × the noise-only {expected:.3e}"
    );
    assert!(
        measured <= 2e-3,
        "{name}: relMSE(GPU, CPU) = {measured:.3e} above issue 14's 2e-3"
    );
}

fn load(file: &str) -> SceneDesc {
    tyndall_load::load(&scenes_dir().join(file), Default::default()).expect("scene loads")
}

#[test]
fn fig07_spot_sphere_matches_cpu_march() {
    gpu_matches_cpu(
        "fig07-spot-sphere",
        load("fig07-spot-sphere.toml"),
        IntegratorKind::March,
    );
}

#[test]
fn fig08_glass_pair_blend_matches_cpu_march() {
    gpu_matches_cpu(
        "fig08-glass-pair",
        load("fig08-glass-pair.toml"),
        IntegratorKind::March,
    );
}

#[test]
fn fig03_spot_in_fog_matches_cpu_march() {
    gpu_matches_cpu(
        "fig03-spot-in-fog",
        load("fig03-spot-in-fog.toml"),
        IntegratorKind::March,
    );
}

#[test]
fn demo_matches_cpu_march() {
    gpu_matches_cpu(
        "demo",
        tyndall_load::demo::load().expect("demo loads"),
        IntegratorKind::March,
    );
}

/// The demo as the viewer runs it: a 4×4 tile sharing out the march's
/// lattice (each pixel evaluates 1/16 of the cells per frame; 64 frames
/// take each residue 4 times), two lights whose reaches start the
/// lattice at different cells, glass and a glossy sphere.
#[test]
fn demo_interleaved_matches_cpu_march() {
    let mut desc = tyndall_load::demo::load().expect("demo loads");
    desc.settings.interleave = 4;
    gpu_matches_cpu("demo interleaved", desc, IntegratorKind::March);
}

/// Interleaved sampling (Keller & Heidrich 2001) with a long step: each
/// pixel's expectation depends on its stratum of the 4×4 tile, so the GPU
/// must give every pixel the CPU's stratum (CPU images with interleave 1
/// and 4 differ by relMSE ≈ 1.6e-4 here at 64×48, 64 spp: twice the
/// GPU's noise at this frame count).
#[test]
fn fig07_interleaved_long_step_matches_cpu_march() {
    let mut desc = load("fig07-spot-sphere.toml");
    desc.settings.interleave = 4;
    desc.settings.step = 0.4;
    gpu_matches_cpu("fig07-spot-sphere interleaved", desc, IntegratorKind::March);
}

/// Fig. 7 through a thin lens focused before the sphere (the sphere and
/// the spot's beam blurred): the GPU's lens rays (`camera_ray`'s lens
/// point and plane of focus) against the CPU's.
#[test]
fn fig07_through_a_thin_lens_matches_cpu_single() {
    let mut desc = load("fig07-spot-sphere.toml");
    desc.camera.value.aperture = tyndall::camera::Aperture::ThinLens {
        radius: 0.25,
        focus_distance: 3.0,
    };
    gpu_matches_cpu("fig07-thin-lens", desc, IntegratorKind::Single);
}

#[test]
fn fig07_spot_sphere_single_matches_cpu_single() {
    gpu_matches_cpu(
        "fig07-spot-sphere",
        load("fig07-spot-sphere.toml"),
        IntegratorKind::Single,
    );
}

#[test]
fn fig03_spot_in_fog_single_matches_cpu_single() {
    gpu_matches_cpu(
        "fig03-spot-in-fog",
        load("fig03-spot-in-fog.toml"),
        IntegratorKind::Single,
    );
}

#[test]
fn demo_single_matches_cpu_single() {
    gpu_matches_cpu(
        "demo",
        tyndall_load::demo::load().expect("demo loads"),
        IntegratorKind::Single,
    );
}

/// One equiangular sample per light on a 4×4 tile: each pixel's own
/// offsets then span only 1/16 of the light's angle per frame, so a pixel
/// whose offsets stayed in its stratum (no per-frame rotation) would
/// see only its sixteenth of the beam. A sun is added, and the fog
/// bounded by a box above the floor (in fog filling all space a sun's
/// light never arrives), which the camera looks into from outside: the
/// sun has no emitting point, so its in-scattered light comes from the
/// distance sample alone, as on the CPU.
#[test]
fn fig07_one_interleaved_sample_and_a_sun_match_cpu_single() {
    let mut desc = load("fig07-spot-sphere.toml");
    desc.settings.volume_samples = 1;
    let fog = &mut desc.fog.as_mut().expect("fig. 7 has fog").value;
    fog.bounds = Some(Bounds::new(
        Vec3::new(-5.0, 0.0, -5.0),
        Vec3::new(5.0, 6.0, 5.0),
    ));
    desc.add_light(
        LightDesc::Directional(DirectionalLight {
            direction: Vec3::new(0.3, -1.0, -0.4).normalize(),
            irradiance: Rgb::new(0.6, 0.5, 0.4),
        }),
        Origin::Code,
    );
    gpu_matches_cpu(
        "fig07-spot-sphere, one sample and a sun",
        desc,
        IntegratorKind::Single,
    );
}

/// Fig. 7 with a grille of 144 small triangles between the spot and the
/// sphere: a BVH several levels deep (the other scenes have a few dozen
/// primitives at most), walked by camera rays, shadow rays and the
/// spot's map texels, against the CPU's own BVH. The grille's shafts
/// and the gaps between them are a few pixels wide here, so a node the
/// walk skipped wrongly, or a leaf it entered without testing, shows.
#[test]
fn fig07_with_a_triangle_grille_matches_cpu_march() {
    let mut desc = load("fig07-spot-sphere.toml");
    let material = desc.add_material(
        tyndall::materials::Material::Opaque(tyndall::materials::Surface::diffuse(Rgb::splat(0.5))),
        Origin::Code,
    );
    const CELLS: usize = 12;
    let cell = 2.0 / CELLS as f32;
    let mut triangles = Vec::new();
    for i in 0..CELLS {
        for j in 0..CELLS {
            let (x, z) = (-1.0 + i as f32 * cell, -1.0 + j as f32 * cell);
            let corner = |dx: f32, dz: f32| Vec3::new(x + dx * cell, 3.0, z + dz * cell);
            triangles.push(tyndall::shapes::Shape::Triangle(
                tyndall::shapes::Triangle::new(
                    corner(0.0, 0.0),
                    corner(1.0, 0.0),
                    corner(0.0, 1.0),
                )
                .expect("a proper triangle"),
            ));
        }
    }
    desc.add_shapes(triangles, material, Origin::Code);
    gpu_matches_cpu("fig07 with a triangle grille", desc, IntegratorKind::March);
}

/// The Cornell box in fog with every kind of area light: its ceiling
/// rectangle (surfaces sample it in solid angle), an emissive sphere
/// (surfaces sample its cone), a two-sided emissive mesh of two
/// triangles of unequal area (its point picked through the area table)
/// and a parallelogram, which surfaces sample by area. Fog points connect
/// to a point of each light uniform by area, on both sides. With maps on
/// these lights keep shadow rays, so the maps run covers the fallback.
fn cornell_with_every_area_light() -> SceneDesc {
    use tyndall::materials::Material;
    use tyndall::shapes::{Quad, Shape, Sphere, Triangle};
    let mut desc = load("cornell-fog.toml");
    // Thinner fog than the scene's, so that the walls' direct light, where
    // surfaces sample the lights differently from fog points, shows.
    desc.fog.as_mut().expect("the box has fog").value.sigma_t = 0.2;
    let emitter = |desc: &mut SceneDesc, radiance: Rgb, two_sided: bool, shapes: Vec<Shape>| {
        let material = desc.add_material(Material::emitter(radiance, two_sided), Origin::Code);
        desc.add_shapes(shapes, material, Origin::Code);
    };
    emitter(
        &mut desc,
        Rgb::new(8.0, 6.0, 4.0),
        false,
        vec![Shape::Sphere(Sphere {
            center: Vec3::new(0.7, 1.1, -0.72),
            radius: 0.15,
        })],
    );
    let triangle = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
        Shape::Triangle(
            Triangle::new(Vec3::from(a), Vec3::from(b), Vec3::from(c)).expect("a proper triangle"),
        )
    };
    emitter(
        &mut desc,
        Rgb::new(2.0, 4.0, 8.0),
        true,
        vec![
            triangle([-0.8, 1.45, 0.3], [-0.4, 1.45, 0.3], [-0.6, 1.75, 0.55]),
            triangle([-0.85, 0.9, 0.55], [-0.6, 0.9, 0.55], [-0.72, 1.1, 0.7]),
        ],
    );
    emitter(
        &mut desc,
        Rgb::new(3.0, 1.0, 1.0),
        false,
        vec![Shape::Quad(
            Quad::new(
                Vec3::new(0.25, 0.9, -0.95),
                Vec3::new(0.3, 0.0, 0.0),
                Vec3::new(0.1, 0.2, 0.0),
                true,
            )
            .expect("a proper parallelogram"),
        )],
    );
    desc
}

#[test]
fn every_area_light_matches_cpu_march() {
    gpu_matches_cpu(
        "cornell with every area light",
        cornell_with_every_area_light(),
        IntegratorKind::March,
    );
}

#[test]
fn every_area_light_matches_cpu_single() {
    gpu_matches_cpu(
        "cornell with every area light",
        cornell_with_every_area_light(),
        IntegratorKind::Single,
    );
}
