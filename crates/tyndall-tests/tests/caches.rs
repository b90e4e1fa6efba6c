//! Simulation caches as users have them: one OpenVDB file per frame
//! (`fluid_data_####.vdb`, read at the frame chosen at load time) and a
//! cache in Blender's layout (nine half-float grids a frame).

mod common;

use glam::Vec3;
use std::path::{Path, PathBuf};

/// The extinction per unit density of the test scenes' media.
const SIGMA: f32 = 2.0;
/// The centre of the fog sphere of `sphere.vdb`
/// (tests/data/make_test_vdbs.py).
const CENTER: Vec3 = Vec3::new(0.5, 0.25, -0.25);

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// A cache as Blender writes it, one file per frame
/// (`cache/data/fluid_data_0012.vdb`): `file = "…_####.vdb"` reads the
/// frame chosen at load time (issue 21), the same grid as naming the
/// file itself. Without a frame, or at a frame whose file is missing,
/// the error names the scene's line (that of `file`) and the file.
#[test]
fn a_frame_sequence_reads_the_chosen_frame() {
    let dir = std::env::temp_dir().join(format!("tyndall-vdb-frames-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("cache/data")).expect("temp dir");
    std::fs::copy(
        data("sphere.vdb"),
        dir.join("cache/data/fluid_data_0012.vdb"),
    )
    .expect("copy");
    let scene = |file: &str| {
        let path = dir.join("fluid.toml");
        std::fs::write(
            &path,
            format!(
                "[camera]\nposition = [0, 0, 10]\nlook_at = [0, 0, 0]\nfov_y_deg = 30\n\n\
                 [render]\nintegrator = \"volpath\"\n\n\
                 [[media]]\nsigma_t = {SIGMA}\nalbedo = 0.5\ndensity = \"vdb\"\nfile = {file:?}\n"
            ),
        )
        .expect("write scene");
        path
    };
    let at = |frame: Option<u32>| {
        let options = tyndall_load::LoadOptions {
            frame,
            ..Default::default()
        };
        common::load_any(&scene("cache/data/fluid_data_####.vdb"), options)
    };
    let framed = at(Some(12)).expect("frame 12");
    assert!(
        !framed.warnings.iter().any(|w| w.contains("frame")),
        "{:?}",
        framed.warnings
    );
    let named = common::load_any(&scene("cache/data/fluid_data_0012.vdb"), Default::default())
        .expect("the file itself");
    let (a, b) = (&framed.scene.volumes()[0], &named.scene.volumes()[0]);
    for p in [Vec3::ZERO, CENTER, Vec3::new(0.7, 0.1, -0.4)] {
        assert_eq!(a.extinction_at(p), b.extinction_at(p), "at {p}");
    }
    let e = at(None).err().expect("no frame").to_string();
    assert!(
        e.contains("fluid.toml:13:1:") && e.contains("frame sequence") && e.contains("--frame N"),
        "{e}"
    );
    let e = at(Some(13)).err().expect("frame 13 is missing").to_string();
    assert!(e.contains("fluid_data_0013.vdb"), "{e}");
    // A frame no file takes is said, not silently dropped.
    let unused = common::load_any(
        &scene("cache/data/fluid_data_0012.vdb"),
        tyndall_load::LoadOptions {
            frame: Some(3),
            ..Default::default()
        },
    )
    .expect("loads");
    assert!(
        unused
            .warnings
            .iter()
            .any(|w| w.contains("frame 3 is unused")),
        "{:?}",
        unused.warnings
    );
}

/// A smoke cache laid out as Blender writes one (two frames of
/// `blender_cache/data/fluid_data_####.vdb`, half floats, Blender's nine
/// grids, written by OpenVDB: tests/data/make_blender_cache.py says why
/// not by Blender itself): each frame reads its own file (the plume
/// rises from frame 1 to 2), `density` is the default grid, the
/// constant `shadow` grid reads as its tile's value, and the grids that
/// are no density are refused by name: the vec3 `velocity` and the empty
/// `color_r`.
#[test]
fn a_blender_layout_cache_reads_frame_by_frame() {
    let pattern = data("blender_cache/data/fluid_data_####.vdb");
    let scene = |frame: u32, grid: Option<&str>| {
        let mut medium = format!("file = {:?}", pattern.to_str().unwrap());
        if let Some(g) = grid {
            medium += &format!("\ngrid = \"{g}\"");
        }
        let dir = std::env::temp_dir().join(format!("tyndall-vdb-cache-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let path = dir.join("cache.toml");
        std::fs::write(
            &path,
            format!(
                "[camera]\nposition = [0, 0, 10]\nlook_at = [0, 0, 0]\nfov_y_deg = 30\n\n\
                 [render]\nintegrator = \"volpath\"\n\n\
                 [[media]]\nsigma_t = {SIGMA}\nalbedo = 0.5\ndensity = \"vdb\"\n{medium}\n"
            ),
        )
        .expect("write scene");
        let options = tyndall_load::LoadOptions {
            frame: Some(frame),
            ..Default::default()
        };
        common::load_any(&path, options).map_err(|e| e.to_string())
    };
    // The plume's centre: index (8, 8, 3 + 2k) with voxels of 1/8 from
    // (−1, −1, 0) (make_blender_cache.py).
    let centre = |k: f32| Vec3::new(0.0, 0.0, (3.0 + 2.0 * k) / 8.0);
    let density = |frame: u32, at: Vec3| {
        scene(frame, None).expect("density").scene.volumes()[0]
            .extinction_at(at)
            .x
    };
    assert!(density(1, centre(1.0)) > density(2, centre(1.0)));
    assert!(density(2, centre(2.0)) > density(1, centre(2.0)));
    assert!(density(1, centre(1.0)) > 0.5 * SIGMA);
    let shadow = scene(1, Some("shadow")).expect("shadow");
    assert_eq!(
        shadow.scene.volumes()[0]
            .extinction_at(Vec3::new(0.0, 0.0, 1.0))
            .x,
        SIGMA
    );
    let e = scene(1, Some("velocity"))
        .err()
        .expect("a vec3 grid is no density");
    assert!(e.contains("velocity") && e.contains("vec3"), "{e}");
    let e = scene(2, Some("color_r"))
        .err()
        .expect("an empty grid renders nothing");
    assert!(
        e.contains("fluid_data_####.vdb") || e.contains("no active voxels"),
        "{e}"
    );
}
