//! What the GPU tests share: opening the device, or skipping.

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
