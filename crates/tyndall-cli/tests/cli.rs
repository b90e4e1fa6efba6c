//! The `tyndall` binary: exit status 0 only when the image was written;
//! errors name file, line and column.

mod common;

use common::{repo, stderr, temp, temp_dir, tyndall};
use std::process::Command;

#[test]
fn renders_demo_to_png_and_exr() {
    for name in ["demo.png", "demo.exr"] {
        let out = temp(name);
        let o = tyndall(&[
            "render",
            "-o",
            out.to_str().unwrap(),
            "--width",
            "32",
            "--height",
            "18",
            "--spp",
            "1",
            "-q",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(out.exists());
    }
    let image = tyndall_image::read_exr(&temp_dir().join("demo.exr")).expect("readable EXR");
    assert_eq!((image.width(), image.height()), (32, 18));
    assert!(image.pixels().iter().any(|p| p.max_element() > 0.0));
}

#[test]
fn renders_legacy_scene_with_fog_from_flags() {
    let out = temp("legacy.png");
    let scene = repo().join("scenes/legacy/fig07-spot-sphere.obj");
    let o = tyndall(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "40",
        "--height",
        "30",
        "--spp",
        "2",
        "--step",
        "0.2",
        "--density",
        "0.1",
        "--albedo",
        "5",
        "--threads",
        "2",
        "--seed",
        "3",
        "--exposure",
        "-1",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("not physical"),
        "albedo 5 warns: {}",
        stderr(&o)
    );
    assert!(
        stderr(&o).contains("rays/s"),
        "statistics at the end: {}",
        stderr(&o)
    );
    assert!(out.exists());
}

#[test]
fn volpath_renders_legacy_scene_with_fog_from_flags() {
    let out = temp("volpath.png");
    let scene = repo().join("scenes/legacy/cornell_box.obj");
    let o = tyndall(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--width",
        "24",
        "--height",
        "24",
        "--spp",
        "2",
        "--integrator",
        "volpath",
        "--max-depth",
        "4",
        "--density",
        "0.3",
        "--albedo",
        "0.9",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.exists());
}

/// The smoke scene renders with `volpath`; a single-scattering integrator
/// refuses its volumes with an error that says what to use, and writes
/// nothing.
#[test]
fn smoke_scene_renders_with_volpath_only() {
    let scene = repo().join("scenes/smoke.toml");
    let small = ["--width", "24", "--height", "27", "--spp", "2"];
    let out = temp("smoke.png");
    let mut args = vec![
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend(small);
    let o = tyndall(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.exists());
    let refused = temp("smoke-single.png");
    let mut args = vec![
        "render",
        scene.to_str().unwrap(),
        "-o",
        refused.to_str().unwrap(),
        "--integrator",
        "single",
    ];
    args.extend(small);
    let o = tyndall(&args);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("--integrator volpath"),
        "{}",
        stderr(&o)
    );
    assert!(!refused.exists());
}

#[test]
fn renders_with_shadow_maps_and_interleaving() {
    let out = temp("maps.png");
    let o = tyndall(&[
        "render",
        "-o",
        out.to_str().unwrap(),
        "--width",
        "48",
        "--height",
        "27",
        "--spp",
        "1",
        "--integrator",
        "march",
        "--step",
        "0.3",
        "--visibility",
        "maps",
        "--shadow-map-resolution",
        "64",
        "--interleave",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("shadow maps: 64²"), "{}", stderr(&o));
    assert!(out.exists());
}

#[test]
fn bad_inputs_fail_without_writing_an_image() {
    let bad_scene = temp("bad.toml");
    let good =
        std::fs::read_to_string(repo().join("scenes/fig07-spot-sphere.toml")).expect("scene");
    std::fs::write(
        &bad_scene,
        good.replace("cutoff_deg = 30.0", "cutoff_deg = 120.0"),
    )
    .expect("write");
    let bad = bad_scene.to_str().unwrap().to_owned();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["render", &bad], "bad.toml:"),
        (
            vec!["render", "--width", "0"],
            "--width: `width` must be between 1",
        ),
        (vec!["render", "--density", "-1"], "--density"),
        (vec!["render", "--integrator", "fast"], "unknown integrator"),
        (vec!["render", "no-such-scene.toml"], "no-such-scene.toml"),
        (
            vec!["render", "--albedo", "5", "--integrator", "single"],
            "not physical",
        ),
    ];
    for (mut args, words) in cases {
        let out = temp("never.png");
        args.extend(["-o", out.to_str().unwrap()]);
        let o = tyndall(&args);
        assert!(!o.status.success(), "{args:?} should fail");
        assert!(
            stderr(&o).contains(words),
            "{args:?}: `{words}` not in {}",
            stderr(&o)
        );
        assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
        assert!(!out.exists(), "{args:?} wrote an image");
    }
    let o = tyndall(&["render", &bad]);
    let message = stderr(&o);
    let line = good
        .lines()
        .position(|l| l.starts_with("cutoff_deg"))
        .expect("cutoff line")
        + 1;
    assert!(
        message.contains(&format!("bad.toml:{line}:1:")) && message.contains("cutoff_deg"),
        "line and column: {message}"
    );
}

#[test]
fn help_explains_every_flag() {
    let o = tyndall(&["render", "--help"]);
    let help = String::from_utf8_lossy(&o.stdout);
    for flag in [
        "--width",
        "--height",
        "--spp",
        "--integrator",
        "--step",
        "--density",
        "--albedo",
        "--threads",
        "--seed",
        "--exposure",
        "--output",
        "--max-depth",
        "--volume-samples",
        "--visibility",
        "--shadow-map-resolution",
        "--interleave",
    ] {
        assert!(help.contains(flag), "{flag} missing from --help");
    }
}

/// Issue 11: an unwritable output was found only after the whole render.
/// The output file is now created before rendering, so a render that
/// would take minutes fails at once, naming the path.
#[test]
fn unwritable_output_fails_before_rendering() {
    let out = temp_dir().join("no-such-dir/out.png");
    let start = std::time::Instant::now();
    let o = tyndall(&[
        "render",
        "-o",
        out.to_str().unwrap(),
        "--width",
        "2048",
        "--height",
        "2048",
        "--spp",
        "256",
        "-q",
    ]);
    let secs = start.elapsed().as_secs_f32();
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("no-such-dir/out.png") && err.contains("cannot create the output file"),
        "{err}"
    );
    assert!(secs < 30.0, "took {secs} s: it rendered first");
}

/// The image appears under its name only when complete, and no
/// temporary file is left beside it; `--threads` above the machine's
/// parallelism is capped with a warning.
#[test]
fn output_is_renamed_into_place_and_threads_are_capped() {
    let dir = temp_dir().join("atomic");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("demo.png");
    let o = tyndall(&[
        "render",
        "-o",
        out.to_str().unwrap(),
        "--width",
        "8",
        "--height",
        "8",
        "--spp",
        "1",
        "--threads",
        "100000",
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("100000 threads requested"),
        "{}",
        stderr(&o)
    );
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, vec!["demo.png".to_string()]);
}

/// Issue 11: a PNG cut off by a file-size limit was left behind truncated
/// (or the process was killed by SIGXFSZ). Now the write fails with an
/// error, the exit status is non-zero and nothing is left behind.
#[cfg(unix)]
#[test]
fn file_size_limit_is_an_error_and_leaves_nothing() {
    let dir = temp_dir().join("fsize");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("big.png");
    let script = format!(
        "ulimit -f 1; exec '{}' render -o '{}' --width 128 --height 128 --spp 1 -q",
        env!("CARGO_BIN_EXE_tyndall"),
        out.display()
    );
    let o = Command::new("sh").arg("-c").arg(&script).output().unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("the image was not written"),
        "{}",
        stderr(&o)
    );
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}
