//! `render --aov` and `--denoise` from the command line (issue 24): the
//! AOVs are layers of the EXR beside an unchanged radiance, merged tiles
//! carry them, and bad requests fail before rendering and leave no image.
mod common;

use common::{repo, stderr, temp, tyndall};
use std::path::Path;

/// The channels of an EXR file, by name.
fn channels(path: &Path) -> Vec<(String, Vec<f32>)> {
    use exr::prelude::*;
    let image = read_all_flat_layers_from_file(path).expect("exr");
    let layer = &image.layer_data[0];
    layer
        .channel_data
        .list
        .iter()
        .map(|c| {
            let values = match &c.sample_data {
                FlatSamples::F32(v) => v.clone(),
                other => panic!("{}: not f32: {other:?}", c.name),
            };
            (c.name.to_string(), values)
        })
        .collect()
}

const SIZE: [&str; 6] = ["--width", "24", "--height", "16", "--spp", "2"];

fn render(extra: &[&str], output: &Path) -> std::process::Output {
    render_scene(
        &repo().join("scenes/reference/fog-spot-sphere.toml"),
        extra,
        output,
    )
}

fn render_scene(scene: &Path, extra: &[&str], output: &Path) -> std::process::Output {
    let mut args = vec!["render", scene.to_str().expect("path"), "-q", "-o"];
    args.push(output.to_str().expect("path"));
    args.extend(SIZE);
    args.extend(extra);
    tyndall(&args)
}

/// Renders `scene` as two tiles (`tag` names their files) and merges
/// them with `--aov aovs`; the merged file.
fn merged_tiles(scene: &Path, tag: &str, aovs: &str) -> std::path::PathBuf {
    let (a, b) = (temp(&format!("{tag}0.exr")), temp(&format!("{tag}1.exr")));
    let merged = temp(&format!("{tag}-merged.exr"));
    for (tile, path) in [("0/2", &a), ("1/2", &b)] {
        let out = render_scene(scene, &["--tile", tile], path);
        assert!(out.status.success(), "{}", stderr(&out));
    }
    let out = tyndall(&[
        "merge",
        a.to_str().expect("path"),
        b.to_str().expect("path"),
        "-o",
        merged.to_str().expect("path"),
        "--aov",
        aovs,
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    merged
}

#[test]
fn aovs_are_exr_layers_beside_the_same_radiance() {
    let (plain, with) = (temp("plain.exr"), temp("aovs.exr"));
    assert!(render(&[], &plain).status.success());
    let out = render(
        &[
            "--aov",
            "albedo,normal,depth,position,emission,direct,indirect,volume",
        ],
        &with,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let plain = channels(&plain);
    let with = channels(&with);
    let names: Vec<&str> = with.iter().map(|(n, _)| n.as_str()).collect();
    for name in [
        "B",
        "G",
        "R",
        "albedo.B",
        "albedo.G",
        "albedo.R",
        "depth.Z",
        "normal.X",
        "normal.Y",
        "normal.Z",
        "position.X",
        "position.Y",
        "position.Z",
    ] {
        assert!(names.contains(&name), "{name} missing from {names:?}");
    }
    for (name, values) in &plain {
        let same = with.iter().find(|(n, _)| n == name).expect("channel");
        assert_eq!(&same.1, values, "{name}: the radiance changed");
    }
    // The components sum to the radiance, to f32 rounding.
    let channel = |name: &str| &with.iter().find(|(n, _)| n == name).expect(name).1;
    for c in ["R", "G", "B"] {
        let beauty = channel(c);
        for (i, b) in beauty.iter().enumerate() {
            let sum: f32 = ["emission", "direct", "indirect", "volume"]
                .iter()
                .map(|k| channel(&format!("{k}.{c}"))[i])
                .sum();
            assert!(
                (sum - b).abs() <= 64.0 * f32::EPSILON * b.abs() + 1e-12,
                "{c} {i}: {sum} vs {b}"
            );
        }
    }
    // The floor is grey 0.5 and diffuse: wherever a pixel sees only it,
    // the albedo is 0.5; the normal is a unit vector or (at edges) shorter.
    let albedo = &with
        .iter()
        .find(|(n, _)| n == "albedo.R")
        .expect("albedo")
        .1;
    assert!(albedo.contains(&0.5), "{albedo:?}");
    assert!(albedo.iter().all(|&a| (0.0..=1.0).contains(&a)));
}

#[test]
fn merged_tiles_carry_the_aovs() {
    let scene = repo().join("scenes/reference/fog-spot-sphere.toml");
    let merged = merged_tiles(&scene, "t", "depth");
    let whole = temp("whole.exr");
    assert!(render(&["--aov", "depth"], &whole).status.success());
    assert_eq!(channels(&merged), channels(&whole));
}

/// fog-spot-sphere with its spot in the group `key` and a second spot in
/// `rim-2`, written where the test can read it.
fn grouped_scene() -> std::path::PathBuf {
    let text = std::fs::read_to_string(repo().join("scenes/reference/fog-spot-sphere.toml"))
        .expect("scene");
    let text = format!(
        "{text}light_group = \"key\"\n\n[[lights]]\ntype = \"spot\"\nposition = [1.5, 2.5, 1.0]\nlook_at = [0.0, 0.5, 0.0]\ncutoff_deg = 15.0\nintensity = 30.0\nlight_group = \"rim-2\"\n"
    );
    let path = temp("grouped.toml");
    std::fs::write(&path, text).expect("write");
    path
}

/// `--aov light_groups` writes one layer per group, which sum to the
/// radiance; tiles keep the groups' sums unasked, and merged they give
/// the whole render's layers bit for bit.
#[test]
fn light_groups_are_layers_that_sum_to_the_radiance_and_merge() {
    let scene = grouped_scene();
    let whole = temp("groups.exr");
    let out = render_scene(&scene, &["--aov", "light_groups"], &whole);
    assert!(out.status.success(), "{}", stderr(&out));
    let layers = channels(&whole);
    let channel = |name: &str| &layers.iter().find(|(n, _)| n == name).expect(name).1;
    for c in ["R", "G", "B"] {
        for (i, b) in channel(c).iter().enumerate() {
            let sum: f32 = ["other", "key", "rim-2"]
                .iter()
                .map(|g| channel(&format!("light_group.{g}.{c}"))[i])
                .sum();
            assert!(
                (sum - b).abs() <= 64.0 * f32::EPSILON * b.abs() + 1e-12,
                "{c} {i}: {sum} vs {b}"
            );
        }
    }
    // Only the two spots light the scene: the rest is black.
    assert!(channel("light_group.other.R").iter().all(|&v| v == 0.0));
    for group in ["key", "rim-2"] {
        let lit = channel(&format!("light_group.{group}.G"));
        assert!(lit.iter().any(|&v| v > 0.0), "{group} has no light");
    }
    let merged = merged_tiles(&scene, "g", "light_groups");
    assert_eq!(channels(&merged), layers);
}

#[test]
fn bad_requests_fail_before_rendering_and_write_nothing() {
    let cases: [(&[&str], &str, &str); 5] = [
        (
            &["--aov", "depth", "--tile", "0/2"],
            "x.exr",
            "tyndall merge --aov",
        ),
        (&["--aov", "albedo,shadow"], "x.exr", "unknown AOV `shadow`"),
        (&["--aov", "albedo"], "x.png", "must be an .exr"),
        (&["--denoise", "--tile", "0/2"], "x.exr", "merge --denoise"),
        (
            &["--gpu", "--aov", "depth"],
            "x.exr",
            "--aov cannot be used with --gpu",
        ),
    ];
    for (flags, name, says) in cases {
        let output = temp(name);
        let out = render(flags, &output);
        assert!(!out.status.success(), "{flags:?} succeeded");
        assert!(stderr(&out).contains(says), "{flags:?}: {}", stderr(&out));
        assert!(!output.exists(), "{flags:?} wrote {}", output.display());
    }
    // Components of a render with light paths (caustics): refused.
    let output = temp("caustic.exr");
    let scene = repo().join("scenes/glass-sphere-focus.toml");
    let out = tyndall(&[
        "render",
        scene.to_str().expect("path"),
        "-q",
        "--aov",
        "volume",
        "--width",
        "8",
        "--height",
        "8",
        "--spp",
        "1",
        "-o",
        output.to_str().expect("path"),
    ]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("light paths"), "{}", stderr(&out));
    assert!(!output.exists());
    // An OIDN that cannot be loaded: named, and no image.
    for library in ["/nonexistent/libOpenImageDenoise.so.2", "/dev/null"] {
        let output = temp("denoised.png");
        let scene = repo().join("scenes/reference/fog-spot-sphere.toml");
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_tyndall"))
            .args([
                "render",
                scene.to_str().expect("path"),
                "-q",
                "--denoise",
                "-o",
            ])
            .arg(&output)
            .args(SIZE)
            .env("TYNDALL_OIDN", library)
            .output()
            .expect("run");
        assert!(!out.status.success());
        let text = stderr(&out);
        assert!(
            text.contains("--denoise") && text.contains(library),
            "{text}"
        );
        assert!(!output.exists());
    }
}
