//! `tyndall render --gpu`: flags the GPU path cannot honour are errors
//! naming the flag (no image written), and with an adapter the demo
//! renders to a file.
#![cfg(feature = "gpu")]

mod common;

use common::{repo, stderr, temp, tyndall};

#[test]
fn flags_the_gpu_cannot_honour_are_errors_naming_them() {
    let fig07 = repo().join("scenes/fig07-spot-sphere.toml");
    let fig07 = fig07.to_str().unwrap();
    let cornell = repo().join("scenes/cornell-fog.toml");
    let cornell = cornell.to_str().unwrap();
    let cases: [(&str, &[&str], &str); 8] = [
        (fig07, &["--integrator", "volpath"], "--integrator volpath"),
        (fig07, &["--tile", "0/2"], "--tile"),
        (fig07, &["--samples", "0..4"], "--samples"),
        (fig07, &["--threads", "2"], "--threads"),
        (fig07, &["--max-depth", "3"], "--max-depth"),
        // Volume samples are `single`'s; the march cannot honour them.
        (
            fig07,
            &["--integrator", "march", "--volume-samples", "4"],
            "--volume-samples",
        ),
        // The scene file asks for `volpath`: the GPU says so, not ignores it.
        (
            cornell,
            &[],
            "add --integrator march or --integrator single",
        ),
        (
            cornell,
            &["--integrator", "volpath"],
            "--integrator volpath",
        ),
    ];
    for (scene, flags, words) in cases {
        let out = temp("gpu-never.png");
        let mut args = vec!["render", scene, "--gpu", "-o", out.to_str().unwrap()];
        args.extend(flags);
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
}

#[test]
fn renders_the_demo_on_the_gpu() {
    for integrator in ["march", "single"] {
        renders_the_demo_with(integrator);
    }
}

/// The demo on the GPU with `integrator`: a lit, finite image of the size
/// asked for.
fn renders_the_demo_with(integrator: &str) {
    let out = temp(&format!("gpu-demo-{integrator}.exr"));
    let o = tyndall(&[
        "render",
        "--gpu",
        "--integrator",
        integrator,
        "--width",
        "32",
        "--height",
        "18",
        "--spp",
        "2",
        "-o",
        out.to_str().unwrap(),
    ]);
    let message = stderr(&o);
    if !o.status.success()
        && message.contains("no GPU adapter")
        && std::env::var("TYNDALL_REQUIRE_GPU").map_or(true, |v| v != "1")
    {
        eprintln!("renders_the_demo_on_the_gpu: SKIPPED, no GPU adapter on this machine");
        return;
    }
    assert!(o.status.success(), "{integrator}: {message}");
    let image = tyndall_image::read_exr(&out).expect("readable EXR");
    assert_eq!((image.width(), image.height()), (32, 18));
    assert!(image.pixels().iter().any(|p| p.max_element() > 0.0));
    assert!(image.pixels().iter().all(|p| p.is_finite()));
}
