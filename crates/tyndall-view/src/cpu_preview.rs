//! The progressive CPU render (`R`, `tyndall view --cpu`, and the default
//! where the only GPU is a software one): the render loop of the CLI
//! (`tyndall::render::render_region`) on a background thread, one sample
//! per pixel per pass, each pass's running mean shown — so after N passes
//! the view is exactly `tyndall render --spp N` of the same view, but for
//! minified textures: the view filters them over whole pixels at every
//! pass (`RenderSettings::footprint_spp` 1: no shimmer at one sample), a
//! render over `max(1/8, 1/√N)` of a pixel. With a
//! denoiser, the image is denoised (Open Image Denoise, with the
//! first-surface guides, not prefiltered) at passes 1, 2, 4, …, 64 and
//! then every 32nd, and only the denoised images are shown. A view change or leaving CPU
//! mode abandons the render: the thread stops after the pass it is in.

use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::thread::JoinHandle;
use tyndall::region::RenderRegion;
use tyndall::render::Accumulation;
use tyndall::{Image, SceneDesc};
use tyndall_denoise::{DenoiseGuides, Denoiser};

/// Most samples per pixel the preview accumulates, unless told fewer.
pub const MAX_SPP: u32 = 1 << 16;

/// Up to this many samples per pixel every power of two is denoised;
/// after it, every [`DENOISE_EVERY`]th pass.
const YOUNG_SPP: u32 = 64;
const DENOISE_EVERY: u32 = 32;

/// A finished pass.
pub struct Pass {
    pub spp: u32,
    pub image: Image,
    /// Since the render started.
    pub seconds: f64,
    pub denoised: bool,
}

/// A running progressive CPU render.
pub struct CpuPreview {
    passes: Receiver<Result<Pass, String>>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

/// Whether pass `n` (1-based) of `last` is denoised and shown, with a
/// denoiser: the last one always is.
fn denoised_at(n: u32, last: u32) -> bool {
    if n == last {
        true
    } else if n <= YOUNG_SPP {
        n.is_power_of_two()
    } else {
        n.is_multiple_of(DENOISE_EVERY)
    }
}

impl CpuPreview {
    /// Starts rendering `desc` (its camera, fog, lights and settings)
    /// with the integrator the GPU view shows (`march` or `single`), its
    /// CPU twin, for `spp` passes (at most [`MAX_SPP`]); denoised by
    /// `denoiser` if given. The last pass is always sent, so a view that
    /// stops after N passes shows exactly N.
    pub fn start(desc: &SceneDesc, spp: u32, denoiser: Option<Arc<Denoiser>>) -> Self {
        let spp = spp.clamp(1, MAX_SPP);
        let desc = desc.clone();
        let (send, passes) = channel();
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = stop.clone();
        let thread = std::thread::spawn(move || {
            let scene = match crate::accumulator::build_scene(&desc) {
                Ok(scene) => scene,
                Err(e) => {
                    let _ = send.send(Err(format!("{e:#}")));
                    return;
                }
            };
            // Every pass is looked at, the first ones too: textures are
            // filtered over whole pixels, as for a one-sample image, so
            // that they do not shimmer while the view is young.
            let settings = tyndall::RenderSettings {
                spp,
                guides: denoiser.is_some(),
                footprint_spp: Some(1),
                ..desc.settings
            };
            let region = RenderRegion::full(settings.width, settings.height, spp);
            let start = std::time::Instant::now();
            let mut after_pass = |sums: &Accumulation, _| {
                if stopped.load(Ordering::Relaxed) {
                    return ControlFlow::Break(());
                }
                let n = sums.passes();
                let pass = match &denoiser {
                    None => Ok((sums.resolve(), false)),
                    Some(_) if !denoised_at(n, spp) => return ControlFlow::Continue(()),
                    Some(denoiser) => denoise(denoiser, sums).map(|image| (image, true)),
                };
                let pass = pass.map(|(image, denoised)| Pass {
                    spp: n,
                    image,
                    seconds: start.elapsed().as_secs_f64(),
                    denoised,
                });
                let failed = pass.is_err();
                // The viewer gone or moved on: nobody needs the passes.
                if send.send(pass).is_err() || failed {
                    return ControlFlow::Break(());
                }
                ControlFlow::Continue(())
            };
            let rendered = tyndall::render::render_region(
                &scene,
                &settings,
                &region,
                None,
                &|_| {},
                &mut after_pass,
            );
            if let Err(e) = rendered {
                let _ = send.send(Err(e.to_string()));
            }
        });
        Self {
            passes,
            stop,
            thread: Some(thread),
        }
    }

    /// The newest finished pass, if one finished since the last call.
    pub fn latest(&self) -> Option<Result<Pass, String>> {
        let mut newest = None;
        loop {
            match self.passes.try_recv() {
                Ok(pass) => newest = Some(pass),
                Err(TryRecvError::Empty | TryRecvError::Disconnected) => return newest,
            }
        }
    }
}

/// The running mean of `sums`, denoised with its guides.
fn denoise(denoiser: &Denoiser, sums: &Accumulation) -> Result<Image, String> {
    let image = sums.resolve();
    let guides = sums.resolve_guides().ok_or("the render kept no guides")?;
    let guides = DenoiseGuides {
        albedo: &guides.albedo,
        normal: &guides.normal,
        // A third of the time, as good on the reference scenes
        // (docs/benchmarks.md): a live view wants the image sooner.
        prefilter: false,
    };
    denoiser
        .denoise(&image, Some(guides))
        .map_err(|e| format!("denoising failed: {e}"))
}

impl Drop for CpuPreview {
    /// Asks the thread to stop after its pass, without waiting for it:
    /// the window stays responsive while a long pass finishes.
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        drop(self.thread.take());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn young_views_are_denoised_at_powers_of_two_then_every_32nd_pass() {
        let shown: Vec<u32> = (1..=160).filter(|&n| denoised_at(n, MAX_SPP)).collect();
        assert_eq!(shown, [1, 2, 4, 8, 16, 32, 64, 96, 128, 160]);
        let shown: Vec<u32> = (1..=5).filter(|&n| denoised_at(n, 5)).collect();
        assert_eq!(shown, [1, 2, 4, 5]);
    }
}
