//! The environment light (issue 22): furnace tests with closed forms,
//! agreement of the integrators that sample it differently, and bad
//! input. Its references from Mitsuba 3 are in `reference.rs`.
mod common;

use common::{excess_disagreement, mean_and_stderr, render, repo, scene};
use tyndall::settings::VisibilityMode;
use tyndall::{Image, IntegratorKind};
use tyndall_load::SourceText;

/// A white (reflectance 1) sphere seen by a camera, lit by a uniform
/// environment of radiance 1; `extra` adds tables.
fn white_sphere(extra: &str) -> String {
    format!(
        r#"[camera]
position = [0, 0, 4]
look_at = [0, 0, 0]
fov_y_deg = 30

[render]
width = 24
height = 18

[materials.white]
type = "diffuse"
reflectance = 1

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "white"

[[lights]]
type = "environment"
radiance = 1
{extra}"#
    )
}

/// The pixels' mean and its standard error from their scatter. Every
/// pixel of a furnace has the same expectation, so the scatter estimates
/// the pixels' variance.
fn mean_of_channels(image: &Image) -> (f64, f64) {
    let values: Vec<f64> = image
        .pixels()
        .iter()
        .flat_map(|p| [p.x, p.y, p.z])
        .map(f64::from)
        .collect();
    mean_and_stderr(&values)
}

/// The furnace test: a closed white object under a uniform environment of
/// radiance 1 reflects radiance 1 everywhere (it only returns the light it
/// receives, and a convex one receives exactly L·π from its hemisphere;
/// the integrators without interreflection agree, there being none).
/// With shadow maps the environment keeps shadow rays, as area lights do.
/// Every pixel, the sphere's and the sky's, has expectation 1: the image
/// mean must be 1 within 4 standard errors (and f32 rounding). A light 1 %
/// too bright or dark is ≥ 10 standard errors out at these sample counts.
#[test]
fn white_sphere_in_a_uniform_environment_is_white() {
    let desc = scene(&white_sphere(""));
    let maps = VisibilityMode::Maps { resolution: 64 };
    for (kind, visibility) in IntegratorKind::ALL
        .into_iter()
        .flat_map(|k| [(k, VisibilityMode::ShadowRays), (k, maps)])
    {
        let image = render(&desc, |s| {
            s.spp = 64;
            s.integrator = kind;
            s.visibility = visibility;
        });
        let (mean, stderr) = mean_of_channels(&image);
        assert!(
            (mean - 1.0).abs() <= 4.0 * stderr + 1e-5,
            "{kind:?}, {visibility:?}: mean {mean:.5} ± {stderr:.1e}"
        );
        assert!(
            stderr < 1e-3,
            "{kind:?}: the test has no power: {stderr:.1e}"
        );
    }
}

/// The same furnace in a box of fog that scatters without absorbing
/// (albedo 1), and in a volume that does so, the sphere inside them and
/// the camera outside: light is
/// neither made nor lost, so `volpath` (every order of scattering) still
/// sees radiance 1 everywhere — the environment reached through fog by
/// next event estimation at fog events and by phase-sampled paths that
/// leave the box, weighed against each other.
#[test]
fn white_sphere_in_lossless_fog_is_white() {
    let fog = r#"
[fog]
sigma_t = 0.8
albedo = 1
g = 0.4
box = { min = [-2, -2, -2], max = [2, 2, 2] }
"#;
    // The same as a general medium (`[[media]]`, tracked, with RGB
    // extinction): its collisions' NEE and escapes.
    let volume = r#"
[[media]]
sigma_t = [0.4, 0.8, 1.2]
albedo = 1
g = -0.3
box = { min = [-2, -2, -2], max = [2, 2, 2] }
"#;
    // Tracking's collisions are noisier than the fog's free flights.
    for (medium, spp) in [(fog, 64), (volume, 256)] {
        let desc = scene(&white_sphere(medium));
        let image = render(&desc, |s| {
            s.spp = spp;
            s.integrator = IntegratorKind::Volpath;
        });
        let (mean, stderr) = mean_of_channels(&image);
        assert!(
            (mean - 1.0).abs() <= 4.0 * stderr + 1e-5,
            "{medium}: mean {mean:.5} ± {stderr:.1e}"
        );
        assert!(stderr < 2e-3, "the test has no power: {stderr:.1e}");
    }
}

/// The white sphere made a lamp that also reflects (glTF's emission over
/// a base colour): emitting 0.25 over a diffuse reflectance of 0.75
/// under the sky of radiance 1 it leaves 0.25 + 0.75 · 1 = 1, so the
/// furnace stays white — for every integrator, and for `volpath` in
/// lossless fog, where the fog sees the sphere's emission by NEE and by
/// phase-sampled hits weighed against each other, and the sphere
/// reflects the fog's light. A lamp that did not reflect would leave
/// 0.25 on the sphere; one that ignored its emission, 0.75.
#[test]
fn an_emitter_that_reflects_keeps_the_furnace_white() {
    use tyndall::materials::{Material, Surface};
    let fog = r#"
[fog]
sigma_t = 0.8
albedo = 1
g = 0.4
box = { min = [-2, -2, -2], max = [2, 2, 2] }
"#;
    let runs = IntegratorKind::ALL
        .into_iter()
        .map(|k| (k, "", 64))
        .chain([(IntegratorKind::Volpath, fog, 64)]);
    for (kind, medium, spp) in runs {
        let mut desc = scene(&white_sphere(medium)).desc;
        for material in &mut desc.materials {
            material.value = Material::Emissive {
                radiance: tyndall::Rgb::splat(0.25),
                two_sided: false,
                surface: Surface::diffuse(tyndall::Rgb::splat(0.75)),
            };
        }
        let desc = common::Loaded::new(desc).expect("scene");
        let image = render(&desc, |s| {
            s.spp = spp;
            s.integrator = kind;
        });
        let (mean, stderr) = mean_of_channels(&image);
        assert!(
            (mean - 1.0).abs() <= 4.0 * stderr + 1e-5,
            "{kind:?}{}: mean {mean:.5} ± {stderr:.1e}",
            if medium.is_empty() { "" } else { " in fog" }
        );
        assert!(stderr < 2e-3, "the test has no power: {stderr:.1e}");
    }
}

/// The white sphere under a clear coat (glTF's `KHR_materials_clearcoat`
/// at factor 1, a mirror coat, over a white Lambertian base of F0 0):
/// the coat reflects 0.04 of the sky and passes 0.96 to the base, which
/// returns all of it, so the furnace stays white in every integrator —
/// each follows the coat by its own strategy (the camera path's one
/// reflected ray, `volpath`'s lobe choice). A coat that did not dim the
/// base would give 1.04 on the sphere (half the image), one that
/// reflected nothing 0.96.
#[test]
fn a_coated_sphere_keeps_the_furnace_white() {
    use tyndall::materials::{Clearcoat, Material, MetallicRoughness};
    let coated = MetallicRoughness {
        base: tyndall::Rgb::ONE,
        metallic: 0.0,
        roughness: 1.0,
        f0: tyndall::Rgb::ZERO,
        clearcoat: Clearcoat {
            factor: 1.0,
            roughness: 0.0,
        },
    }
    .surface();
    for kind in IntegratorKind::ALL {
        let mut desc = scene(&white_sphere("")).desc;
        for material in &mut desc.materials {
            material.value = Material::Opaque(coated);
        }
        let desc = common::Loaded::new(desc).expect("scene");
        let image = render(&desc, |s| {
            s.spp = 64;
            s.integrator = kind;
        });
        let (mean, stderr) = mean_of_channels(&image);
        assert!(
            (mean - 1.0).abs() <= 4.0 * stderr + 1e-5,
            "{kind:?}: mean {mean:.5} ± {stderr:.1e}"
        );
        assert!(stderr < 2e-3, "the test has no power: {stderr:.1e}");
    }
}

/// `single` (light sampled at the surface point and at the distance
/// sample on each camera ray) and `volpath` limited to one scattering
/// event (NEE at its events weighed against phase- and BSDF-sampled
/// escapes) estimate the same single-scattered image of a mapped sky:
/// the reference scene (a floor, a sphere and a block in a box of fog),
/// and the sky alone through a thick box of fog around the camera, whose
/// pixels are mostly light the fog scattered. For independent renders the
/// disagreement beyond noise ([`excess_disagreement`]) must be within 4
/// standard errors; each check shows it would see a 3 % bias.
#[test]
fn single_and_volpath_agree_under_a_mapped_sky_in_fog() {
    let dir = repo().join("scenes/reference/environment");
    let reference = common::load_native(&dir.join("env-map-fog.toml")).expect("scene");
    let sky = dir.join("sky.exr");
    let haze = scene(&format!(
        r#"[camera]
position = [0, 0.5, 0]
look_at = [1, 0.9, 1]
fov_y_deg = 70

[fog]
sigma_t = 0.6
albedo = 0.9
g = 0.5
box = {{ min = [-3, -3, -3], max = [3, 3, 3] }}

[[lights]]
type = "environment"
map = {:?}
"#,
        sky.display().to_string()
    ));
    // The haze is noisier (one sampled direction per fog point): more
    // samples, so that a 3 % bias stands out.
    for (desc, spp) in [(&reference, 32), (&haze, 256)] {
        let shot = |kind: IntegratorKind, seed: u64| {
            render(desc, |s| {
                s.width = 64;
                s.height = 48;
                s.spp = spp;
                s.integrator = kind;
                s.max_depth = 1;
                s.seed = seed;
            })
        };
        let a = [
            shot(IntegratorKind::Single, 1),
            shot(IntegratorKind::Single, 2),
        ];
        let b = [
            shot(IntegratorKind::Volpath, 3),
            shot(IntegratorKind::Volpath, 4),
        ];
        let (mean, stderr) = excess_disagreement([&a[0], &a[1]], [&b[0], &b[1]], 1.0);
        assert!(
            mean <= 4.0 * stderr,
            "single vs volpath: excess {mean:.3e} is {:.1} standard errors",
            mean / stderr
        );
        let (bmean, bstderr) = excess_disagreement([&a[0], &a[1]], [&b[0], &b[1]], 1.03);
        assert!(
            bmean > 4.0 * bstderr,
            "a 3 % bias should be detected: {:.1} standard errors",
            bmean / bstderr
        );
    }
}

fn native_error(text: &str) -> String {
    match common::parse_native(&SourceText::new("scene.toml", text)) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// An environment without radiance or map, a second one, one beside a
/// background, a turn without a map, a negative radiance, a map that is
/// missing or holds no radiance: errors that name the file and line.
#[test]
fn bad_environments_are_refused() {
    let good = white_sphere("");
    let e = native_error(&good.replace("radiance = 1", ""));
    assert!(
        e.starts_with("scene.toml:") && e.contains("`radiance`"),
        "{e}"
    );
    let e = native_error(&format!(
        "{good}\n[[lights]]\ntype = \"environment\"\nradiance = 2\n"
    ));
    assert!(e.contains("one environment light"), "{e}");
    let e = native_error(&good.replace("height = 18", "height = 18\nbackground = 0.5"));
    assert!(e.contains("`background`"), "{e}");
    let e = native_error(&good.replace("radiance = 1", "map = \"no-such-sky.exr\""));
    assert!(e.contains("no-such-sky.exr") && e.contains("map"), "{e}");
    let e = native_error(&good.replace("radiance = 1", "radiance = 1\nmap_rotate_deg = 30"));
    assert!(e.contains("`map_rotate_deg`"), "{e}");
    let e = native_error(&good.replace("radiance = 1", "radiance = -1"));
    assert!(e.contains("radiance"), "{e}");
    // A PNG is not a map of radiance.
    let png = repo().join("scenes/rig/star.png");
    let e = native_error(&good.replace(
        "radiance = 1",
        &format!("map = {:?}", png.display().to_string()),
    ));
    assert!(e.contains("not an OpenEXR or Radiance HDR"), "{e}");
}

/// A map with a NaN texel is refused naming the file and the texel; an
/// EXR written here of one bright texel loads and lights.
#[test]
fn maps_are_read_and_checked() {
    let dir = std::env::temp_dir().join(format!("tyndall-env-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let write = |name: &str, texels: Vec<tyndall::color::Rgb>| {
        let path = dir.join(name);
        let image = Image::from_pixels(8, 4, texels);
        tyndall_image::write_image(&image, &path, 0.0).expect("write");
        path
    };
    let mut texels = vec![tyndall::color::Rgb::splat(0.5); 32];
    let good = write("good.exr", texels.clone());
    texels[13] = tyndall::color::Rgb::new(0.5, f32::NAN, 0.5);
    let bad = write("bad.exr", texels);
    let map = tyndall_load::images::load_environment_map(&good).expect("map");
    assert_eq!((map.width(), map.height()), (8, 4));
    let e = tyndall_load::images::load_environment_map(&bad).unwrap_err();
    assert!(e.contains("bad.exr") && e.contains("texel (5, 1)"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}
