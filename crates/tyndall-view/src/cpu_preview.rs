//! The progressive CPU render (`R`): `tyndall::render` of the same view
//! on a background thread, 1, 2, 4, … samples per pixel, each pass a whole
//! render shown when it finishes. A view change or leaving CPU mode
//! abandons it: the thread stops after the pass it is in.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::thread::JoinHandle;
use tyndall::{Image, SceneDesc};

/// Most samples per pixel the preview doubles up to.
const MAX_SPP: u32 = 1 << 16;

/// A finished pass.
pub struct Pass {
    pub spp: u32,
    pub image: Image,
    pub seconds: f64,
}

/// A running progressive CPU render.
pub struct CpuPreview {
    passes: Receiver<Result<Pass, String>>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl CpuPreview {
    /// Starts rendering `desc` (its camera, fog, lights and settings)
    /// with the integrator the GPU view shows (`march` or `single`), its
    /// CPU twin.
    pub fn start(desc: &SceneDesc) -> Self {
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
            let mut spp = 1;
            while spp <= MAX_SPP && !stopped.load(Ordering::Relaxed) {
                let mut settings = desc.settings;
                settings.spp = spp;
                let start = std::time::Instant::now();
                let pass = tyndall::render(&scene, &settings, &|_| {})
                    .map(|r| Pass {
                        spp,
                        image: r.image,
                        seconds: start.elapsed().as_secs_f64(),
                    })
                    .map_err(|e| e.to_string());
                let failed = pass.is_err();
                // The viewer gone or moved on: nobody needs the pass.
                if send.send(pass).is_err() || failed {
                    return;
                }
                spp *= 2;
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

impl Drop for CpuPreview {
    /// Asks the thread to stop after its pass, without waiting for it:
    /// the window stays responsive while a long pass finishes.
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        drop(self.thread.take());
    }
}
