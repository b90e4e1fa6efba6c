//! Hostile input (issue 11): every case that crashed, hung, exhausted
//! memory or rendered silently wrong, each from a minimal input. Each is
//! refused with a message naming the file and place, or handled.
mod common;

use common::Loaded;
use glam::Vec3;
use std::time::Instant;
use tyndall::accel::{Geometry, Primitive};
use tyndall::lights::Light;
use tyndall::ray::Ray;
use tyndall::settings::VisibilityMode;
use tyndall::shapes::{Shape, Sphere};
use tyndall::{IntegratorKind, RenderSettings};
use tyndall_load::LegacyOptions;
use tyndall_load::mesh::{MeshTransform, parse_obj_mesh};
use tyndall_load::{SceneError, SourceText};

const CAMERA: &str = "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\n";

fn parse(text: &str) -> Result<Loaded, SceneError> {
    common::parse_native(&SourceText::new("scene.toml", text))
}

fn error(text: &str) -> String {
    match parse(text) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// Asserts the error names `scene.toml:line:` and contains `words`.
fn assert_at(e: &str, line: usize, words: &str) {
    assert!(
        e.starts_with(&format!("scene.toml:{line}:")),
        "wrong place: {e}"
    );
    assert!(e.contains(words), "`{words}` not in: {e}");
}

fn legacy_error(text: &str) -> String {
    match common::parse_legacy(
        &SourceText::new("scene.obj", text),
        LegacyOptions::default(),
    ) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e.to_string(),
    }
}

// --- Coordinates -----------------------------------------------------

/// obvhs panicked (`bvh2_to_cwbvh.rs: index out of bounds`) on a sphere
/// of radius 1e20 beside small ones; now refused where it is written.
#[test]
fn huge_sphere_is_refused_at_its_radius() {
    let text = format!(
        "{CAMERA}[materials.m]\ntype = \"diffuse\"\nreflectance = 0.5\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1e20\nmaterial = \"m\"\n"
    );
    assert_at(&error(&text), 11, "radius");
    let far = text
        .replace("radius = 1e20", "radius = 1")
        .replace("center = [0, 0, 0]", "center = [0, 0, 3e38]");
    assert_at(&error(&far), 10, "too far out");
}

/// A legacy vertex at 3e38 crashed the BVH build.
#[test]
fn far_legacy_vertex_is_refused_at_its_place() {
    let e = legacy_error("v 0 0 0\nv 1 0 0\nv 3e38 1 0\n");
    assert!(e.starts_with("scene.obj:3:3:"), "{e}");
    assert!(e.contains("too far out"), "{e}");
}

/// At the coordinate limit the BVH still finds what a linear scan finds:
/// spheres from 10⁻³ to 10⁹ across, rays through each small one.
#[test]
fn bvh_agrees_with_a_linear_scan_up_to_the_coordinate_limit() {
    let limit = tyndall::limits::MAX_COORDINATE;
    // The widest scene the loaders accept: largest radii at the largest
    // coordinates, 4·limit across.
    let mut spheres = vec![
        Sphere {
            center: Vec3::new(0.0, 0.0, -limit),
            radius: limit * 0.999,
        },
        Sphere {
            center: Vec3::splat(limit),
            radius: limit,
        },
        Sphere {
            center: Vec3::splat(-limit),
            radius: limit,
        },
    ];
    for i in 0..40 {
        let x = (i as f32 - 20.0) * 0.1;
        spheres.push(Sphere {
            center: Vec3::new(x, (i % 7) as f32 * 0.05, (i % 5) as f32 * 0.1),
            radius: 1e-3 * (1 + i % 4) as f32,
        });
    }
    let primitives: Vec<Primitive> = spheres
        .iter()
        .map(|s| Primitive {
            shape: Shape::Sphere(*s),
            material: 0,
        })
        .collect();
    let geometry = Geometry::new(primitives.clone());
    for (k, target) in spheres.iter().enumerate().skip(3) {
        for origin in [Vec3::new(0.0, 0.0, 10.0), Vec3::new(3.0, 2.0, 8.0)] {
            let ray = Ray::new(origin, (target.center - origin).normalize());
            let scan = primitives
                .iter()
                .enumerate()
                .filter_map(|(i, p)| p.shape.intersect(&ray, f32::INFINITY).map(|t| (t, i)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let hit = geometry.intersect(&ray, f32::INFINITY);
            assert_eq!(
                hit.map(|h| (h.t, h.primitive as usize)),
                scan,
                "sphere {k} from {origin}"
            );
        }
    }
}

/// Geometry built past the limit by other means than the loaders (a
/// sphere of radius 1e20 beside small ones panicked in obvhs) falls back
/// to a linear scan and still intersects correctly.
#[test]
fn geometry_past_the_limit_does_not_panic() {
    let mut primitives = vec![Primitive {
        shape: Shape::Sphere(Sphere {
            center: Vec3::new(0.0, 0.0, -2e20),
            radius: 1e20,
        }),
        material: 0,
    }];
    for i in 0..8 {
        primitives.push(Primitive {
            shape: Shape::Sphere(Sphere {
                center: Vec3::new(i as f32, 0.0, 0.0),
                radius: 0.25,
            }),
            material: 0,
        });
    }
    let geometry = Geometry::new(primitives);
    let ray = Ray::new(Vec3::new(3.0, 0.0, 10.0), Vec3::NEG_Z);
    let hit = geometry.intersect(&ray, f32::INFINITY).expect("a hit");
    assert_eq!(hit.primitive, 4);
    assert!((hit.t - 9.75).abs() < 1e-4, "{}", hit.t);
}

// --- Files -------------------------------------------------------------

/// `/dev/zero` as a scene reached 8.4 GB before failing; as a mesh, 17 GB
/// and an abort. Both now fail after reading a bounded prefix.
#[test]
fn endless_files_are_refused_quickly() {
    if !std::path::Path::new("/dev/zero").exists() {
        return;
    }
    let start = Instant::now();
    let e = common::load_native(std::path::Path::new("/dev/zero"))
        .err()
        .expect("refused");
    assert!(e.to_string().contains("never ends"), "{e}");
    let e = tyndall_load::mesh::load_obj_mesh(std::path::Path::new("/dev/zero"), &identity())
        .err()
        .expect("refused");
    assert!(e.contains("/dev/zero") && e.contains("never ends"), "{e}");
    // A grid reads its header first: `/dev/zero` has none.
    let e = tyndall_load::tgrid::read(std::path::Path::new("/dev/zero")).expect_err("refused");
    assert!(e.contains("/dev/zero") && e.contains("header"), "{e}");
    assert!(start.elapsed().as_secs_f32() < 10.0);
}

fn identity() -> MeshTransform {
    MeshTransform {
        translate: Vec3::ZERO,
        scale: Vec3::ONE,
        rotate_deg: Vec3::ZERO,
    }
}

/// The mesh reader followed `mtllib` (to `/dev/zero`: 17 GB); the scene
/// ignores mesh materials, so the line is not followed at all.
#[test]
fn mtllib_is_not_followed() {
    let obj = b"mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n";
    let mesh = parse_obj_mesh(obj, &identity()).expect("the mesh loads");
    assert_eq!(mesh.triangles.len(), 1);
}

/// A mesh placed beyond the coordinate limit is refused.
#[test]
fn mesh_vertices_beyond_the_limit_are_refused() {
    let obj = b"v 0 0 0\nv 1 0 0\nv 0 1e16 0\nf 1 2 3\n";
    let e = parse_obj_mesh(obj, &identity()).err().expect("refused");
    assert!(e.contains("vertex 3") && e.contains("too far out"), "{e}");
}

// --- Densities and steps -------------------------------------------------

/// Noise at frequency 1024 with 8 octaves never finished loading (a dense
/// scan of frequency³ lattice points per majorant cell).
#[test]
fn highest_noise_frequency_loads_quickly() {
    let text = format!(
        "{CAMERA}[[media]]\nsigma_t = 1.0\nalbedo = 0.5\nbox = {{ min = [-1, -1, -1], max = [1, 1, 1] }}\n\
         density = \"noise\"\nfrequency = 1024\noctaves = 8\n"
    );
    let start = Instant::now();
    parse(&text).expect("loads");
    let secs = start.elapsed().as_secs_f32();
    assert!(secs < 10.0, "took {secs} s");
}

fn fog_scene(render: &str) -> String {
    format!(
        "{CAMERA}[render]\n{render}\n[fog]\nsigma_t = 0.5\nalbedo = 0.8\n\
         box = {{ min = [-2, -2, -2], max = [2, 2, 2] }}\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = 1\n"
    )
}

/// `step = 3e-7` looped forever (an f32 counter stops at 2²⁴) and
/// `step = 1e-45` rendered no fog at all: both now refused up front, with
/// the smallest step that would do.
#[test]
fn march_steps_beyond_the_bound_are_refused() {
    let desc = parse(&fog_scene("integrator = \"march\"\nstep = 3e-7")).unwrap();
    for step in [3e-7, 1e-45] {
        // 1e-45 comes from the command line (the scene file refuses
        // denormal steps on its own).
        let s = settings(&desc, |s| s.step = step);
        let e = s.validate(&desc.scene).unwrap_err().to_string();
        assert!(e.contains("steps per ray") && e.contains("at least"), "{e}");
    }
    // The longest segment is the fog box's diagonal, 4·√3: a step just
    // above diagonal / MAX_MARCH_STEPS passes.
    let min_step = 4.0 * 3f64.sqrt() / tyndall::settings::MAX_MARCH_STEPS as f64;
    let desc = parse(&fog_scene(&format!(
        "integrator = \"march\"\nstep = {}",
        min_step * 1.01
    )))
    .unwrap();
    desc.settings
        .validate(&desc.scene)
        .expect("within the bound");
}

/// `sigma_t = [1, 1e9, 1]` under volpath did not finish an 8×8 image in
/// 60 s; now refused at `sigma_t` with the reason.
#[test]
fn uneven_rgb_extinction_is_refused_with_the_reason() {
    let text = format!(
        "{CAMERA}[[media]]\nsigma_t = [1, 1e9, 1]\nalbedo = 0.5\n\
         box = {{ min = [-1, -1, -1], max = [1, 1, 1] }}\n"
    );
    assert_at(&error(&text), 6, "times apart");
    let zero = text.replace("[1, 1e9, 1]", "[1, 0, 1]");
    assert_at(&error(&zero), 6, "a channel of 0");
    // Within the ratio: accepted.
    parse(&text.replace("[1, 1e9, 1]", "[1, 100, 1]")).expect("within the ratio");
}

/// A dense non-uniform medium would take sigma_t × diagonal tentative
/// collisions per ray where the density is far below its bound.
#[test]
fn dense_non_uniform_media_are_refused() {
    let text = format!(
        "{CAMERA}[[media]]\nsigma_t = 1e9\nalbedo = 0.5\n\
         box = {{ min = [-1, -1, -1], max = [1, 1, 1] }}\ndensity = \"noise\"\nbias = 1\n"
    );
    assert_at(&error(&text), 6, "diagonal");
}

// --- Memory, threads, samples ------------------------------------------

fn settings(desc: &Loaded, f: impl FnOnce(&mut RenderSettings)) -> RenderSettings {
    let mut s = desc.settings;
    f(&mut s);
    s
}

/// 32768² committed 12.6 GB at once; shadow maps at 16384² around a
/// point light 12.3 GB. Both refused up front, saying how much they need.
#[test]
fn renders_beyond_the_memory_limit_are_refused_with_the_amount() {
    let desc = parse(&fog_scene("")).unwrap();
    let big = settings(&desc, |s| {
        s.width = 32768;
        s.height = 32768;
    });
    let e = big.validate(&desc.scene).unwrap_err().to_string();
    // 48 bytes a pixel: the f64 sums, the resolved image and the file.
    assert!(e.contains("48.0 GiB") && e.contains("32768×32768"), "{e}");
    let maps = settings(&desc, |s| {
        s.visibility = VisibilityMode::Maps { resolution: 16384 };
    });
    let e = maps.validate(&desc.scene).unwrap_err().to_string();
    assert!(e.contains("6 shadow-map faces of 16384² texels"), "{e}");
    let fine = settings(&desc, |s| {
        s.width = 4096;
        s.height = 4096;
    });
    fine.validate(&desc.scene).expect("4096² fits");
}

/// The light paths' exact sums (48 bytes a pixel, for the whole image):
/// 4096² with volpath and a dielectric is counted, and is within the
/// limit; 8192² is not.
#[test]
fn light_tracer_films_are_counted() {
    let text = format!(
        "{}[materials.glass]\ntype = \"dielectric\"\nior = 1.5\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 0.5\nmaterial = \"glass\"\n",
        fog_scene("integrator = \"volpath\"")
    );
    let desc = parse(&text).unwrap();
    let at = |side: u32| {
        settings(&desc, |s| {
            s.width = side;
            s.height = side;
        })
    };
    let (bytes, what) = at(4096).memory_estimate(&desc.scene);
    assert!(what.contains("light-path sums"), "{what}");
    assert!(bytes >= 2 * 4096 * 4096 * 48, "{bytes}");
    at(4096).validate(&desc.scene).expect("fits");
    let e = at(8192).validate(&desc.scene).unwrap_err().to_string();
    assert!(e.contains("light-path sums"), "{e}");
}

/// `--threads 100000` spawned threads until the PID space ran out; now
/// capped at the machine's parallelism with a warning.
#[test]
fn threads_are_capped_with_a_warning() {
    let desc = parse(&fog_scene("")).unwrap();
    let s = settings(&desc, |s| s.threads = Some(100_000));
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    assert_eq!(s.worker_threads(), Some(cores));
    assert!(
        s.warnings(&desc.scene)
            .iter()
            .any(|w| w.contains("100000 threads"))
    );
}

/// `--spp 4294967295` was accepted.
#[test]
fn samples_per_pixel_are_bounded() {
    let desc = parse(&fog_scene("")).unwrap();
    let s = settings(&desc, |s| s.spp = u32::MAX);
    assert!(
        s.validate(&desc.scene)
            .unwrap_err()
            .to_string()
            .contains("at most")
    );
    assert_at(&error(&fog_scene("spp = 4294967295")), 6, "spp");
}

// --- Degenerate lights and cameras ------------------------------------

/// `direction = [0, -1, -1.5e38]` normalised to zero (the squared length
/// overflowed) and the spot lit nothing; now it is a valid direction.
#[test]
fn huge_direction_components_still_give_a_unit_direction() {
    let text = format!(
        "{CAMERA}[[lights]]\ntype = \"spot\"\nposition = [0, 1, 0]\n\
         direction = [0, -1, -1.5e38]\ncutoff_deg = 30\nintensity = 1\n"
    );
    let desc = parse(&text).unwrap();
    let Light::Spot(spot) = &desc.scene.lights()[0] else {
        panic!("a spot light");
    };
    assert!(
        (spot.direction - Vec3::NEG_Z).length() < 1e-6,
        "{}",
        spot.direction
    );
}

/// Intensities that overflow to infinity are refused where written.
#[test]
fn overflowing_emission_is_refused() {
    let text =
        format!("{CAMERA}[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\npower = 3e38\n");
    assert_at(&error(&text), 8, "too large");
    // Legacy: a spotlight's intensity is `emitted` × area.
    let e = legacy_error(
        "v -1e9 -1e9 0\nv 1e9 -1e9 0\nv 1e9 1e9 0\nv -1e9 1e9 0\nmaterial\nemitted 1e20 1e20 1e20\nc 30\nm 0\nf 1 2 3 4\n",
    );
    assert!(
        e.starts_with("scene.obj:9:1:") && e.contains("intensity"),
        "{e}"
    );
}

/// A legacy scene with no camera, far from the origin, put its default
/// camera on its own target (every ray NaN, a black image).
#[test]
fn degenerate_default_camera_is_refused() {
    let e = legacy_error(
        "v 0 0 1e9\nv 0.001 0 1e9\nv 0.001 0.001 1e9\nv 0 0.001 1e9\nmaterial\ndiffuse 1 1 1\nm 0\nf 1 2 3 4\n",
    );
    assert!(e.contains("default camera"), "{e}");
}

/// Renders of small accepted scenes drop no samples, and the statistics
/// carry the count (zero here; the CLI warns when it is not).
#[test]
fn statistics_count_dropped_samples() {
    let desc = parse(&fog_scene("width = 8\nheight = 8\nspp = 1")).unwrap();
    for integrator in [
        IntegratorKind::March,
        IntegratorKind::Single,
        IntegratorKind::Volpath,
    ] {
        let s = settings(&desc, |s| s.integrator = integrator);
        let render = tyndall::render(&desc.scene, &s, &|_| {}).unwrap();
        assert_eq!(render.stats.invalid_samples, 0);
        assert_eq!(render.stats.samples, 64);
    }
}

/// Found by the fuzzer: legacy reflectances far above 1 (`diffuse 1e15
/// 0.54 0.54`, `reflective 3e37 0.8 0.8`) overflowed paths to infinity and
/// dropped samples as NaN; now refused where written.
#[test]
fn legacy_reflectance_above_one_is_refused() {
    for field in ["diffuse 1e15 0.5 0.5", "reflective 3e37 0.8 0.8"] {
        let e = legacy_error(&format!("material\n{field}\n"));
        assert!(e.starts_with("scene.obj:2:"), "{e}");
        assert!(e.contains("at most 1"), "{e}");
    }
}

/// Found by fuzzing: a medium filling all space with `sigma_t = 1e-30`
/// scattered ~10³⁰ units away and every `volpath` sample was NaN; now
/// refused at `sigma_t`. A bounded box of it is fine (flights leave it).
#[test]
fn vanishing_extinction_filling_all_space_is_refused() {
    let text = format!(
        "{CAMERA}[[media]]\nsigma_t = 1e-30\nalbedo = 1.0\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 2, 0]\nintensity = 10\n"
    );
    assert_at(&error(&text), 6, "too thin");
    let boxed = text.replace(
        "albedo = 1.0\n",
        "albedo = 1.0\nbox = { min = [-1, -1, -1], max = [1, 1, 1] }\n",
    );
    let desc = parse(&boxed).expect("a bounded thin medium loads");
    let s = settings(&desc, |s| {
        s.width = 8;
        s.height = 8;
        s.spp = 1;
        s.integrator = IntegratorKind::Volpath;
    });
    let render = tyndall::render(&desc.scene, &s, &|_| {}).unwrap();
    assert_eq!(render.stats.invalid_samples, 0);
}

/// Found by fuzzing: `background_color 1e20 0 0` decoded from sRGB (a
/// power of 2.4) to infinite radiance, and every sample that left the
/// scene was NaN; now refused where written.
#[test]
fn legacy_background_beyond_the_emission_limit_is_refused() {
    let e = legacy_error("v 0 0 0\nbackground_color 1e20 0 0\n");
    assert!(e.starts_with("scene.obj:2:18:"), "{e}");
    assert!(e.contains("too large"), "{e}");
}

/// A spot's `look_at` a denormal distance from its position normalised to
/// NaN (the squared length underflowed to 0); now a unit direction.
#[test]
fn spot_look_at_a_tiny_distance_away_gives_a_unit_direction() {
    let text = format!(
        "{CAMERA}[[lights]]\ntype = \"spot\"\nposition = [0, 1, 0]\n\
         look_at = [0, 1, 1e-40]\ncutoff_deg = 30\nintensity = 1\n"
    );
    let desc = parse(&text).unwrap();
    let Light::Spot(spot) = &desc.scene.lights()[0] else {
        panic!("a spot light");
    };
    assert!(
        (spot.direction - Vec3::Z).length() < 1e-6,
        "{}",
        spot.direction
    );
}

/// A legacy camera whose `up` is too short to normalise in f32 gave NaN
/// rays; it is refused, naming the up vector.
#[test]
fn legacy_camera_up_too_short_is_refused() {
    let e = legacy_error(
        "PerspectiveCamera {\ncamera_position < 0, 0, 5 >\npoint_of_interest < 0, 0, 0 >\nup < 0, 1e-30, 0 >\nangle 40\n}\n",
    );
    assert!(
        e.starts_with("scene.obj:1:1:") && e.contains("up vector must be a non-zero"),
        "{e}"
    );
}

/// A march visits every light at every step: the step bound counts
/// steps × lights, and a scene holds at most 1024 lights.
#[test]
fn march_work_counts_lights_and_lights_are_bounded() {
    let one = parse(&fog_scene("integrator = \"march\"")).unwrap();
    // 4·√3 / 0.001 ≈ 6928 steps: fine with one light.
    let s = settings(&one, |s| s.step = 1e-3);
    s.validate(&one.scene).expect("one light");
    let light = "[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = 1\n";
    let many = parse(&(fog_scene("integrator = \"march\"") + &light.repeat(31))).unwrap();
    let e = s.validate(&many.scene).unwrap_err().to_string();
    assert!(e.contains("32 light(s)"), "{e}");
    let too_many = fog_scene("") + &light.repeat(1024);
    let e = error(&too_many);
    assert!(e.contains("at most 1024 lights"), "{e}");
    // The scene's own light ends on line 14; the 1025th light's `type` is
    // the second line of the 1024th four-line copy.
    assert!(
        e.starts_with(&format!("scene.toml:{}:", 14 + 4 * 1023 + 2)),
        "{e}"
    );
}

/// Found by fuzzing: fog `albedo = 3e38` (accepted for `march`) made the
/// scattered radiance infinite, and a denormal fog `sigma_t = 1e-45` in a
/// box made `volpath` samples NaN. Both refused where written, and from
/// the command line.
#[test]
fn extreme_fog_is_refused() {
    let scene = fog_scene("");
    assert_at(
        &error(&scene.replace("albedo = 0.8", "albedo = 3e38")),
        9,
        "at most 100",
    );
    assert_at(
        &error(&scene.replace("sigma_t = 0.5", "sigma_t = 1e-45")),
        8,
        "sigma_t",
    );
    assert_at(
        &error(&scene.replace("sigma_t = 0.5", "sigma_t = 3e38")),
        8,
        "sigma_t",
    );
    let mut desc = parse(&scene).unwrap();
    assert!(
        desc.override_fog(Some(1e-45), None)
            .unwrap_err()
            .contains("--density")
    );
    assert!(
        desc.override_fog(None, Some(1e30))
            .unwrap_err()
            .contains("--albedo")
    );
    // The paper's albedo 10 and a vacuum (0) are fine.
    desc.override_fog(Some(0.0), Some(10.0))
        .expect("the paper's values");
}

// --- Issue 28: the second campaign's core cases ---------------------------

/// 32,768 coincident triangles (a repeated .obj face, or a glTF DAG
/// instancing one mesh) took 30 s in the BVH build: PLOC's merge costs
/// tied everywhere, so one pair merged per sweep. The build boxes' small
/// per-primitive padding breaks the ties. The tree still answers as a
/// linear scan does, for the coincident pile and for a regular row (which
/// tied the same way); the time bound only guards against a hang (the
/// build now takes milliseconds).
#[test]
fn coincident_triangles_build_quickly_and_intersect_exactly() {
    let triangle = |offset: Vec3| {
        Shape::Triangle(
            tyndall::shapes::Triangle::new(offset, offset + Vec3::X, offset + Vec3::Y)
                .expect("triangle"),
        )
    };
    let pile: Vec<Primitive> = (0..32_768)
        .map(|_| Primitive {
            shape: triangle(Vec3::ZERO),
            material: 0,
        })
        .collect();
    let row: Vec<Primitive> = (0..4096)
        .map(|i| Primitive {
            shape: triangle(Vec3::new(i as f32 * 1.5, 0.0, 0.0)),
            material: 0,
        })
        .collect();
    for (name, primitives) in [("pile", pile), ("row", row)] {
        let start = Instant::now();
        let geometry = Geometry::new(primitives.clone());
        assert!(
            start.elapsed().as_secs_f32() < 10.0,
            "{name}: {:?}",
            start.elapsed()
        );
        for k in 0..64 {
            let x = (k as f32 * 0.37) % (if name == "row" { 6000.0 } else { 1.0 });
            let origin = Vec3::new(x + 0.2, 0.25, 5.0);
            let ray = Ray::new(origin, Vec3::new(0.01, -0.02, -1.0).normalize());
            let scan = primitives
                .iter()
                .filter_map(|p| p.shape.intersect(&ray, f32::INFINITY))
                .min_by(f32::total_cmp);
            let hit = geometry.intersect(&ray, f32::INFINITY).map(|h| h.t);
            assert_eq!(hit, scan, "{name}: ray {k}");
            assert_eq!(geometry.occluded(&ray, f32::INFINITY), scan.is_some());
        }
    }
}

/// An emissive sphere 10⁴ radii away gave volpath NaN for every sample
/// (dropped with a warning: a black image, exit 0): the cone it subtends
/// had an infinite density. Now no sample is lost, and the pixels that
/// see the sphere through thin fog hold about its radiance times the
/// transmittance `exp(−σt·(d − r − 5))` (in-scattered light is a
/// fraction Ω/4π ≈ 10⁻⁹ of that: nothing else lights the fog).
#[test]
fn a_far_emissive_sphere_renders_without_nan() {
    let sigma_t = 1e-5f32;
    let text = format!(
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, -10000]\nfov_y_deg = 0.02\n\
         [render]\nwidth = 8\nheight = 8\nspp = 4\nintegrator = \"volpath\"\n\
         [fog]\nsigma_t = {sigma_t}\nalbedo = 0.5\n\
         [materials.e]\ntype = \"emissive\"\nradiance = 100\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, -10000]\nradius = 1\nmaterial = \"e\"\n"
    );
    let desc = parse(&text).expect("scene");
    let render = tyndall::render(&desc.scene, &desc.settings, &|_| {}).expect("render");
    assert_eq!(render.stats.invalid_samples, 0);
    let transmittance = (-(sigma_t as f64) * (10_000.0 - 1.0 - 5.0)).exp();
    // The sphere (0.0057° in radius) fills the middle of the 0.02° view.
    // A loose, noise-proof bound on four samples: each pixel's mean lies
    // between half the transmitted radiance and the unattenuated one
    // (`far_spheres_have_finite_cone_densities` checks the density
    // exactly).
    for (x, y) in [(3, 3), (4, 4), (3, 4), (4, 3)] {
        let p = render.image.pixel(x, y);
        assert!(p.is_finite() && p.x > 0.0, "pixel ({x}, {y}): {p}");
        let expected = 100.0 * transmittance;
        assert!(
            (p.x as f64) <= 100.0 * 1.001 && (p.x as f64) > 0.5 * expected,
            "pixel ({x}, {y}): {p} against {expected}"
        );
    }
}

/// A legacy camera's `angle 179.5` was refused without line or column,
/// under the native format's key (`fov_y_deg`), and with a range
/// ("(0, 180)") that was not the range checked ((0°, 179°]).
#[test]
fn legacy_camera_angle_out_of_range_is_refused_at_its_place() {
    for angle in ["179.5", "0", "1e-9"] {
        let e = legacy_error(&format!(
            "PerspectiveCamera {{\ncamera_position < 0, 0, 5 >\npoint_of_interest < 0, 0, 0 >\nup < 0, 1, 0 >\nangle {angle}\n}}\n"
        ));
        assert!(e.starts_with("scene.obj:5:7:"), "{angle}: {e}");
        assert!(
            e.contains("`angle`") && e.contains("from 0.001° to 179°") && !e.contains("fov_y_deg"),
            "{angle}: {e}"
        );
    }
    // The ends of the range itself are accepted.
    for angle in ["179", "0.001"] {
        common::parse_legacy(
            &SourceText::new("scene.obj", format!(
                "PerspectiveCamera {{\ncamera_position < 0, 0, 5 >\npoint_of_interest < 0, 0, 0 >\nup < 0, 1, 0 >\nangle {angle}\n}}\n"
            )),
            LegacyOptions::default(),
        )
        .unwrap_or_else(|e| panic!("angle {angle}: {e}"));
    }
}

/// volpath in endless albedo-1 fog (figs. 3 and 8) took 28–36 s at
/// 32×32×4 spp: roulette never ended a path, which ran to 65,536 events.
/// An unlimited depth there is now bounded by `LOSSLESS_FOG_DEPTH`, with a
/// warning naming it; a depth the user sets, fog that absorbs, or fog in
/// a box leave the depth alone.
#[test]
fn endless_lossless_fog_bounds_the_path_depth_and_says_so() {
    use tyndall::render::LOSSLESS_FOG_DEPTH;
    use tyndall::settings::UNLIMITED_DEPTH;
    let scene = |fog: &str| {
        parse(&format!(
            "{CAMERA}[render]\nintegrator = \"volpath\"\n[fog]\n{fog}\n\
             [[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = 1\n"
        ))
        .expect("scene")
    };
    let lossless = scene("sigma_t = 0.1\nalbedo = 1");
    let s = lossless.settings;
    assert_eq!(s.max_depth, UNLIMITED_DEPTH);
    assert_eq!(s.path_depth(&lossless.scene), LOSSLESS_FOG_DEPTH);
    let warnings = s.warnings(&lossless.scene);
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("absorbs nothing") && w.contains(&LOSSLESS_FOG_DEPTH.to_string())),
        "{warnings:?}"
    );
    let chosen = settings(&lossless, |s| s.max_depth = 5000);
    assert_eq!(chosen.path_depth(&lossless.scene), 5000);
    assert!(chosen.warnings(&lossless.scene).is_empty());
    for fog in [
        "sigma_t = 0.1\nalbedo = 0.99",
        "sigma_t = 0.1\nalbedo = 1\nbox = { min = [-2, -2, -2], max = [2, 2, 2] }",
    ] {
        let desc = scene(fog);
        assert_eq!(
            desc.settings.path_depth(&desc.scene),
            UNLIMITED_DEPTH,
            "{fog}"
        );
    }
    // The render itself is bounded: at most LOSSLESS_FOG_DEPTH events for
    // each of 8×8×2 paths (at 65,536 events this took seconds).
    let small = settings(&lossless, |s| {
        s.width = 8;
        s.height = 8;
        s.spp = 2;
    });
    let render = tyndall::render(&lossless.scene, &small, &|_| {}).expect("render");
    assert_eq!(render.stats.invalid_samples, 0);
}
