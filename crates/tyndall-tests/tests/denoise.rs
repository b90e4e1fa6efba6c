//! Denoising with Open Image Denoise (issue 24) against the references of
//! independent renderers: at 4 samples per pixel, the denoised image is
//! closer to the Mitsuba 3 reference than the raw one on every shared
//! reference scene (scenes/reference/, REFERENCE-README.md).
//!
//! Skipped, with a message, where OIDN is not installed; where
//! `TYNDALL_OIDN` names it (as `.ci/run` does) a library that fails to
//! load fails the test instead.

mod common;

use common::repo;
use tyndall_denoise::{DenoiseGuides, Denoiser};
use tyndall_image::metrics::relative_mse;

fn denoiser() -> Option<Denoiser> {
    match Denoiser::find() {
        Ok(d) => Some(d),
        Err(e) if std::env::var_os(tyndall_denoise::LIBRARY_VARIABLE).is_some() => {
            panic!("{e}")
        }
        Err(e) => {
            eprintln!("skipped: {e}");
            None
        }
    }
}

/// The shared references (../shared/reference, copied to
/// scenes/reference/): single scattering under a spot, and multiple
/// scattering and interreflection in a box and a fog-filled room. Each
/// renders with its own settings (integrator, depth) at 4 spp.
#[test]
fn denoising_reduces_the_error_against_every_reference() {
    let Some(denoiser) = denoiser() else { return };
    let dir = repo().join("scenes/reference");
    for name in [
        "fog-spot-empty",
        "fog-spot-sphere",
        "fog-spot-glass-pair",
        "cornell-surfaces",
        "cornell-surfaces-depth3",
        "fog-room-multi",
        "fog-room-depth2",
    ] {
        let desc = common::load_native(&dir.join(format!("{name}.toml"))).expect("scene");
        let reference =
            tyndall_image::read_exr(&dir.join(format!("{name}.exr"))).expect("reference");
        let settings = tyndall::RenderSettings {
            spp: 4,
            seed: 1,
            guides: true,
            ..desc.settings
        };
        let sums = common::accumulate(&desc, &settings);
        let raw = sums.resolve();
        let guides = sums.resolve_guides().expect("guides");
        let denoised = denoiser
            .denoise(
                &raw,
                Some(DenoiseGuides {
                    albedo: &guides.albedo,
                    normal: &guides.normal,
                    prefilter: true,
                }),
            )
            .expect("denoise");
        let (before, after) = (
            relative_mse(&raw, &reference),
            relative_mse(&denoised, &reference),
        );
        eprintln!("{name}: relMSE {before:.3e} raw, {after:.3e} denoised");
        assert!(
            after < before,
            "{name}: denoising raised relMSE from {before:.3e} to {after:.3e}"
        );
    }
}
