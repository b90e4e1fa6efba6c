//! `tyndall render --tile/--samples/--checkpoint/--time-limit` and
//! `tyndall merge` (issue 13): parts reassemble into the single render,
//! a killed render resumes to the same file, bad requests fail cleanly.

mod common;

use common::{repo, stderr, temp, tyndall};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 path")
}

/// The glass-sphere scene (volpath with caustic light paths), tiny.
fn focus_args(extra: &[&str]) -> Vec<String> {
    let scene = repo().join("scenes/glass-sphere-focus.toml");
    let mut args: Vec<String> = [
        "render",
        s(&scene),
        "--width",
        "30",
        "--height",
        "24",
        "--spp",
        "3",
        "-q",
    ]
    .iter()
    .map(|a| a.to_string())
    .collect();
    args.extend(extra.iter().map(|a| a.to_string()));
    args
}

fn run(args: &[String]) -> Output {
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    tyndall(&args)
}

fn pixel_bits(path: &Path) -> Vec<[u32; 3]> {
    tyndall_image::read_exr(path)
        .expect("readable EXR")
        .pixels()
        .iter()
        .map(|p| p.to_array().map(f32::to_bits))
        .collect()
}

#[test]
fn tiles_and_sample_ranges_merge_into_the_single_render() {
    let single = temp("single.exr");
    let o = run(&focus_args(&["-o", s(&single)]));
    assert!(o.status.success(), "{}", stderr(&o));
    let tiles: Vec<PathBuf> = (0..3).map(|i| temp(&format!("tile{i}.exr"))).collect();
    for (i, t) in tiles.iter().enumerate() {
        let o = run(&focus_args(&["--tile", &format!("{i}/3"), "-o", s(t)]));
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let merged = temp("merged.exr");
    let o = tyndall(&[
        "merge",
        s(&tiles[2]),
        s(&tiles[0]),
        s(&tiles[1]),
        "-o",
        s(&merged),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(pixel_bits(&merged), pixel_bits(&single), "merged tiles");

    let ranges = [temp("s01.exr"), temp("s13.exr")];
    for (range, path) in ["0..1", "1..3"].iter().zip(&ranges) {
        let o = run(&focus_args(&["--samples", range, "-o", s(path)]));
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let merged_samples = temp("merged-samples.exr");
    let o = tyndall(&[
        "merge",
        s(&ranges[1]),
        s(&ranges[0]),
        "-o",
        s(&merged_samples),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let a = tyndall_image::read_exr(&merged_samples).expect("merged");
    let b = tyndall_image::read_exr(&single).expect("single");
    let e = tyndall_image::metrics::relative_mse(&a, &b);
    assert!(e <= 1e-12, "merged sample ranges: relMSE {e:e}");
}

#[test]
fn a_killed_render_resumes_from_its_checkpoint_to_the_same_file() {
    // Long enough (many passes) that it is still running after its first
    // checkpoints; small enough to finish in about a second.
    let args = |out: &Path, checkpoint: Option<&Path>| {
        let mut a: Vec<String> = [
            "render", "--width", "32", "--height", "18", "--spp", "300", "-q", "-o",
        ]
        .iter()
        .map(|a| a.to_string())
        .collect();
        a.push(s(out).to_string());
        if let Some(c) = checkpoint {
            a.extend(["--checkpoint", s(c), "--checkpoint-every", "0s"].map(String::from));
        }
        a
    };
    let reference = temp("uninterrupted.exr");
    let o = run(&args(&reference, None));
    assert!(o.status.success(), "{}", stderr(&o));

    let out = temp("resumed.exr");
    let checkpoint = temp("progress.ckpt.exr");
    let mut child = Command::new(env!("CARGO_BIN_EXE_tyndall"))
        .args(args(&out, Some(&checkpoint)))
        .stderr(Stdio::null())
        .spawn()
        .expect("start render");
    let start = Instant::now();
    while !checkpoint.exists() {
        assert!(
            child.try_wait().expect("wait").is_none(),
            "the render ended before its first checkpoint"
        );
        assert!(start.elapsed() < Duration::from_secs(60), "no checkpoint");
        std::thread::sleep(Duration::from_millis(2));
    }
    std::thread::sleep(Duration::from_millis(20));
    assert!(
        child.try_wait().expect("wait").is_none(),
        "the render finished before it could be killed: make it longer"
    );
    child.kill().expect("kill");
    child.wait().expect("reap");
    assert!(!out.exists(), "a killed render wrote no image");
    let saved = tyndall_image::parts::read_part(&checkpoint).expect("a whole checkpoint");
    let done = saved.accumulation.region.samples.clone();
    assert!(
        done.start == 0 && done.end >= 1 && done.end < 300,
        "{done:?}"
    );

    let o = run(&args(&out, Some(&checkpoint)));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(&out).expect("resumed image"),
        std::fs::read(&reference).expect("reference"),
        "the resumed render's file equals the uninterrupted render's, byte for byte"
    );
    assert!(!checkpoint.exists(), "the checkpoint is removed when done");
}

#[test]
fn a_time_limit_renders_whole_passes_and_says_how_many() {
    let limited = temp("limited.exr");
    let checkpoint = temp("limited.ckpt.exr");
    let o = tyndall(&[
        "render",
        "--width",
        "24",
        "--height",
        "16",
        "--spp",
        "50",
        "--time-limit",
        "1ms",
        "--checkpoint",
        s(&checkpoint),
        "-o",
        s(&limited),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Any pass takes longer than 1 ms: the first is the last.
    assert!(
        stderr(&o).contains("time limit reached: 1 samples per pixel (samples 0..1) of the 50"),
        "{}",
        stderr(&o)
    );
    let one = temp("one.exr");
    let o = tyndall(&[
        "render",
        "--width",
        "24",
        "--height",
        "16",
        "--spp",
        "1",
        "-q",
        "-o",
        s(&one),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(&limited).unwrap(),
        std::fs::read(&one).unwrap()
    );
    // The checkpoint keeps the progress: running again without a limit
    // continues from pass 1 to the full render.
    let part = tyndall_image::parts::read_part(&checkpoint).expect("checkpoint kept");
    assert_eq!(part.accumulation.region.samples, 0..1);
}

#[test]
fn bad_splits_fail_without_writing_anything() {
    let out = temp("bad.exr");
    let png = temp("bad.png");
    for (extra, expected) in [
        (vec!["--tile", "3/3", "-o", s(&out)], "I below N"),
        (vec!["--tile", "x", "-o", s(&out)], "expected I/N"),
        (vec!["--samples", "4..4", "-o", s(&out)], "empty"),
        (vec!["--samples", "4-8", "-o", s(&out)], "expected A..B"),
        // Issue 28: ran until killed, leaving a 0-byte temporary file.
        (
            vec!["--samples", "0..4294967295", "-o", s(&out)],
            "reaches past sample index 1048576",
        ),
        // Issue 28: failed after rendering, leaving out.exr behind.
        (
            vec!["--checkpoint", s(&out), "-o", s(&out)],
            "--checkpoint names the output file",
        ),
        (vec!["--tile", "0/2", "-o", s(&png)], "must be an .exr"),
        (vec!["--tile", "0/100", "-o", s(&out)], "at most 24 tiles"),
        (
            vec!["--time-limit", "3 parsecs", "-o", s(&out)],
            "unknown unit",
        ),
    ] {
        let o = run(&focus_args(&extra));
        assert!(!o.status.success(), "{extra:?} succeeded");
        assert!(stderr(&o).contains(expected), "{extra:?}: {}", stderr(&o));
        assert!(!out.exists() && !png.exists(), "{extra:?} wrote a file");
        let left: Vec<_> = std::fs::read_dir(out.parent().expect("folder"))
            .expect("scratch folder")
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().starts_with(".bad"))
            .collect();
        assert!(left.is_empty(), "{extra:?} left a temporary file");
    }
    // Merging a plain image, or tiles that leave a gap.
    let plain = temp("plain.exr");
    assert!(run(&focus_args(&["-o", s(&plain)])).status.success());
    let o = tyndall(&["merge", s(&plain), "-o", s(&out)]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("plain.exr: not a Tyndall render part"),
        "{}",
        stderr(&o)
    );
    let t0 = temp("gap0.exr");
    assert!(
        run(&focus_args(&["--tile", "0/3", "-o", s(&t0)]))
            .status
            .success()
    );
    let t2 = temp("gap2.exr");
    assert!(
        run(&focus_args(&["--tile", "2/3", "-o", s(&t2)]))
            .status
            .success()
    );
    let o = tyndall(&["merge", s(&t0), s(&t2), "-o", s(&out)]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("some tiles are missing"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
    // A checkpoint of another render, or of other pixels, is refused, not
    // silently mixed in.
    let o = run(&focus_args(&["--checkpoint", s(&t0), "-o", s(&out)]));
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("gap0.exr: cannot resume"),
        "{}",
        stderr(&o)
    );
    let seeded = temp("seed7.exr");
    let o = run(&focus_args(&[
        "--samples",
        "0..1",
        "--seed",
        "7",
        "-o",
        s(&seeded),
    ]));
    assert!(o.status.success());
    let o = run(&focus_args(&["--checkpoint", s(&seeded), "-o", s(&out)]));
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("seed7.exr: this checkpoint is of another"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
}

#[test]
fn help_explains_the_splitting_flags_and_merge() {
    let o = tyndall(&["render", "--help"]);
    let help = String::from_utf8_lossy(&o.stdout);
    for flag in [
        "--tile",
        "--samples",
        "--checkpoint",
        "--checkpoint-every",
        "--time-limit",
    ] {
        assert!(help.contains(flag), "{flag} missing from render --help");
    }
    let o = tyndall(&["merge", "--help"]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stdout).contains("--output"));
}

/// Issue 28: a part with four flipped bits in its pixel data was merged
/// into 11 NaN, 14 infinite and 19 negative pixels, exit 0. Its checksum
/// now refuses it, naming the file, and nothing is written.
#[test]
fn a_damaged_part_is_refused_by_merge() {
    let parts: Vec<PathBuf> = (0..2).map(|i| temp(&format!("damaged{i}.exr"))).collect();
    for (i, p) in parts.iter().enumerate() {
        let o = run(&focus_args(&["--tile", &format!("{i}/2"), "-o", s(p)]));
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let mut bytes = std::fs::read(&parts[1]).expect("part");
    // Bits in the last bytes of the file: the pixel data of its last block.
    let n = bytes.len();
    for (at, bit) in [
        (n - 9, 0x40),
        (n - 21, 0x08),
        (n - 40, 0x80),
        (n - 77, 0x01),
    ] {
        bytes[at] ^= bit;
    }
    std::fs::write(&parts[1], &bytes).expect("damage");
    let out = temp("damaged-merged.exr");
    let o = tyndall(&["merge", s(&parts[0]), s(&parts[1]), "-o", s(&out)]);
    assert!(!o.status.success(), "merged a damaged part");
    let e = stderr(&o);
    assert!(e.contains("damaged1.exr"), "{e}");
    assert!(!e.contains("panicked"), "{e}");
    assert!(!out.exists());
}
