//! What the GPU tests share: opening the device, or skipping; a scene
//! written to a folder of its own and loaded. (Each test crate uses some
//! of it.)
#![allow(dead_code)]

use tyndall_gpu::{Gpu, GpuError};

/// The GPU device, or `None` (with a message) when this machine has no
/// adapter at all. With `TYNDALL_REQUIRE_GPU=1` (set by `.ci/run`, which
/// installs lavapipe) a missing adapter fails the test instead. Any other
/// error fails it always.
pub fn gpu_or_skip(test: &str) -> Option<Gpu> {
    match Gpu::new() {
        Ok(gpu) => Some(gpu),
        Err(GpuError::NoAdapter(why)) => {
            if std::env::var("TYNDALL_REQUIRE_GPU").is_ok_and(|v| v == "1") {
                panic!("{test}: no GPU adapter, and TYNDALL_REQUIRE_GPU=1: {why}");
            }
            eprintln!("{test}: SKIPPED, no GPU adapter on this machine ({why})");
            None
        }
        Err(e) => panic!("{test}: {e}"),
    }
}

/// The scene `text` with the side files `files` (name, contents), written
/// to a folder of the test's own (the tests of a file run in parallel
/// threads), loaded and built.
pub fn scene_in_folder(
    test: &str,
    text: &str,
    files: &[(&str, &str)],
) -> (tyndall::SceneDesc, tyndall::Scene) {
    let dir = std::env::temp_dir().join(format!("tyndall-gpu-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for (name, contents) in files {
        std::fs::write(dir.join(name), contents).expect("write a side file");
    }
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).expect("write scene");
    let desc = tyndall_load::load(&path, Default::default()).expect("scene loads");
    let scene = tyndall::Scene::build(&desc).expect("scene builds");
    (desc, scene)
}
