//! `tyndall view` in a real window: started under a display (Xvfb in CI:
//! `.ci/run` runs this test under `xvfb-run`), it renders N frames, saves
//! its image and exits. The screenshot must equal `tyndall render --gpu`
//! of the same view with N frames byte for byte: both are the mean of the
//! same N frames (same seed, same frame indices, same device, sums in the
//! same order), tone-mapped by the same function (`to_srgb8`), so any
//! difference is a bug — a lost or extra frame, a wrong size, a stale
//! view, a framebuffer packing error — not noise. Both run without an
//! interleaving tile (`--interleave 1`): with one, the young view shows
//! its in-scattered light filtered over the tile, which files never hold
//! (`GpuMarch::display_image`, tested in crates/tyndall-gpu/tests).
//!
//! Skips with a message when there is no display or no GPU adapter,
//! unless `TYNDALL_REQUIRE_GPU=1` (CI), where both are failures.
#![cfg(feature = "view")]

mod common;

use common::{stderr, temp, tyndall};

fn required() -> bool {
    std::env::var("TYNDALL_REQUIRE_GPU").is_ok_and(|v| v == "1")
}

/// Decodes a PNG into (width, height, RGB bytes).
fn read_png(path: &std::path::Path) -> (u32, u32, Vec<u8>) {
    let image = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .into_rgb8();
    (image.width(), image.height(), image.into_raw())
}

#[test]
fn viewer_screenshot_equals_the_headless_gpu_render() {
    const TEST: &str = "viewer_screenshot_equals_the_headless_gpu_render";
    if std::env::var_os("DISPLAY").is_none() {
        assert!(
            !required(),
            "{TEST}: no DISPLAY, and TYNDALL_REQUIRE_GPU=1 (run under xvfb-run)"
        );
        eprintln!("{TEST}: SKIPPED, no DISPLAY (run under xvfb-run)");
        return;
    }
    let (width, height, frames) = ("64", "40", "6");
    let shot = temp("view-shot.png");
    let o = tyndall(&[
        "view",
        // On lavapipe the view would start on the CPU.
        "--gpu",
        "--interleave",
        "1",
        "--width",
        width,
        "--height",
        height,
        "--frames",
        frames,
        "--screenshot",
        shot.to_str().unwrap(),
    ]);
    let message = stderr(&o);
    if !o.status.success() && message.contains("no GPU adapter") && !required() {
        eprintln!("{TEST}: SKIPPED, no GPU adapter on this machine");
        return;
    }
    assert!(o.status.success(), "view failed: {message}");
    let reference = temp("view-reference.png");
    let o = tyndall(&[
        "render",
        "--gpu",
        "--integrator",
        "march",
        "--interleave",
        "1",
        "--width",
        width,
        "--height",
        height,
        "--spp",
        frames,
        "-o",
        reference.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "render --gpu failed: {}", stderr(&o));
    let (w, h, shot_bytes) = read_png(&shot);
    let (rw, rh, reference_bytes) = read_png(&reference);
    assert_eq!((w, h), (64, 40), "screenshot size");
    assert_eq!((rw, rh), (64, 40), "reference size");
    // Not vacuous: the demo's beam makes a visible image.
    let lit = shot_bytes.iter().filter(|&&b| b > 8).count();
    assert!(
        lit > shot_bytes.len() / 20,
        "the screenshot is (nearly) black: {lit} bytes above 8"
    );
    let differing = shot_bytes
        .iter()
        .zip(&reference_bytes)
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(
        differing,
        0,
        "{differing} of {} bytes differ from render --gpu",
        shot_bytes.len()
    );
}

/// The progressive CPU view (`--cpu`, the default on lavapipe): after N
/// passes its screenshot equals `tyndall render --spp N` of the same view
/// byte for byte — the same render loop, one pass per sample index — and
/// `--denoise` with a library that does not load is an error before any
/// window opens.
#[test]
fn cpu_view_screenshot_equals_the_cpu_render() {
    const TEST: &str = "cpu_view_screenshot_equals_the_cpu_render";
    if std::env::var_os("DISPLAY").is_none() {
        assert!(
            !required(),
            "{TEST}: no DISPLAY, and TYNDALL_REQUIRE_GPU=1 (run under xvfb-run)"
        );
        eprintln!("{TEST}: SKIPPED, no DISPLAY (run under xvfb-run)");
        return;
    }
    let size = ["--width", "64", "--height", "40", "--interleave", "4"];
    let shot = temp("cpu-view-shot.png");
    let mut args = vec!["view", "--cpu", "--frames", "5", "--screenshot"];
    args.push(shot.to_str().unwrap());
    args.extend(size);
    let o = tyndall(&args);
    let message = stderr(&o);
    if !o.status.success() && message.contains("no GPU adapter") && !required() {
        eprintln!("{TEST}: SKIPPED, no GPU adapter on this machine");
        return;
    }
    assert!(o.status.success(), "view --cpu failed: {message}");
    let reference = temp("cpu-view-reference.png");
    let mut args = vec!["render", "--integrator", "march", "--spp", "5", "-o"];
    args.push(reference.to_str().unwrap());
    args.extend(size);
    let o = tyndall(&args);
    assert!(o.status.success(), "render failed: {}", stderr(&o));
    let (shot, reference) = (read_png(&shot), read_png(&reference));
    assert_eq!((shot.0, shot.1), (64, 40));
    let lit = shot.2.iter().filter(|&&b| b > 8).count();
    assert!(lit > shot.2.len() / 20, "the screenshot is (nearly) black");
    assert!(
        shot == reference,
        "the CPU view's 5 passes differ from render --spp 5"
    );

    let o = std::process::Command::new(env!("CARGO_BIN_EXE_tyndall"))
        .args(["view", "--cpu", "--denoise", "--frames", "1"])
        .env("TYNDALL_OIDN", "/nonexistent/oidn")
        .output()
        .expect("run");
    assert!(!o.status.success());
    assert!(stderr(&o).contains("/nonexistent/oidn"), "{}", stderr(&o));
    // The GPU view is not denoised: asking is an error, not ignored (it
    // needs a library that loads, which CI names).
    if std::env::var_os("TYNDALL_OIDN").is_some() {
        let o = tyndall(&["view", "--gpu", "--denoise", "--frames", "1"]);
        assert!(!o.status.success());
        assert!(stderr(&o).contains("only the CPU view"), "{}", stderr(&o));
    }
}

#[test]
fn view_help_lists_the_controls_and_bad_flags_are_errors() {
    let o = tyndall(&["view", "--help"]);
    assert!(o.status.success());
    let help = String::from_utf8_lossy(&o.stdout);
    for words in [
        "mouse drag",
        "fog density",
        "march step",
        "glass model",
        "save a PNG",
    ] {
        assert!(help.contains(words), "`{words}` not in --help:\n{help}");
    }
    let cases: [(&[&str], &str); 4] = [
        (&["--screenshot", "x.png"], "--frames"),
        (&["--cpu", "--gpu"], "cannot be used with"),
        (&["--frames", "2", "--screenshot", "x.exr"], "PNG"),
        (&["--integrator", "volpath"], "only `march`"),
    ];
    for (flags, words) in cases {
        let mut args = vec!["view"];
        args.extend(flags);
        let o = tyndall(&args);
        assert!(!o.status.success(), "{args:?} should fail");
        assert!(
            stderr(&o).contains(words),
            "{args:?}: `{words}` not in {}",
            stderr(&o)
        );
    }
}
