//! OpenVDB grids as `[[media]]` densities. The test files were written by
//! the real OpenVDB library (tests/data/make_test_vdbs.py): a fog sphere
//! of radius 1 at (0.5, 0.25, −0.25), voxel size h = 1/16, each voxel
//! holding the fraction of its cell inside the sphere.

mod common;

use glam::Vec3;
use std::path::{Path, PathBuf};
use tyndall::media::tracking::VolumeTracker;
use tyndall::media::volume::Volume;
use tyndall::ray::Ray;
use tyndall::testing::RandomStream;

const RADIUS: f32 = 1.0;
const CENTER: Vec3 = Vec3::new(0.5, 0.25, -0.25);
const VOXEL: f32 = 1.0 / 16.0;
const SIGMA: f32 = 2.0;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Loads a scene holding one medium written by `medium` (TOML lines).
fn load(name: &str, medium: &str) -> Result<common::Loaded, String> {
    let dir = std::env::temp_dir().join(format!("tyndall-load-vdb-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join(format!("{name}.toml"));
    let text = format!(
        "[camera]\nposition = [0, 0, 10]\nlook_at = [0, 0, 0]\nfov_y_deg = 30\n\n\
         [render]\nintegrator = \"volpath\"\n\n\
         [[media]]\nsigma_t = {SIGMA}\nalbedo = 0.5\ndensity = \"vdb\"\n{medium}\n"
    );
    std::fs::write(&path, text).expect("write scene");
    common::load_any(&path, Default::default()).map_err(|e| e.to_string())
}

/// Optical depth along the line `origin + t·dir` (|dir| = 1) over
/// `[t0, t1]` by the midpoint rule with steps of h/16: far finer than the
/// voxels, so its error is negligible beside the voxelisation's.
fn optical_depth(volume: &Volume, origin: Vec3, dir: Vec3, t0: f32, t1: f32) -> f32 {
    let n = ((t1 - t0) / (VOXEL / 16.0)).ceil() as usize;
    let dt = (t1 - t0) / n as f32;
    (0..n)
        .map(|i| {
            volume
                .extinction_at(origin + dir * (t0 + (i as f32 + 0.5) * dt))
                .x
                * dt
        })
        .sum()
}

/// Lines at impact parameter `b` from `center`, in a few directions.
fn lines(center: Vec3, b: f32) -> Vec<(Vec3, Vec3)> {
    [
        (Vec3::X, Vec3::Y),
        (Vec3::Y, Vec3::Z),
        (
            Vec3::new(1.0, 1.0, 1.0).normalize(),
            Vec3::new(1.0, -1.0, 0.0).normalize(),
        ),
        (Vec3::new(0.3, -0.8, 0.5).normalize(), Vec3::Z),
    ]
    .into_iter()
    .map(|(dir, across)| {
        let across = (across - dir * across.dot(dir)).normalize();
        (center + across * b, dir)
    })
    .collect()
}

/// The optical depth through the voxelised sphere matches the uniform
/// sphere's closed form `σ·2√(R² − b²)` within the voxelisation's
/// resolution: the anti-aliased boundary is smeared over one voxel
/// spacing at each end, so the chord is right to within `h` in total,
/// an optical-depth tolerance of `σ·h`. Also for a copy placed with
/// `scale = 2` and `translate`, whose radius is 2 and voxels 2h.
#[test]
fn vdb_sphere_optical_depth_matches_the_uniform_sphere() {
    let file = data("sphere.vdb");
    let desc = load("sphere", &format!("file = {:?}", file.to_str().unwrap())).expect("loads");
    let placed = load(
        "placed",
        &format!(
            "file = {:?}\nscale = 2\ntranslate = [0, 5, 0]",
            file.to_str().unwrap()
        ),
    )
    .expect("loads");
    for (desc, center, radius, h) in [
        (&desc, CENTER, RADIUS, VOXEL),
        (
            &placed,
            2.0 * CENTER + Vec3::new(0.0, 5.0, 0.0),
            2.0 * RADIUS,
            2.0 * VOXEL,
        ),
    ] {
        let volume = &desc.scene.volumes()[0];
        for b in [0.0, 0.3, 0.6, 0.9] {
            let b = b * radius;
            for (p, dir) in lines(center, b) {
                let reach = radius + 4.0 * h;
                let tau = optical_depth(volume, p, dir, -reach, reach);
                let expected = SIGMA * 2.0 * (radius * radius - b * b).sqrt();
                assert!(
                    (tau - expected).abs() <= SIGMA * h,
                    "b = {b}, dir {dir}: τ = {tau}, sphere {expected}, tolerance {}",
                    SIGMA * h
                );
            }
        }
        // Outside the sphere the density is the background, 0.
        let outside = center + Vec3::new(radius + 2.0 * h, 0.0, 0.0);
        assert_eq!(volume.extinction_at(outside).x, 0.0);
    }
}

/// Ratio tracking against the grid's majorants (built from its leaves
/// and tiles) estimates the transmittance of the field itself: the mean
/// of N independent estimates lies within 4 standard errors of
/// exp(−τ) with τ from quadrature. A majorant below the density would
/// clamp the ratio-tracking weights and bias the estimate low.
#[test]
fn ratio_tracking_through_the_vdb_sphere_is_unbiased() {
    let file = data("sphere.vdb");
    let desc = load("tracking", &format!("file = {:?}", file.to_str().unwrap())).expect("loads");
    let volumes = desc.scene.volumes();
    for b in [0.0, 0.5, 0.95] {
        let (p, dir) = lines(CENTER, b)[2];
        let reach = RADIUS + 4.0 * VOXEL;
        let exact = (-optical_depth(&volumes[0], p, dir, -reach, reach)).exp();
        let ray = Ray::new(p - dir * reach, dir);
        let mut tracker = VolumeTracker::new(RandomStream::new(17));
        let n = 4000;
        let samples: Vec<f64> = (0..n)
            .map(|_| tracker.transmittance(volumes, &ray, 0.0, 2.0 * reach).x as f64)
            .collect();
        let mean = samples.iter().sum::<f64>() / n as f64;
        let var = samples.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let stderr = (var / n as f64).sqrt().max(1e-4);
        assert!(
            (mean - exact as f64).abs() <= 4.0 * stderr,
            "b = {b}: ratio tracking {mean} ± {stderr}, quadrature {exact}"
        );
    }
}

/// A second grid is chosen by `grid`, with its own transform: index
/// (i, j, k) at (1, 2, 3) + 0.25·(i, j, k); the medium's box is the
/// active voxels' cells.
#[test]
fn grid_key_picks_a_grid_with_its_transform() {
    let file = data("multi.vdb");
    let desc = load(
        "temperature",
        &format!(
            "file = {:?}\ngrid = \"temperature\"",
            file.to_str().unwrap()
        ),
    )
    .expect("loads");
    let volume = &desc.scene.volumes()[0];
    let b = volume.field_box();
    assert!(
        (b.min - Vec3::new(0.875, 1.875, 2.875)).abs().max_element() < 1e-5,
        "{b:?}"
    );
    assert!(
        (b.max - Vec3::new(1.375, 2.375, 3.375)).abs().max_element() < 1e-5,
        "{b:?}"
    );
    // Value 2 at every active voxel centre; between them too.
    let x = Vec3::new(1.125, 2.125, 3.125);
    assert!((volume.extinction_at(x).x - SIGMA * 2.0).abs() < 1e-5);
}

/// Every reader failure is an error naming the scene line, the file and
/// the grid — never a panic.
#[test]
fn vdb_errors_name_file_and_grid() {
    let cases = [
        ("half.vdb", None, "half floats"),
        ("multi.vdb", Some("velocity"), "only float grids"),
        (
            "multi.vdb",
            Some("smoke"),
            "\"density\", \"temperature\", \"velocity\"",
        ),
        ("missing.vdb", None, "cannot open"),
        ("make_test_vdbs.py", None, "not a readable OpenVDB file"),
    ];
    for (name, grid, expected) in cases {
        let file = data(name);
        let mut medium = format!("file = {:?}", file.to_str().unwrap());
        if let Some(g) = grid {
            medium += &format!("\ngrid = \"{g}\"");
        }
        let m = load("bad", &medium).err().expect("a bad grid is an error");
        assert!(m.contains(expected) && m.contains(name), "{name}: {m}");
        if expected != "cannot open" && expected != "not a readable OpenVDB file" {
            assert!(
                m.contains(&format!("grid \"{}\"", grid.unwrap_or("density"))),
                "{m}"
            );
        }
        assert!(m.contains("bad.toml:"), "names the scene line: {m}");
    }
}

/// A `box` restricts a VDB medium without moving its field: inside the
/// box (x below the sphere's centre) the optical depth along the x axis
/// through the centre is half the sphere's, σR, within the voxelisation's
/// half-voxel; and ratio tracking along the whole line sees only that half
/// (mean of N estimates within 4 standard errors of exp(−τ_half)).
#[test]
fn box_restricts_a_vdb_medium() {
    let file = data("sphere.vdb");
    let medium = format!(
        "file = {:?}\nbox = {{ min = [-2, -2, -2], max = [{}, 2, 2] }}",
        file.to_str().unwrap(),
        CENTER.x
    );
    let desc = load("boxed", &medium).expect("loads");
    let volumes = desc.scene.volumes();
    let reach = RADIUS + 4.0 * VOXEL;
    let tau_half = optical_depth(&volumes[0], CENTER, Vec3::X, -reach, 0.0);
    assert!(
        (tau_half - SIGMA * RADIUS).abs() <= SIGMA * VOXEL / 2.0,
        "τ = {tau_half}, half sphere {}",
        SIGMA * RADIUS
    );
    let ray = Ray::new(CENTER - Vec3::X * reach, Vec3::X);
    let mut tracker = VolumeTracker::new(RandomStream::new(5));
    let n = 4000;
    let samples: Vec<f64> = (0..n)
        .map(|_| tracker.transmittance(volumes, &ray, 0.0, 2.0 * reach).x as f64)
        .collect();
    let mean = samples.iter().sum::<f64>() / n as f64;
    let var = samples.iter().map(|s| (s - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    let stderr = (var / n as f64).sqrt().max(1e-4);
    let exact = (-tau_half as f64).exp();
    assert!(
        (mean - exact).abs() <= 4.0 * stderr,
        "ratio tracking {mean} ± {stderr}, half sphere {exact}"
    );
}

/// scenes/smoke-vdb.toml holds the plume of scenes/smoke.toml converted to
/// OpenVDB (scenes/smoke/make_plume_vdb.py): both hold the same densities
/// at the same voxel centres, so between the outermost centres their
/// trilinear fields agree to float rounding at every point of a lattice.
#[test]
fn vdb_plume_matches_the_tgrid_plume() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let dense = common::load_any(&scenes.join("smoke.toml"), Default::default()).expect("tgrid");
    let sparse = common::load_any(&scenes.join("smoke-vdb.toml"), Default::default()).expect("vdb");
    let (a, b) = (&dense.scene.volumes()[0], &sparse.scene.volumes()[0]);
    let lo = Vec3::new(-1.2, 0.0, -1.2) + 0.025;
    let hi = Vec3::new(1.2, 4.0, 1.2) - 0.025;
    let n = 23;
    let mut largest = 0.0f32;
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let u = Vec3::new(i as f32, j as f32, k as f32) / (n - 1) as f32;
                let x = lo + (hi - lo) * u;
                let (da, db) = (a.extinction_at(x), b.extinction_at(x));
                largest = largest.max(da.max_element());
                assert!(
                    (da - db).abs().max_element() <= 1e-4 * (1.0 + da.max_element()),
                    "at {x}: tgrid {da}, vdb {db}"
                );
            }
        }
    }
    assert!(largest > 1.0, "the lattice meets the smoke");
}
