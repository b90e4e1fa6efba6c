//! Lights as fixture makers measure them (issue 23): IES LM-63 profiles on
//! point and spot lights (native and glTF) and colour temperature on every
//! light; gobos are in gobos.rs.
//!
//! The files are four real luminaires' (scenes/luminaires/README.md), one
//! of each horizontal symmetry. Each is checked against what is
//! independent of Tyndall: its total flux against the figure Photometric
//! Toolbox computes from it, and the light arriving at points on rays
//! through its tabulated angles against its candela numbers, read here by
//! a parser of the test's own.

mod common;

use glam::{DVec3, Vec3};
use std::f64::consts::PI;
use tyndall::color::blackbody;
use tyndall::lights::Light;

const EPS: f64 = f32::EPSILON as f64;

fn luminaire_file(name: &str) -> std::path::PathBuf {
    common::repo().join("scenes/luminaires").join(name)
}

/// An LM-63 file's table as this test reads it: the numbers after `TILT=`
/// in the order LM-63 gives them.
struct Table {
    vertical: Vec<f64>,
    horizontal: Vec<f64>,
    /// `candela[h][v]`
    candela: Vec<Vec<f64>>,
    /// The candela multiplier times the two ballast factors.
    scale: f64,
}

fn read_table(name: &str) -> Table {
    let text = std::fs::read_to_string(luminaire_file(name)).expect("luminaire file");
    let after_tilt = text
        .lines()
        .skip_while(|l| !l.starts_with("TILT=NONE"))
        .skip(1);
    let n: Vec<f64> = after_tilt
        .flat_map(|l| {
            l.split([' ', ',', '\t'])
                .map(str::to_owned)
                .collect::<Vec<_>>()
        })
        .filter(|t| !t.trim().is_empty())
        .map(|t| t.trim().parse().expect("a number"))
        .collect();
    let (nv, nh) = (n[3] as usize, n[4] as usize);
    let scale = n[2] * n[10] * n[11];
    let rest = &n[13..];
    let vertical = rest[..nv].to_vec();
    let horizontal = rest[nv..nv + nh].to_vec();
    let candela = (0..nh)
        .map(|h| rest[nv + nh + h * nv..nv + nh + (h + 1) * nv].to_vec())
        .collect();
    Table {
        vertical,
        horizontal,
        candela,
        scale,
    }
}

/// The four files with the total flux Photometric Toolbox computes from
/// each (lm, as echowuzangye/CU-calculations-based-on-IES-file's
/// ies/ies_summary.md lists them for its files 2, 3, 5 and 7).
const FILES: [(&str, f64); 4] = [
    ("rab-cled52.ies", 5834.2),
    ("deliver-dlf1906103.ies", 13359.57),
    ("rab-boa2.ies", 753.8),
    ("rab-dled6r8y.ies", 531.98),
];

/// The files' total flux, `peak·∫P dω` of Tyndall's interpolant (exact
/// for it), matches Photometric Toolbox's. The two interpolate the same
/// samples differently; both lie within linear interpolation's error of
/// any smooth intensity through them, `h²/8·|I''|` per interval, which
/// the test bounds by the table's second differences in θ and in φ
/// (|Δ²I|/8 at the interval's ends), integrated over each zone's solid
/// angle, plus the toolbox's rounding to 0.01 lm.
#[test]
fn total_flux_matches_photometric_toolbox() {
    for (name, toolbox) in FILES {
        let file = tyndall_load::ies::load(&luminaire_file(name)).expect("the file parses");
        let flux = f64::from(file.peak_candela) * 4.0 * PI * f64::from(file.profile.mean());
        let t = read_table(name);
        let nv = t.vertical.len();
        let second = |row: &[f64], i: usize| -> f64 {
            if i == 0 || i + 1 >= row.len() {
                0.0
            } else {
                (row[i - 1] - 2.0 * row[i] + row[i + 1]).abs()
            }
        };
        // Per horizontal angle, ∫ (|Δ²_θ I| + |Δ²_φ I|)/8 sin θ dθ.
        let row_bound = |h: usize| -> f64 {
            let column: Vec<f64> = (0..nv).map(|v| t.candela[h][v]).collect();
            (0..nv - 1)
                .map(|v| {
                    let across = |v: usize| {
                        let ring: Vec<f64> = t.candela.iter().map(|r| r[v]).collect();
                        second(&ring, h)
                    };
                    let d2 = second(&column, v)
                        .max(second(&column, v + 1))
                        .max(across(v))
                        .max(across(v + 1));
                    let (a, b) = (t.vertical[v].to_radians(), t.vertical[v + 1].to_radians());
                    d2 / 8.0 * (a.cos() - b.cos())
                })
                .sum()
        };
        let nh = t.horizontal.len();
        let bound = if nh == 1 {
            2.0 * PI * row_bound(0)
        } else {
            let listed: f64 = (0..nh - 1)
                .map(|h| {
                    0.5 * (row_bound(h) + row_bound(h + 1))
                        * (t.horizontal[h + 1] - t.horizontal[h]).to_radians()
                })
                .sum();
            listed * 360.0 / (t.horizontal[nh - 1] - t.horizontal[0])
        } * t.scale;
        let tolerance = bound + 0.005 + 1e-5 * toolbox;
        assert!(
            (flux - toolbox).abs() <= tolerance,
            "{name}: {flux:.2} lm, Photometric Toolbox {toolbox} lm (tolerance {tolerance:.2})"
        );
        // The bound is not vacuous: under 1 % of the flux.
        assert!(bound < 1e-2 * toolbox, "{name}: bound {bound:.2} lm");
    }
}

/// The unit frame the scene format documents for a profile with nadir
/// `nadir` turned `rotate_deg`: 0° along world +X (or +Z near ±X)
/// perpendicular to the nadir, 90° along zero × nadir.
fn frame(nadir: DVec3, rotate_deg: f64) -> (DVec3, DVec3) {
    let reference = if nadir.x.abs() > 0.9 {
        DVec3::Z
    } else {
        DVec3::X
    };
    let zero = (reference - reference.dot(nadir) * nadir).normalize();
    let ninety = zero.cross(nadir);
    let (s, c) = rotate_deg.to_radians().sin_cos();
    let zero = zero * c + ninety * s;
    (zero, zero.cross(nadir))
}

/// At points 3 units from the light along the directions of the table's
/// own angles (and their mirror images under the file's symmetry), the
/// light arriving is the file's candela there over 683 lm/W and d²: the
/// orientation (θ from the nadir, φ counter-clockwise from the turned 0°
/// plane), the symmetry folds and the units. Tolerance: the direction's
/// angles are within 8ε/sin θ rad of the table's after f32 rounding (acos
/// and atan2 lose precision towards the poles), which moves the value by
/// its slope to the neighbouring entries; products and the square add
/// 16ε.
fn check_tabulated_angles(
    light: &Light,
    position: Vec3,
    nadir: DVec3,
    rotate_deg: f64,
    t: &Table,
    cutoff_deg: f64,
) {
    let (zero, ninety) = frame(nadir.normalize(), rotate_deg);
    let nv = t.vertical.len();
    let nh = t.horizontal.len();
    let mut checked = 0;
    for h in 0..nh {
        let phi = t.horizontal[h];
        // The mirror images each symmetry implies.
        let span = t.horizontal[nh - 1] - t.horizontal[0];
        let images: Vec<f64> = match (nh, span as i64) {
            (1, _) => vec![0.0, 77.0, 200.0],
            (_, 90) => vec![phi, 180.0 - phi, 180.0 + phi, 360.0 - phi],
            (_, 180) if t.horizontal[0] == 0.0 => vec![phi, 360.0 - phi],
            (_, 180) => vec![phi, 180.0 - phi],
            _ => vec![phi],
        };
        for v in 0..nv {
            let theta = t.vertical[v];
            // At the poles every φ is one direction (row 0's); a full
            // table's 360° row is its 0° row's direction.
            let pole = (theta == 0.0 || theta == 180.0) && h > 0;
            if theta >= cutoff_deg - 1e-9 || pole || phi == 360.0 {
                continue;
            }
            let candela = t.candela[h][v] * t.scale;
            let slope = |row: &[f64], i: usize, angles: &[f64]| -> f64 {
                let mut s: f64 = 0.0;
                if i > 0 {
                    s = s.max((row[i] - row[i - 1]).abs() / (angles[i] - angles[i - 1]));
                }
                if i + 1 < row.len() {
                    s = s.max((row[i + 1] - row[i]).abs() / (angles[i + 1] - angles[i]));
                }
                s
            };
            let ring: Vec<f64> = t.candela.iter().map(|r| r[v]).collect();
            // Near the poles acos and atan2 lose precision as 1/sin θ.
            let delta_deg = 8.0 * EPS * 180.0 / PI / theta.to_radians().sin().max(1e-3);
            let wobble = (slope(&t.candela[h], v, &t.vertical)
                + if nh > 1 {
                    slope(&ring, h, &t.horizontal)
                } else {
                    0.0
                })
                * delta_deg
                * t.scale;
            for &image in &images {
                let (st, ct) = theta.to_radians().sin_cos();
                let (sp, cp) = image.to_radians().sin_cos();
                let omega = nadir.normalize() * ct + (zero * cp + ninety * sp) * st;
                let x = position + (omega * 3.0).as_vec3();
                let expected = candela / 683.0 / 9.0;
                let got = light
                    .incident(x, None)
                    .map_or(0.0, |inc| f64::from(inc.irradiance.x));
                let tolerance = wobble / 683.0 / 9.0 + 16.0 * EPS * expected + 1e-12;
                assert!(
                    (got - expected).abs() <= tolerance,
                    "θ {theta}°, φ {phi}° (as {image}°): {got} vs the file's {candela} cd → {expected}"
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 30, "{checked} directions checked");
}

/// A scene holding one light table `light`, beside the luminaire files.
fn scene_with(light: &str) -> common::Loaded {
    let dir = std::env::temp_dir().join(format!("tyndall-photometry-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let name = format!(
        "{:x}.toml",
        light.len() * 7919 + light.bytes().map(usize::from).sum::<usize>()
    );
    let path = dir.join(name);
    let text = format!(
        "[camera]\nposition = [0, 1, 6]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\n\n\
         [render]\nwidth = 4\nheight = 4\n\n[[lights]]\n{light}\n"
    );
    std::fs::write(&path, text).expect("write scene");
    common::load_native(&path).expect("scene loads")
}

fn ies_path(name: &str) -> String {
    luminaire_file(name)
        .display()
        .to_string()
        .replace('\\', "/")
}

#[test]
fn point_light_gives_each_files_candela_at_its_angles() {
    for (name, _) in FILES {
        let nadir = DVec3::new(0.2, -1.0, 0.3);
        let loaded = scene_with(&format!(
            "type = \"point\"\nposition = [0.5, 3, -1]\ndirection = [0.2, -1.0, 0.3]\n\
             ies = \"{}\"\nies_rotate_deg = 30",
            ies_path(name)
        ));
        let light = &loaded.scene.lights()[0];
        check_tabulated_angles(
            light,
            Vec3::new(0.5, 3.0, -1.0),
            nadir,
            30.0,
            &read_table(name),
            181.0,
        );
    }
}

/// Lights naming one IES file share one parsed profile: a rig of 1024
/// heads reads it once, and each head still turns it its own way.
#[test]
fn lights_naming_one_file_share_its_profile() {
    let name = FILES[0].0;
    let head = |x: f32, turn: f32| {
        format!(
            "type = \"spot\"\nposition = [{x}, 3, 0]\ndirection = [0, -1, 0]\ncutoff_deg = 60\n\
             ies = \"{}\"\nies_rotate_deg = {turn}",
            ies_path(name)
        )
    };
    let loaded = scene_with(&format!(
        "{}\n\n[[lights]]\n{}",
        head(-1.0, 0.0),
        head(1.0, 90.0)
    ));
    let luminaires: Vec<_> = loaded
        .scene
        .lights()
        .iter()
        .filter_map(|l| match l {
            tyndall::lights::Light::Spot(s) => s.luminaire.as_ref(),
            _ => None,
        })
        .collect();
    assert_eq!(luminaires.len(), 2);
    assert!(std::sync::Arc::ptr_eq(
        &luminaires[0].profile,
        &luminaires[1].profile
    ));
    assert_ne!(luminaires[0], luminaires[1], "each head keeps its own turn");
}

/// A glTF file in `dir` holding a camera and one light of `kind` (with
/// `fields`, JSON members after its type) at a node turned −90° about x,
/// so that its −z is −y.
fn gltf_with_light(
    dir: &std::path::Path,
    file: &str,
    kind: &str,
    fields: &str,
) -> std::path::PathBuf {
    let half = std::f64::consts::FRAC_1_SQRT_2;
    let gltf = format!(
        r#"{{"asset": {{"version": "2.0"}},
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {{"KHR_lights_punctual": {{"lights": [{{"type": "{kind}", {fields}}}]}}}},
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.7, "znear": 0.01}}}}],
  "scene": 0, "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [{{"translation": [0.5, 3, -1], "rotation": [{r}, 0, 0, {half}],
    "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}},
    {{"translation": [0, 1, 6], "camera": 0}}]}}"#,
        r = -half,
    );
    let path = dir.join(file);
    std::fs::write(&path, gltf).expect("write the glTF");
    path
}

/// A glTF point light whose `extras` name a file (beside the glTF, turned
/// 30°) is the file's luminaire with its nadir along the light's −z (here
/// −y). Its `intensity` in candela is the profile's peak: set to the
/// file's largest candela, every tabulated direction must give the file's
/// own number.
#[test]
fn gltf_point_light_takes_the_profile_its_extras_name() {
    let dir = std::env::temp_dir().join(format!("tyndall-gltf-ies-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for (name, _) in FILES {
        let table = read_table(name);
        let peak = table
            .candela
            .iter()
            .flatten()
            .fold(0.0f64, |m, &c| m.max(c))
            * table.scale;
        std::fs::copy(luminaire_file(name), dir.join("profile.ies")).expect("copy the file");
        let fields = format!(
            r#""intensity": {peak}, "extras": {{"ies": "profile.ies", "ies_rotate_deg": 30}}"#
        );
        let path = gltf_with_light(&dir, &format!("{name}.gltf"), "point", &fields);
        let loaded = common::load_gltf(&path).expect("the glTF loads");
        let light = &loaded.scene.lights()[0];
        check_tabulated_angles(
            light,
            Vec3::new(0.5, 3.0, -1.0),
            DVec3::NEG_Y,
            30.0,
            &table,
            181.0,
        );
    }
}

/// Bad profile extras on a glTF light: an error naming the file and the
/// element (and the IES file's own place), never a panic.
#[test]
fn gltf_profile_extras_are_checked() {
    let dir = std::env::temp_dir().join(format!("tyndall-gltf-bad-ies-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(
        dir.join("short.ies"),
        "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3\n",
    )
    .expect("write a bad file");
    let cases = [
        (
            "point",
            r#""extras": {"ies": 5}"#,
            "lights[0].extras.ies: must be a string",
        ),
        (
            "point",
            r#""extras": {"ies": "a.ies", "ies_rotate_deg": 400}"#,
            "lights[0].extras.ies_rotate_deg: must be an angle",
        ),
        (
            "point",
            r#""extras": {"ies_rotate_deg": 10}"#,
            "there is no `ies`",
        ),
        (
            "point",
            r#""extras": {"ies": "missing.ies"}"#,
            "missing.ies",
        ),
        ("point", r#""extras": {"ies": "short.ies"}"#, "short.ies:"),
        (
            "directional",
            r#""extras": {"ies": "short.ies"}"#,
            "a measured profile needs a point or spot light",
        ),
    ];
    for (i, (kind, fields, expected)) in cases.iter().enumerate() {
        let path = gltf_with_light(&dir, &format!("bad{i}.gltf"), kind, fields);
        match common::load_gltf(&path) {
            Ok(_) => panic!("case {i} ({fields}) loaded"),
            Err(e) => {
                let message = e.to_string();
                assert!(
                    message.contains(expected) && message.contains(&format!("bad{i}.gltf")),
                    "case {i}: {message}"
                );
            }
        }
    }
}

/// A spot's cone bounds the profile: inside a hard cone the light is the
/// file's, outside nothing.
#[test]
fn spot_light_is_its_cone_times_the_profile() {
    let name = "rab-cled52.ies";
    let loaded = scene_with(&format!(
        "type = \"spot\"\nposition = [0, 3, 0]\ndirection = [0, -1, 0]\ncutoff_deg = 50\n\
         profile = \"hard\"\nies = \"{}\"\nies_rotate_deg = -45",
        ies_path(name)
    ));
    let light = &loaded.scene.lights()[0];
    let t = read_table(name);
    check_tabulated_angles(light, Vec3::new(0.0, 3.0, 0.0), -DVec3::Y, -45.0, &t, 50.0);
    // Beyond the cutoff, nothing, though the file has light there.
    let outside = Vec3::new(0.0, 3.0, 0.0)
        + Vec3::new(60f32.to_radians().sin(), -60f32.to_radians().cos(), 0.0) * 3.0;
    assert!(light.incident(outside, None).is_none());
}

/// `power` sets the total flux the profile spreads: the light tracer's
/// emission averages to it (tyndall's own test checks that for a
/// synthetic table), and the peak is power/(4π·mean).
#[test]
fn power_spreads_over_the_profile() {
    let name = "rab-boa2.ies";
    let loaded = scene_with(&format!(
        "type = \"point\"\nposition = [0, 3, 0]\npower = 10.0\nies = \"{}\"",
        ies_path(name)
    ));
    let light = &loaded.scene.lights()[0];
    let power = f64::from(light.power(1.0).x);
    assert!((power - 10.0).abs() < 1e-5 * 10.0, "power {power}");
    // The same flux by this test's trapezoid quadrature of the table (a
    // downlight: nothing above 90°), scaled to the peak of 1 the profile
    // is normalised to. Tyndall integrates its interpolant, linear in θ,
    // times sin θ exactly; the trapezoid rule on I·sin θ errs from that by
    // h³/12·|f''| an interval, f'' = 2I'cos θ − I sin θ (I'' = 0 there),
    // so by h³/12·(2|ΔI|/h + max I). Both use the trapezoid rule in φ.
    let t = read_table(name);
    let peak = t.candela.iter().flatten().fold(0.0f64, |a, &b| a.max(b));
    // (∫ over θ by the trapezoid rule, its error bound) for row h.
    let row = |h: usize| -> (f64, f64) {
        (0..t.vertical.len() - 1)
            .map(|v| {
                let (a, b) = (t.vertical[v].to_radians(), t.vertical[v + 1].to_radians());
                let (ia, ib) = (t.candela[h][v], t.candela[h][v + 1]);
                let step = b - a;
                let sum = 0.5 * (ia * a.sin() + ib * b.sin()) * step;
                let error = step.powi(3) / 12.0 * (2.0 * (ib - ia).abs() / step + ia.max(ib));
                (sum, error)
            })
            .fold((0.0, 0.0), |(s, e), (ds, de)| (s + ds, e + de))
    };
    let (quarter, quarter_error) = (0..t.horizontal.len() - 1)
        .map(|h| {
            let (r0, r1) = (row(h), row(h + 1));
            let dphi = (t.horizontal[h + 1] - t.horizontal[h]).to_radians();
            (0.5 * (r0.0 + r1.0) * dphi, 0.5 * (r0.1 + r1.1) * dphi)
        })
        .fold((0.0, 0.0), |(s, e), (ds, de)| (s + ds, e + de));
    let integral = 4.0 * quarter / peak;
    let relative_error = quarter_error / quarter;
    let Light::Point(p) = light else {
        panic!("a point light")
    };
    let expected_peak = 10.0 / integral;
    let got_peak = f64::from(p.intensity.x);
    // f32 rounding of the profile's mean and the division add 16ε.
    let tolerance = (relative_error + 16.0 * EPS) * expected_peak;
    assert!(
        (got_peak - expected_peak).abs() <= tolerance,
        "peak {got_peak} W/sr vs {expected_peak} from the test's quadrature (tolerance {tolerance:.2e})"
    );
    // The bound is informative: under 0.5 % (it is 0.11 % for this file).
    assert!(
        relative_error < 5e-3,
        "trapezoid error bound {relative_error:.2e}"
    );
}

/// `temperature_k` colours a light as blackbody media are coloured: the
/// blackbody's chromaticity at luminance 1 (Rec. 709's Y weights), so
/// `intensity` stays the luminance; on every kind of light.
#[test]
fn colour_temperature_keeps_luminance_and_takes_the_blackbodys_chromaticity() {
    let luminance =
        |c: Vec3| 0.2126 * f64::from(c.x) + 0.7152 * f64::from(c.y) + 0.0722 * f64::from(c.z);
    let chromaticity = |c: Vec3| {
        // Rec. 709 (D65) to XYZ.
        let (r, g, b) = (f64::from(c.x), f64::from(c.y), f64::from(c.z));
        let x = 0.4124 * r + 0.3576 * g + 0.1805 * b;
        let y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
        let z = 0.0193 * r + 0.1192 * g + 0.9505 * b;
        (x / (x + y + z), y / (x + y + z))
    };
    for kelvin in [2000.0f64, 3200.0, 5600.0, 10_000.0] {
        let tables = [
            format!(
                "type = \"point\"\nposition = [0, 3, 0]\nintensity = 4.0\ntemperature_k = {kelvin}"
            ),
            format!(
                "type = \"spot\"\nposition = [0, 3, 0]\ndirection = [0, -1, 0]\ncutoff_deg = 30\nintensity = 4.0\ntemperature_k = {kelvin}"
            ),
            format!(
                "type = \"directional\"\ndirection = [0, -1, 0]\nirradiance = 4.0\ntemperature_k = {kelvin}"
            ),
        ];
        let [bx, by, bz] = blackbody::xyz(kelvin);
        let (ex, ey) = (bx / (bx + by + bz), by / (bx + by + bz));
        for table in &tables {
            let loaded = scene_with(table);
            let light = &loaded.scene.lights()[0];
            let colour = light.incident(Vec3::ZERO, None).expect("lit").irradiance
                * match light {
                    Light::Directional(_) => 1.0,
                    _ => 9.0,
                };
            let y = luminance(colour);
            assert!(
                (y - 4.0).abs() < 1e-3 * 4.0,
                "{kelvin} K, {table}: luminance {y}"
            );
            let (x, yy) = chromaticity(colour);
            // The Rec. 709 matrices' four decimals: 1e-4 in xy.
            assert!(
                (x - ex).abs() < 3e-4 && (yy - ey).abs() < 3e-4,
                "{kelvin} K: xy ({x:.4}, {yy:.4}) vs the blackbody's ({ex:.4}, {ey:.4})"
            );
        }
    }
}

/// Malformed files and keys: a clear error naming the scene, the key and
/// the IES file's line and column; never a panic.
#[test]
fn bad_photometry_is_refused_clearly() {
    let good = std::fs::read_to_string(luminaire_file("rab-boa2.ies")).expect("file");
    let dir = std::env::temp_dir().join(format!("tyndall-bad-ies-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let cut = good.rfind("278").expect("a value");
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "ends early",
            good[..cut].to_string(),
            "the file ends before",
        ),
        (
            "negative candela",
            good.replacen("278 278 277", "278 -278 277", 1),
            "must be ≥ 0",
        ),
        (
            "angles out of order",
            good.replacen("0 2.5 5 7.5", "0 5 2.5 7.5", 1),
            "vertical angles must increase",
        ),
        (
            "a word for a number",
            good.replacen("278 278 277", "278 abc 277", 1),
            "found `abc`",
        ),
        (
            "Type B",
            good.replacen("120 -1 1 37 5 1 1", "120 -1 1 37 5 2 1", 1),
            "Type B photometry is not supported",
        ),
        (
            "tilt in a file",
            good.replacen("TILT=NONE", "TILT=lamp.tlt", 1),
            "`TILT=lamp.tlt`",
        ),
        (
            "no tilt line",
            good.replacen("TILT=NONE", "", 1),
            "no `TILT=` line",
        ),
        (
            "one vertical angle",
            good.replacen("120 -1 1 37 5 1 1", "120 -1 1 1 5 1 1", 1),
            "at least two vertical angles",
        ),
        (
            "too many angles",
            good.replacen("120 -1 1 37 5 1 1", "120 -1 1 1000000 5 1 1", 1),
            "from 1 to 1024",
        ),
        (
            "odd horizontal set",
            good.replacen("0 22.5 45 67.5 90", "0 22.5 45 67.5 100", 1),
            "none of LM-63's sets",
        ),
    ];
    for (what, text, expected) in cases {
        let ies = dir.join(format!("{}.ies", what.replace(' ', "-")));
        std::fs::write(&ies, &text).expect("write");
        let scene = dir.join(format!("{}.toml", what.replace(' ', "-")));
        std::fs::write(
            &scene,
            format!(
                "[camera]\nposition = [0, 1, 6]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\n\n\
                 [[lights]]\ntype = \"point\"\nposition = [0, 3, 0]\nies = \"{}\"\n",
                ies.file_name().unwrap().to_string_lossy()
            ),
        )
        .expect("write scene");
        let err = common::load_native(&scene)
            .err()
            .unwrap_or_else(|| panic!("{what}: accepted"))
            .to_string();
        assert!(err.contains(expected), "{what}: {err}");
        assert!(
            err.contains(".toml") && err.contains(".ies:"),
            "{what}: names both files: {err}"
        );
        // The `ies` key is on line 9 of the scene.
        assert!(err.contains(".toml:9:"), "{what}: points at the key: {err}");
    }
    // A gobo that does not decode, and one in too wide a cone.
    std::fs::write(dir.join("broken.png"), b"\x89PNG\r\n\x1a\n not really").expect("write");
    std::fs::write(dir.join("text.png"), b"hello").expect("write");
    image::RgbImage::from_pixel(2, 2, image::Rgb([200, 100, 50]))
        .save(dir.join("fine.png"))
        .expect("write");
    // Keys without their profile, and a temperature out of range.
    for (table, expected) in [
        (
            "type = \"spot\"\nposition = [0, 3, 0]\ndirection = [0, -1, 0]\ncutoff_deg = 30\nintensity = 1.0\ngobo = \"broken.png\"",
            "cannot read the image",
        ),
        (
            "type = \"spot\"\nposition = [0, 3, 0]\ndirection = [0, -1, 0]\ncutoff_deg = 30\nintensity = 1.0\ngobo = \"text.png\"",
            "not a PNG or JPEG",
        ),
        (
            "type = \"spot\"\nposition = [0, 3, 0]\ndirection = [0, -1, 0]\ncutoff_deg = 30\nintensity = 1.0\ngobo = \"missing.png\"",
            "missing.png: ",
        ),
        (
            "type = \"spot\"\nposition = [0, 3, 0]\ndirection = [0, -1, 0]\ncutoff_deg = 85\nintensity = 1.0\ngobo = \"fine.png\"",
            "at most 80°",
        ),
        (
            "type = \"spot\"\nposition = [0, 3, 0]\ndirection = [0, -1, 0]\ncutoff_deg = 30\nintensity = 1.0\ngobo_rotate_deg = 5",
            "gobo_rotate_deg",
        ),
        (
            "type = \"point\"\nposition = [0, 3, 0]\nintensity = 1.0\nies_rotate_deg = 10",
            "ies_rotate_deg",
        ),
        (
            "type = \"point\"\nposition = [0, 3, 0]\nintensity = 1.0\ndirection = [0, -1, 0]",
            "nadir",
        ),
        (
            "type = \"point\"\nposition = [0, 3, 0]\nintensity = 1.0\ntemperature_k = 100",
            "temperature_k",
        ),
        (
            "type = \"point\"\nposition = [0, 3, 0]\nies = \"missing.ies\"",
            "missing.ies: ",
        ),
        (
            "type = \"spot\"\nposition = [0, 3, 0]\ndirection = [0, -1, 0]\ncutoff_deg = 30",
            "intensity",
        ),
    ] {
        let scene = dir.join("keys.toml");
        std::fs::write(
            &scene,
            format!("[camera]\nposition = [0, 1, 6]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\n\n[[lights]]\n{table}\n"),
        )
        .expect("write scene");
        let err = common::load_native(&scene)
            .err()
            .unwrap_or_else(|| panic!("{table}: accepted"))
            .to_string();
        assert!(err.contains(expected), "{table}: {err}");
    }
}
