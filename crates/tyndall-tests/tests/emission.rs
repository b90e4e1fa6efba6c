//! Emitting media (docs/physics.md §2.5): `volpath`'s emission along a
//! ray against closed forms and quadrature written here, Planck's law
//! against Stefan–Boltzmann and the published Planckian locus, and the
//! errors for bad emission input. Tolerances come from the sample counts
//! (standard errors) and from the stated accuracy of each reference.

mod common;

use glam::{IVec3, Vec3};
use std::path::PathBuf;
use tyndall::IntegratorKind;
use tyndall::color::blackbody;
use tyndall::media::volume::Volume;
use tyndall::ray::Ray;

/// A scene with no lights and a black background around one medium
/// (TOML lines), looked at along −z.
fn scene_text(medium: &str) -> String {
    format!(
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov_y_deg = 30\n\n\
         [render]\nintegrator = \"volpath\"\n\n[[media]]\n{medium}\n"
    )
}

/// The fire scene's VDB file (density, temperature, flame).
fn fire_vdb() -> PathBuf {
    common::repo().join("scenes/fire/fire.vdb")
}

/// A scene text written to a file of its own (so that it may name
/// files), loaded.
fn load(name: &str, text: &str) -> Result<common::Loaded, String> {
    let dir = std::env::temp_dir().join(format!("tyndall-emission-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).expect("write scene");
    common::load_any(&path, Default::default()).map_err(|e| e.to_string())
}

fn ray_down_z(x: f32, y: f32) -> Ray {
    Ray {
        origin: Vec3::new(x, y, 5.0),
        direction: Vec3::NEG_Z,
    }
}

/// Asserts `estimate ± 4 standard errors` holds `exact`, per channel
/// (plus 10⁻⁴ relative for f32 rounding over thousands of steps).
fn assert_within_noise(what: &str, (mean, stderr): (Vec3, Vec3), exact: Vec3) {
    for c in 0..3 {
        let bound = 4.0 * stderr[c] + 1e-4 * exact[c].abs();
        assert!(
            (mean[c] - exact[c]).abs() <= bound,
            "{what}, channel {c}: {} ± {} vs exact {}",
            mean[c],
            stderr[c],
            exact[c]
        );
    }
}

/// `∫ T(t)·j(t) dt` along `ray` over `[t0, t1]` by the midpoint rule in
/// `n` steps, with `T` accumulated from the midpoint sum of σt.
fn emission_quadrature(volume: &Volume, ray: &Ray, t0: f32, t1: f32, n: usize) -> Vec3 {
    let dt = ((t1 - t0) / n as f32) as f64;
    let mut depth = glam::DVec3::ZERO;
    let mut sum = glam::DVec3::ZERO;
    for i in 0..n {
        let x = ray.at(t0 + (i as f32 + 0.5) * dt as f32);
        let sigma = volume.extinction_at(x).as_dvec3();
        // Transmittance to the midpoint: the steps before plus half this one.
        let t = (-(depth + sigma * (0.5 * dt))).exp();
        sum += t * volume.emission_at(x).as_dvec3() * dt;
        depth += sigma * dt;
    }
    sum.as_vec3()
}

/// A homogeneous absorbing, emitting cube of side d = 2, RGB extinction:
/// `L = e·(1 − exp(−σt·d))/σt` per channel in closed form (emission
/// `e` per unit length, no scattering, nothing behind).
#[test]
fn homogeneous_emitting_slab_matches_the_closed_form() {
    let sigma = Vec3::new(1.0, 2.0, 0.5);
    let e = Vec3::new(3.0, 2.0, 1.0);
    let loaded = common::scene(&scene_text(
        "sigma_t = [1.0, 2.0, 0.5]\nalbedo = 0\nbox = { min = [-1, -1, -1], max = [1, 1, 1] }\nemission = [3.0, 2.0, 1.0]",
    ));
    let exact = e * (Vec3::ONE - (-sigma * 2.0).exp()) / sigma;
    let estimate = common::estimate_ray(
        &loaded,
        IntegratorKind::Volpath,
        0.0,
        ray_down_z(0.1, -0.2),
        20_000,
    );
    assert_within_noise("slab", estimate, exact);
}

/// A medium that emits but does not absorb (σt = 0): `L = e·d`. Tracking
/// has no extinction majorant to walk by, so the volume's majorant floor
/// must supply the tentative collisions.
#[test]
fn pure_emitter_without_extinction_is_found() {
    let loaded = common::scene(&scene_text(
        "sigma_t = 0\nalbedo = 0\nbox = { min = [-1, -1, -1], max = [1, 1, 1] }\nemission = [0.5, 1.0, 2.0]",
    ));
    let exact = Vec3::new(0.5, 1.0, 2.0) * 2.0;
    let estimate = common::estimate_ray(
        &loaded,
        IntegratorKind::Volpath,
        0.0,
        ray_down_z(0.3, 0.3),
        20_000,
    );
    assert_within_noise("pure emitter", estimate, exact);
}

/// A graded procedural medium whose emission follows its density, RGB
/// extinction: the tracking estimate against a fine midpoint sum.
#[test]
fn graded_noise_medium_matches_quadrature() {
    let loaded = common::scene(&scene_text(
        "sigma_t = [2.0, 3.0, 1.5]\nalbedo = 0\nbox = { min = [-1, -1, -1], max = [1, 1, 1] }\ndensity = \"noise\"\nfrequency = 2\nbias = 0.2\nemission = [4.0, 2.0, 1.0]",
    ));
    let volume = &loaded.scene.volumes()[0];
    for (x, y) in [(0.0, 0.0), (0.3, -0.25)] {
        let ray = ray_down_z(x, y);
        let exact = emission_quadrature(volume, &ray, 4.0, 6.0, 20_000);
        assert!(
            exact.min_element() > 0.05,
            "the ray must cross emission: {exact}"
        );
        let estimate = common::estimate_ray(&loaded, IntegratorKind::Volpath, 0.0, ray, 20_000);
        assert_within_noise("noise medium", estimate, exact);
    }
}

const FIRE_MEDIUM: &str = "sigma_t = 6.0\nalbedo = 0\ndensity = \"vdb\"\ntemperature_grid = \"temperature\"\ntemperature_scale = 1000.0\nblackbody_intensity = 0.02\nemission = [60.0, 22.0, 5.0]\nemission_grid = \"flame\"";

fn fire_scene(extra: &str) -> String {
    scene_text(&format!(
        "{FIRE_MEDIUM}\nfile = \"{}\"\n{extra}",
        fire_vdb().display()
    ))
}

/// The fire's VDB medium (blackbody emission from a temperature grid
/// and a colour on a flame grid, each another grid of the file): the
/// emission coefficient at voxel centres against the grids' values
/// (read here with the VDB reader) combined by the documented formula
/// `j = emission·flame + intensity·σa·B(1000·temperature)`, and the
/// tracking estimate along rays through the flame against quadrature.
#[test]
fn fire_vdb_emission_matches_the_formula_and_quadrature() {
    let loaded = load("fire", &fire_scene("")).expect("fire scene");
    let volume = &loaded.scene.volumes()[0];
    let grid = |name: &str| tyndall_load::vdb::read_grid(&fire_vdb(), name).expect("grid");
    let (density, temperature, flame) = (grid("density"), grid("temperature"), grid("flame"));
    // scenes/fire/make_fire_vdb.py: voxel centres at (-0.6, 0, -0.6) +
    // (index + 0.5)·0.04.
    let mut checked = 0;
    for index in [
        IVec3::new(15, 8, 15),
        IVec3::new(14, 15, 16),
        IVec3::new(16, 4, 13),
        IVec3::new(15, 12, 15),
        IVec3::new(17, 9, 15),
        IVec3::new(10, 30, 12),
    ] {
        let x = Vec3::new(-0.6, 0.0, -0.6) + (index.as_vec3() + 0.5) * 0.04;
        let sigma_a = 6.0 * density.value(index);
        let expected = Vec3::new(60.0, 22.0, 5.0) * flame.value(index)
            + 0.02 * sigma_a * blackbody::rgb(1000.0 * temperature.value(index) as f64);
        let j = volume.emission_at(x);
        // The blackbody table's interpolation (its unit test: < 10⁻³
        // relative from 800 K up), and 10⁻⁴ absolute where the emission
        // is negligible (below 800 K linear interpolation of the steep
        // Planck curve overshoots; j there is 10⁻⁷ of the core's).
        let error = (j - expected).abs().max_element();
        assert!(
            error < 2e-3 * expected.max_element() + 1e-4,
            "voxel {index}: j = {j}, expected {expected}"
        );
        checked += usize::from(expected.max_element() > 1.0);
    }
    assert!(checked >= 3, "the voxels must emit");
    for (x, y) in [(0.0, 0.4), (-0.03, 0.3), (0.02, 0.55)] {
        let ray = ray_down_z(x, y);
        let exact = emission_quadrature(volume, &ray, 4.3, 5.7, 20_000);
        assert!(
            exact.max_element() > 0.5,
            "the ray must cross the flame: {exact}"
        );
        let estimate = common::estimate_ray(&loaded, IntegratorKind::Volpath, 0.0, ray, 20_000);
        assert_within_noise("fire", estimate, exact);
    }
}

/// Cycles' blackbody law (`blackbody_law = "cycles"`, docs/physics.md
/// §2.5): at voxel centres of the fire, `j = tint·(σ_SB·10⁻⁶/π)·T⁴·ĉ(T)`
/// with σ_SB = 5.670374419·10⁻⁸ W·m⁻²·K⁻⁴ (CODATA 2018, written here)
/// and ĉ the blackbody colour at luminance 1 — its Rec. 709 luminance,
/// weighed here with the matrix's Y row, is 1 (to the 10⁻⁴ the 4-digit
/// matrices are inverse to; no channel is clipped) — independent of
/// density; between voxels the law at the voxels interpolated, as
/// Cycles' stochastic lookups average it; and tracking finds it against
/// quadrature, with extinction and without (σt = 0: the majorant floor
/// where the temperature grid is positive is all that samples it).
#[test]
fn cycles_blackbody_law_matches_its_formula_and_quadrature() {
    const SIGMA: f64 = 5.670_374_419e-8;
    let tint = Vec3::new(1.0, 0.8, 0.6);
    let medium = |sigma_t: f32| {
        format!(
            "sigma_t = {sigma_t:?}\nalbedo = 0\ndensity = \"vdb\"\nfile = \"{}\"\ntemperature_grid = \"temperature\"\ntemperature_scale = 2000.0\nblackbody_law = \"cycles\"\nblackbody_tint = [1.0, 0.8, 0.6]",
            fire_vdb().display()
        )
    };
    let temperature = tyndall_load::vdb::read_grid(&fire_vdb(), "temperature").expect("grid");
    let loaded = load("cycles-law", &scene_text(&medium(6.0))).expect("scene");
    let volume = &loaded.scene.volumes()[0];
    let mut checked = 0;
    for index in [
        IVec3::new(15, 8, 15),
        IVec3::new(14, 15, 16),
        IVec3::new(16, 4, 13),
        IVec3::new(10, 30, 12),
    ] {
        let x = Vec3::new(-0.6, 0.0, -0.6) + (index.as_vec3() + 0.5) * 0.04;
        let kelvin = 2000.0 * temperature.value(index) as f64;
        let colour = blackbody::unit_luminance_rgb(kelvin);
        let y = 0.2126 * colour.x + 0.7152 * colour.y + 0.0722 * colour.z;
        assert!((y - 1.0).abs() < 1e-3, "{kelvin} K: luminance {y}");
        let power = SIGMA * 1e-6 / std::f64::consts::PI * kelvin.powi(4);
        let expected = tint * colour * power as f32;
        let j = volume.emission_at(x);
        // The table's interpolation, as for Kirchhoff's law above.
        let error = (j - expected).abs().max_element();
        assert!(
            error < 2e-3 * expected.max_element() + 1e-4,
            "voxel {index} at {kelvin} K: j = {j}, expected {expected}"
        );
        checked += usize::from(kelvin > 2000.0);
    }
    assert!(checked >= 2, "the voxels must be hot");
    // Halfway between two voxel centres along x, at 1286 K and 1938 K:
    // the mean of the law at the two, not the law at their mean
    // temperature (T⁴ is convex: they differ by a fifth here).
    let (a, b) = (IVec3::new(12, 5, 15), IVec3::new(13, 5, 15));
    let centre = |i: IVec3| Vec3::new(-0.6, 0.0, -0.6) + (i.as_vec3() + 0.5) * 0.04;
    let law = |i: IVec3| {
        let kelvin = 2000.0 * temperature.value(i) as f64;
        let power = SIGMA * 1e-6 / std::f64::consts::PI * kelvin.powi(4);
        tint * blackbody::unit_luminance_rgb(kelvin) * power as f32
    };
    let expected = (law(a) + law(b)) * 0.5;
    let mean_kelvin = 1000.0 * (temperature.value(a) + temperature.value(b)) as f64;
    let at_mean_kelvin = tint
        * blackbody::unit_luminance_rgb(mean_kelvin)
        * (SIGMA * 1e-6 / std::f64::consts::PI * mean_kelvin.powi(4)) as f32;
    let j = volume.emission_at((centre(a) + centre(b)) * 0.5);
    assert!(
        (j - expected).abs().max_element() < 2e-3 * expected.max_element(),
        "between voxels {a} and {b}: j = {j}, expected {expected}"
    );
    assert!(
        (at_mean_kelvin - expected).abs().max_element() > 0.1 * expected.max_element(),
        "the two readings must differ here: {at_mean_kelvin} vs {expected}"
    );
    for sigma_t in [6.0, 0.0] {
        let loaded = load("cycles-law", &scene_text(&medium(sigma_t))).expect("scene");
        let volume = &loaded.scene.volumes()[0];
        for (x, y) in [(0.0, 0.2), (0.03, 0.4)] {
            let ray = ray_down_z(x, y);
            let exact = emission_quadrature(volume, &ray, 4.3, 5.7, 20_000);
            assert!(
                exact.max_element() > 0.1,
                "the ray must cross the flame: {exact}"
            );
            let estimate = common::estimate_ray(&loaded, IntegratorKind::Volpath, 0.0, ray, 20_000);
            assert_within_noise(&format!("Cycles' law, σt {sigma_t}"), estimate, exact);
        }
    }
}

/// Planck's law integrated over all wavelengths is the Stefan–Boltzmann
/// radiance σT⁴/π (σ = 5.670374419·10⁻⁸ W·m⁻²·K⁻⁴, CODATA 2018), by a
/// midpoint sum in ln λ from 10 nm to 1 mm (the tails beyond hold less
/// than 10⁻⁶ of it from 300 K to 30000 K).
#[test]
fn planck_integrates_to_stefan_boltzmann() {
    const SIGMA: f64 = 5.670_374_419e-8;
    for kelvin in [300.0, 1500.0, 5772.0, 30_000.0] {
        let (a, b) = (1e-8f64.ln(), 1e-3f64.ln());
        let n = 200_000;
        let h = (b - a) / n as f64;
        let integral: f64 = (0..n)
            .map(|i| {
                let lambda = (a + (i as f64 + 0.5) * h).exp();
                blackbody::spectral_radiance(lambda, kelvin) * lambda * h
            })
            .sum();
        let exact = SIGMA * kelvin.powi(4) / std::f64::consts::PI;
        assert!(
            (integral / exact - 1.0).abs() < 1e-5,
            "{kelvin} K: {integral} vs σT⁴/π = {exact}"
        );
    }
}

/// The chromaticity of the blackbody's colour (its XYZ, and the Rec. 709
/// RGB converted back with the inverse matrix written here) against the
/// CIE 1931 Planckian locus as published (CIE 015:2018 illuminant A at
/// 2856 K: (0.44757, 0.40745); the others from tables of the locus, e.g.
/// Wyszecki & Stiles), given to 4 decimals. Tolerance 3·10⁻⁴ in x and y:
/// the tables' rounding (5·10⁻⁵), the locus tables' older second
/// radiation constant, and for RGB the round trip through two 4-digit
/// matrices that are inverse only to about 10⁻⁴ (measured, XYZ: at most
/// 1.3·10⁻⁴, at 6504 K; the analytic fit of Wyman et al. 2013 that the
/// core integrated before the CIE's table was off by 0.0044 at 1500 K).
/// A visible shift along the locus is 100 times that (1500 K to 2000 K
/// moves x by 0.06). RGB is checked where the colour is inside the Rec.
/// 709 gamut (from 2000 K): below, its negative blue is clipped to 0.
#[test]
fn blackbody_colours_lie_on_the_planckian_locus() {
    let locus = [
        (1500.0, 0.5857, 0.3931),
        (2000.0, 0.5267, 0.4133),
        (2856.0, 0.44757, 0.40745),
        (4000.0, 0.3805, 0.3768),
        (6504.0, 0.3135, 0.3237),
        (10_000.0, 0.2807, 0.2884),
    ];
    // linear sRGB → XYZ (IEC 61966-2-1), the inverse of the core's matrix.
    let to_xyz = |c: Vec3| {
        let (r, g, b) = (c.x as f64, c.y as f64, c.z as f64);
        [
            0.4124 * r + 0.3576 * g + 0.1805 * b,
            0.2126 * r + 0.7152 * g + 0.0722 * b,
            0.0193 * r + 0.1192 * g + 0.9505 * b,
        ]
    };
    for (kelvin, x, y) in locus {
        let mut forms = vec![("XYZ", blackbody::xyz(kelvin))];
        if kelvin >= 2000.0 {
            forms.push(("RGB", to_xyz(blackbody::rgb(kelvin))));
        }
        for (what, xyz) in forms {
            let s = xyz[0] + xyz[1] + xyz[2];
            let (cx, cy) = (xyz[0] / s, xyz[1] / s);
            assert!(
                (cx - x).abs() < 3e-4 && (cy - y).abs() < 3e-4,
                "{kelvin} K ({what}): ({cx:.4}, {cy:.4}) vs locus ({x}, {y})"
            );
        }
    }
    // 6504 K is near D65, the white of Rec. 709: channels within 10 % of
    // each other; 1500 K is red-orange.
    let white = blackbody::rgb(6504.0);
    assert!(white.max_element() / white.min_element() < 1.1, "{white}");
    let red = blackbody::rgb(1500.0);
    assert!(red.x > 2.0 * red.y && red.y > red.z, "{red}");
}

/// An emitting medium rendered by `march` or `single` is refused, the
/// error naming the medium and the integrator.
#[test]
fn march_and_single_refuse_emitting_media() {
    let loaded = common::scene(&scene_text(
        "sigma_t = 1\nalbedo = 0\nbox = { min = [-1, -1, -1], max = [1, 1, 1] }\nemission = 1",
    ));
    for kind in [IntegratorKind::March, IntegratorKind::Single] {
        let mut settings = loaded.settings;
        settings.integrator = kind;
        let Err(e) = tyndall::render(&loaded.scene, &settings, &|_| {}) else {
            panic!("{kind:?} rendered an emitting medium");
        };
        let text = e.to_string();
        assert!(
            text.contains("medium #0") && text.contains("emits") && text.contains(kind.name()),
            "{text}"
        );
    }
}

/// Bad emission input: an error naming the file and key, never a panic.
#[test]
fn bad_emission_input_names_file_and_key() {
    let boxed = "sigma_t = 1\nalbedo = 0\nbox = { min = [-1, -1, -1], max = [1, 1, 1] }";
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "nan",
            format!("{boxed}\nemission = [nan, 1, 1]"),
            "emission",
        ),
        (
            "negative",
            format!("{boxed}\nemission = [1, -1, 1]"),
            "emission",
        ),
        (
            "infinite",
            format!("{boxed}\nemission = [1, inf, 1]"),
            "emission",
        ),
        (
            "everywhere",
            "sigma_t = 1\nalbedo = 0\nemission = 1".into(),
            "`box` or a `mesh`",
        ),
        (
            "grid_on_noise",
            format!("{boxed}\ndensity = \"noise\"\nemission = 1\nemission_grid = \"flame\""),
            "emission_grid",
        ),
        (
            "temperature_on_uniform",
            format!("{boxed}\ntemperature_grid = \"temperature\""),
            "temperature_grid",
        ),
        (
            "scale_alone",
            format!("{boxed}\ntemperature_scale = 1000"),
            "temperature_scale",
        ),
        (
            "grid_without_colour",
            fire_scene("").replace("emission = [60.0, 22.0, 5.0]\n", ""),
            "emission_grid",
        ),
        (
            "missing_temperature",
            fire_scene("").replace(
                "temperature_grid = \"temperature\"",
                "temperature_grid = \"heat\"",
            ),
            "\"heat\"",
        ),
        (
            "missing_flame",
            fire_scene("").replace("emission_grid = \"flame\"", "emission_grid = \"fuel\""),
            "\"density\", \"temperature\", \"flame\"",
        ),
        (
            "zero_scale",
            fire_scene("").replace("temperature_scale = 1000.0", "temperature_scale = 0"),
            "temperature_scale",
        ),
        (
            "nan_scale",
            fire_scene("").replace("temperature_scale = 1000.0", "temperature_scale = nan"),
            "temperature_scale",
        ),
        (
            "negative_offset",
            fire_scene("temperature_offset = -300"),
            "temperature_offset",
        ),
        (
            "negative_intensity",
            fire_scene("").replace("blackbody_intensity = 0.02", "blackbody_intensity = -1"),
            "blackbody_intensity",
        ),
        (
            "too_hot",
            fire_scene("").replace("temperature_scale = 1000.0", "temperature_scale = 1e9"),
            "K limit",
        ),
        (
            "unknown_law",
            fire_scene("blackbody_law = \"planck\""),
            "unknown blackbody law \"planck\"",
        ),
        (
            "tint_under_kirchhoff",
            fire_scene("blackbody_tint = [1, 0.5, 0.5]"),
            "blackbody_tint",
        ),
        (
            "law_without_temperature",
            format!("{boxed}\nemission = 1\nblackbody_law = \"cycles\""),
            "blackbody_law",
        ),
        (
            "cycles_intensity_above_1",
            fire_scene("blackbody_law = \"cycles\"")
                .replace("blackbody_intensity = 0.02", "blackbody_intensity = 2"),
            "[0, 1]",
        ),
        (
            "negative_tint",
            fire_scene("blackbody_law = \"cycles\"\nblackbody_tint = [1, -1, 1]"),
            "blackbody_tint",
        ),
    ];
    for (name, medium, words) in cases {
        let text = if medium.starts_with("[camera]") {
            medium
        } else {
            scene_text(&medium)
        };
        let e = match load(name, &text) {
            Ok(_) => panic!("{name}: expected an error"),
            Err(e) => e,
        };
        assert!(
            e.contains(&format!("{name}.toml:")),
            "{name}: no file and line in: {e}"
        );
        assert!(e.contains(words), "{name}: `{words}` not in: {e}");
    }
}

/// Negative and NaN values in an emission or temperature grid are
/// refused by the reader, naming the file and grid (grids.vdb holds a
/// voxel of −1 and one of NaN).
#[test]
fn negative_and_nan_grid_values_are_refused() {
    let grids = common::repo().join("crates/tyndall-tests/tests/data/grids.vdb");
    for (key, grid, words) in [
        ("temperature_grid", "negative", "found -1"),
        ("emission_grid", "nan", "found NaN"),
    ] {
        let extra = if key == "emission_grid" {
            "emission = 1\n"
        } else {
            ""
        };
        let text = scene_text(&format!(
            "sigma_t = 1\nalbedo = 0\ndensity = \"vdb\"\nfile = \"{}\"\ngrid = \"density\"\n{extra}{key} = \"{grid}\"",
            grids.display()
        ));
        let e = match load(&format!("bad_{grid}"), &text) {
            Ok(_) => panic!("{grid}: expected an error"),
            Err(e) => e,
        };
        // The place is the key's line: the media table's seventh key.
        let line = if key == "emission_grid" { 16 } else { 15 };
        assert!(
            e.contains(&format!("bad_{grid}.toml:{line}:"))
                && e.contains("grids.vdb")
                && e.contains(words),
            "{key}: {e}"
        );
    }
}
