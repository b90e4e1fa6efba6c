//! The GPU march's interleaving tile sharing out the lattice (each pixel
//! evaluates the cells k ≡ r (mod n²) of its march per frame) and the
//! discontinuity-buffer filter that puts a young image's cells back
//! together (`GpuMarch::display_image`). That the shared-out march
//! converges to the CPU march pixel by pixel is `tests/images.rs`'s
//! `fig07_interleaved_long_step_matches_cpu_march`; here, what one
//! displayed frame is worth.
//!
//! The claim behind "a 4×4 tile makes a 64-step march cost 4 steps a
//! pixel": one filtered frame, whose window holds the 16 pixels that
//! between them evaluate every cell once, is about as close to the
//! converged image as one frame of the full march that evaluates all 64
//! cells in every pixel. The in-scattered noise of one pixel's shared-out
//! estimate is that of a march with 16 times the step; averaging 16
//! pixels with independent cells and jitters divides its variance by up
//! to 16 (fewer where the depth test rejects neighbours), which brings
//! it to the full march's order; the filter adds blur across the window,
//! a bias that the converged image does not have. So the test asks the
//! filtered frame's relMSE against the converged image to be (a) below a
//! quarter of the unfiltered frame's — a filter that averaged nothing,
//! or averaged the wrong pixels' residues, gets nowhere near — and (b)
//! below twice the full march frame's, the allowance for blur.

mod support;

use std::path::Path;
use tyndall::{Image, IntegratorKind, Scene, SceneDesc};
use tyndall_gpu::{GpuMarch, MarchSettings};
use tyndall_image::metrics::pixel_errors;

const WIDTH: u32 = 96;
const HEIGHT: u32 = 72;
const TILE: u32 = 4;

fn relative_mse(candidate: &Image, reference: &Image) -> f64 {
    let errors = pixel_errors(candidate, reference);
    errors.iter().sum::<f64>() / errors.len() as f64
}

fn fig07() -> SceneDesc {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/fig07-spot-sphere.toml");
    let mut desc = tyndall_load::load(&path, Default::default()).expect("fig. 7 loads");
    desc.settings.width = WIDTH;
    desc.settings.height = HEIGHT;
    desc.settings.integrator = IntegratorKind::March;
    desc
}

fn settings(desc: &SceneDesc, interleave: u32, seed: u64) -> MarchSettings {
    MarchSettings {
        interleave,
        seed,
        ..MarchSettings::from(&desc.settings)
    }
}

#[test]
fn one_filtered_frame_is_worth_a_full_march_frame() {
    let Some(gpu) = support::gpu_or_skip("interleave filter") else {
        return;
    };
    let desc = fig07();
    let scene = Scene::build(&desc).expect("scene");
    // The converged image: (n²)² frames of the shared-out march, after
    // which the display is the unfiltered mean.
    let mut converged = GpuMarch::new(&gpu, &scene, &settings(&desc, TILE, 1)).expect("march");
    converged.submit_frames(&gpu, TILE.pow(4));
    converged.wait(&gpu).expect("wait");
    assert!(!converged.display_filters());
    let reference = converged.image(&gpu).expect("image");
    assert_eq!(
        converged.display_image(&gpu).expect("display"),
        reference,
        "past (n²)² frames the display is the mean itself"
    );

    let mut shared = GpuMarch::new(&gpu, &scene, &settings(&desc, TILE, 2)).expect("march");
    shared.submit_frames(&gpu, 1);
    shared.wait(&gpu).expect("wait");
    assert!(shared.display_filters());
    let filtered = relative_mse(&shared.display_image(&gpu).expect("display"), &reference);
    let unfiltered = relative_mse(&shared.image(&gpu).expect("image"), &reference);

    let mut full = GpuMarch::new(&gpu, &scene, &settings(&desc, 1, 3)).expect("march");
    assert!(!full.display_filters(), "nothing to filter without a tile");
    full.submit_frames(&gpu, 1);
    full.wait(&gpu).expect("wait");
    let full_frame = relative_mse(&full.image(&gpu).expect("image"), &reference);
    eprintln!(
        "one frame against the converged image: filtered {filtered:.3e}, unfiltered {unfiltered:.3e}, full march {full_frame:.3e}"
    );
    assert!(
        filtered < unfiltered / 4.0,
        "the filter should cut a shared-out frame's error by 4 or more: {filtered:.3e} against {unfiltered:.3e}"
    );
    assert!(
        filtered < 2.0 * full_frame,
        "a filtered frame should be about as good as a full march frame: {filtered:.3e} against {full_frame:.3e}"
    );
}
