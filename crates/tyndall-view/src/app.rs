//! The window: winit events in, frames out. Each redraw adds one GPU
//! frame to the mean (or shows the CPU render's newest pass), tone-maps
//! it into the softbuffer framebuffer and presents it. An input that
//! changes the scene marks it dirty; the next redraw restarts the
//! accumulation with the change, so the first frame after an input shows
//! it, and the time from the input's arrival to that frame's present is
//! measured and reported. Each redraw first runs the control panel
//! ([`crate::panel`]): events it used (a click or drag on it) do not reach
//! the camera or the keys, the settings its sliders changed are applied
//! before the frame is rendered, and its pixels are drawn over the image.

use crate::accumulator::{Accumulator, FrameTimes};
use crate::controls::LiveScene;
use crate::cpu_preview::{CpuPreview, MAX_SPP, Pass};
use crate::framebuffer::{blit, composite_over, tone_map};
use crate::keys::{Action, action};
use crate::orbit;
use crate::panel::{Panel, Stats};
use anyhow::{Context, Result, anyhow};
use std::num::NonZeroU32;
use std::path::PathBuf;
use std::rc::Rc;
use std::sync::Arc;
use std::time::{Duration, Instant};
use tyndall::{Image, SceneDesc};
use tyndall_denoise::Denoiser;
use winit::application::ApplicationHandler;
use winit::dpi::{PhysicalPosition, PhysicalSize};
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::{Window, WindowId};

/// Frames after which a still view stops accumulating (the mean has
/// converged far below 8-bit display steps).
const MAX_FRAMES: u32 = 1 << 14;

type Surface = softbuffer::Surface<Rc<Window>, Rc<Window>>;

/// What the window shows.
enum Mode {
    Gpu,
    Cpu(CpuPreview),
}

/// Frame rate and times over the last second, printed once a second.
struct Meter {
    since: Instant,
    frames: u32,
    times: FrameTimes,
    /// Tone mapping, copying into the framebuffer and presenting.
    display: Duration,
    fps: f64,
    latency: Option<Duration>,
}

/// The viewer's state between events.
pub struct App {
    live: LiveScene,
    /// The last description the GPU accepted: restored when a change is refused.
    accepted: SceneDesc,
    accumulator: Accumulator,
    mode: Mode,
    window: Option<(Rc<Window>, Surface)>,
    /// The sliders, made with the window.
    panel: Option<Panel>,
    /// When the oldest input the panel took, not yet acted on, arrived.
    panel_input: Option<Instant>,
    /// The image on screen (linear radiance), for re-exposure and `P`.
    shown: Option<Image>,
    /// Scene changed since the last GPU frame.
    dirty: bool,
    /// When the oldest input not yet on screen arrived.
    pending_input: Option<Instant>,
    drag: Option<PhysicalPosition<f64>>,
    cursor: PhysicalPosition<f64>,
    meter: Meter,
    /// The CPU render's newest pass, not yet shown.
    cpu_pass: Option<Result<Pass, String>>,
    /// Samples per pixel of the CPU pass on screen.
    cpu_spp: u32,
    frames: Option<u32>,
    screenshot: Option<PathBuf>,
    /// Denoises the CPU render while it is young, if given.
    denoiser: Option<Arc<Denoiser>>,
    /// An error that ended the event loop.
    pub error: Option<anyhow::Error>,
}

impl App {
    /// The window's state for `live` (uploaded into `accumulator`),
    /// stopping after `frames` frames (or CPU passes) if given, with a
    /// screenshot; starting on the CPU if `cpu`, denoised by `denoiser`.
    pub fn new(
        live: LiveScene,
        frames: Option<u32>,
        screenshot: Option<PathBuf>,
        accumulator: Accumulator,
        cpu: bool,
        denoiser: Option<Arc<Denoiser>>,
    ) -> Self {
        let mut app = Self {
            accepted: live.desc.clone(),
            live,
            accumulator,
            mode: Mode::Gpu,
            window: None,
            panel: None,
            panel_input: None,
            shown: None,
            dirty: false,
            pending_input: None,
            drag: None,
            cursor: PhysicalPosition::new(0.0, 0.0),
            meter: Meter {
                since: Instant::now(),
                frames: 0,
                times: FrameTimes::default(),
                display: Duration::ZERO,
                fps: 0.0,
                latency: None,
            },
            cpu_pass: None,
            cpu_spp: 0,
            frames,
            screenshot,
            denoiser,
            error: None,
        };
        if cpu {
            app.mode = Mode::Cpu(app.start_cpu());
        }
        app
    }

    fn open_window(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let s = &self.live.desc.settings;
        let attributes = Window::default_attributes()
            .with_title("Tyndall")
            .with_inner_size(PhysicalSize::new(s.width, s.height));
        let window = Rc::new(event_loop.create_window(attributes)?);
        let context = softbuffer::Context::new(window.clone())
            .map_err(|e| anyhow!("no framebuffer for the window: {e}"))?;
        let surface = Surface::new(&context, window.clone())
            .map_err(|e| anyhow!("no framebuffer for the window: {e}"))?;
        window.request_redraw();
        self.panel = Some(Panel::new(self.accumulator.gpu(), &window));
        self.window = Some((window, surface));
        Ok(())
    }

    /// A CPU render of the view as it is now, for as many passes as the
    /// view is to last (`--frames`), so that its last screenshot shows
    /// exactly that many — the CPU runs ahead of the window otherwise.
    fn start_cpu(&self) -> CpuPreview {
        let spp = self.frames.unwrap_or(MAX_SPP);
        CpuPreview::start(&self.live.desc, spp, self.denoiser.clone())
    }

    /// Marks the scene changed by an input that arrived at `at`.
    fn changed(&mut self, at: Instant) {
        self.dirty = true;
        self.pending_input.get_or_insert(at);
        if let Mode::Cpu(_) = self.mode {
            self.cpu_pass = None;
            self.cpu_spp = 0;
            self.mode = Mode::Cpu(self.start_cpu());
        }
        self.request_redraw();
    }

    fn request_redraw(&self) {
        if let Some((window, _)) = &self.window {
            window.request_redraw();
        }
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, key: &winit::keyboard::Key, at: Instant) {
        let Some(action) = action(key) else { return };
        match action {
            Action::Quit => event_loop.exit(),
            Action::Fly(step) => {
                let camera = &mut self.live.desc.camera.value;
                let before = *camera;
                orbit::fly(camera, step);
                if !orbit::is_valid(camera) {
                    *camera = before;
                    return;
                }
                self.changed(at);
            }
            Action::Control(control) => match self.live.apply(control) {
                Err(why) => eprintln!("{control:?}: {why}"),
                Ok(()) if control.changes_radiance() => self.changed(at),
                Ok(()) => {
                    // Exposure or the light selection: the same image,
                    // shown again with the new title and exposure.
                    self.pending_input.get_or_insert(at);
                    self.request_redraw();
                }
            },
            Action::SavePng => match self.save_png(None) {
                Ok(path) => eprintln!("saved {}", path.display()),
                Err(e) => eprintln!("error: {e:#}"),
            },
            Action::TogglePanel => {
                if let Some(panel) = &mut self.panel {
                    panel.visible = !panel.visible;
                }
                self.request_redraw();
            }
            Action::ToggleCpu => {
                self.mode = match self.mode {
                    Mode::Gpu => {
                        self.cpu_spp = 0;
                        Mode::Cpu(self.start_cpu())
                    }
                    Mode::Cpu(_) => {
                        self.dirty = true;
                        Mode::Gpu
                    }
                };
                self.request_redraw();
            }
        }
    }

    /// Writes the image on screen with the current exposure (atomically,
    /// as the CLI writes its output) to `path`, or to the first free
    /// `tyndall-view-NNNN.png` in the working directory.
    fn save_png(&self, path: Option<PathBuf>) -> Result<PathBuf> {
        let image = self.shown.as_ref().context("nothing on screen yet")?;
        let path = match path {
            Some(path) => path,
            None => (1..10000)
                .map(|i| PathBuf::from(format!("tyndall-view-{i:04}.png")))
                .find(|p| !p.exists())
                .context("tyndall-view-0001.png to -9999.png all exist")?,
        };
        tyndall_image::write_image(image, &path, self.live.desc.settings.exposure)
            .with_context(|| format!("{}: the screenshot was not written", path.display()))?;
        Ok(path)
    }

    /// Runs the control panel: applies what its sliders changed (through
    /// [`LiveScene::set`], as keys do) before this redraw's frame, so the
    /// change is in it, and returns the panel's pixels to draw over it.
    fn run_panel(&mut self) -> Result<Option<Vec<u8>>> {
        let (Some(panel), Some((window, _))) = (&mut self.panel, &self.window) else {
            return Ok(None);
        };
        let m = &self.meter;
        let stats = Stats {
            fps: m.fps,
            frame_ms: m.times.render.as_secs_f64() * 1e3,
            frames: self.accumulator.frames(),
            latency_ms: m.latency.map(|l| l.as_secs_f64() * 1e3),
        };
        let (outcome, pixels) = panel.frame(self.accumulator.gpu(), window, &self.live, &stats)?;
        let at = self.panel_input.take().unwrap_or_else(Instant::now);
        for setting in outcome.settings {
            match self.live.set(setting) {
                Err(why) => eprintln!("{setting:?}: {why}"),
                Ok(()) if setting.changes_radiance() => self.changed(at),
                Ok(()) => {
                    self.pending_input.get_or_insert(at);
                }
            }
        }
        Ok(pixels)
    }

    /// One redraw: the next GPU frame or the CPU render's newest pass.
    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        let panel = self.run_panel()?;
        match &self.mode {
            Mode::Gpu => {
                if self.dirty {
                    self.dirty = false;
                    match self.accumulator.restart(&self.live.desc) {
                        Ok(()) => self.accepted = self.live.desc.clone(),
                        Err(e) => {
                            eprintln!("refused: {e:#}");
                            self.live.desc = self.accepted.clone();
                        }
                    }
                }
                if self.accumulator.frames() < MAX_FRAMES {
                    let (image, times) = self.accumulator.next_frame()?;
                    self.meter.times = times;
                    self.shown = Some(image);
                }
            }
            Mode::Cpu(_) => match self.cpu_pass.take() {
                Some(Ok(pass)) => {
                    if pass.spp.is_power_of_two() {
                        let how = if pass.denoised { ", denoised" } else { "" };
                        eprintln!("CPU render: {} spp in {:.2} s{how}", pass.spp, pass.seconds);
                    }
                    self.cpu_spp = pass.spp;
                    self.shown = Some(pass.image);
                }
                Some(Err(e)) => {
                    eprintln!("CPU render failed: {e}");
                    self.mode = Mode::Gpu;
                }
                None => {}
            },
        }
        let start = Instant::now();
        self.present(panel.as_deref())?;
        self.meter.display = start.elapsed();
        // A CPU pass of the changed view comes later than the next redraw:
        // latency is measured for GPU frames only.
        let measured = matches!(self.mode, Mode::Gpu);
        if let Some(at) = self.pending_input.take()
            && measured
        {
            let latency = at.elapsed();
            eprintln!(
                "input to frame: {:.1} ms (restart {:.1} ms)",
                latency.as_secs_f64() * 1e3,
                self.accumulator.restart_time.as_secs_f64() * 1e3
            );
            self.meter.latency = Some(latency);
        }
        self.meter.frames += 1;
        self.report();
        let done = match self.mode {
            Mode::Gpu => self.accumulator.frames(),
            Mode::Cpu(_) => self.cpu_spp,
        };
        if let Some(n) = self.frames
            && done >= n
        {
            if let Some(path) = self.screenshot.take() {
                self.save_png(Some(path))?;
            }
            event_loop.exit();
        }
        Ok(())
    }

    /// Tone-maps the image on screen into the framebuffer, draws the
    /// panel's pixels (window-sized, premultiplied RGBA) over it and
    /// presents it.
    fn present(&mut self, panel: Option<&[u8]>) -> Result<()> {
        let (Some((window, surface)), Some(image)) = (&mut self.window, &self.shown) else {
            return Ok(());
        };
        let size = window.inner_size();
        let (Some(w), Some(h)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height)) else {
            return Ok(());
        };
        surface.resize(w, h).map_err(|e| anyhow!("{e}"))?;
        let pixels = tone_map(image, self.live.desc.settings.exposure);
        let mut buffer = surface.buffer_mut().map_err(|e| anyhow!("{e}"))?;
        blit(&pixels, image.width(), &mut buffer, w.get());
        if let Some(panel) = panel
            && panel.len() == buffer.len() * 4
        {
            composite_over(panel, &mut buffer);
        }
        buffer.present().map_err(|e| anyhow!("{e}"))?;
        Ok(())
    }

    /// Updates the title every frame and logs to stderr once a second.
    fn report(&mut self) {
        let m = &mut self.meter;
        let elapsed = m.since.elapsed().as_secs_f64();
        if elapsed >= 1.0 {
            m.fps = m.frames as f64 / elapsed;
            m.frames = 0;
            m.since = Instant::now();
        }
        let mode = match self.mode {
            Mode::Gpu => format!("GPU {} frames", self.accumulator.frames()),
            Mode::Cpu(_) => format!("CPU render {} spp", self.cpu_spp),
        };
        let latency = m.latency.map_or(String::new(), |l| {
            format!(", input→frame {:.0} ms", l.as_secs_f64() * 1e3)
        });
        let line = format!(
            "{:.1} fps, frame {:.1} ms + readback {:.1} ms + display {:.1} ms{latency} | {mode} | {}",
            m.fps,
            m.times.render.as_secs_f64() * 1e3,
            m.times.readback.as_secs_f64() * 1e3,
            m.display.as_secs_f64() * 1e3,
            self.live.summary()
        );
        if m.frames == 0 {
            eprintln!("{line}");
        }
        if let Some((window, _)) = &self.window {
            window.set_title(&format!("Tyndall — {line}"));
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        self.error = Some(e);
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none()
            && let Err(e) = self.open_window(event_loop)
        {
            self.fail(event_loop, e);
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let now = Instant::now();
        if let (Some(panel), Some((window, _))) = (&mut self.panel, &self.window)
            && !matches!(event, WindowEvent::RedrawRequested)
        {
            let used = panel.on_window_event(window, &event);
            let pointer_or_key = matches!(
                event,
                WindowEvent::KeyboardInput { .. }
                    | WindowEvent::MouseInput { .. }
                    | WindowEvent::CursorMoved { .. }
                    | WindowEvent::MouseWheel { .. }
            );
            if pointer_or_key {
                // The panel redraws on hover and clicks, even when the
                // view has converged and nothing else would redraw.
                window.request_redraw();
            }
            if used && pointer_or_key {
                self.panel_input.get_or_insert(now);
                self.drag = None;
                return;
            }
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                let s = &mut self.live.desc.settings;
                if size.width > 0
                    && size.height > 0
                    && (size.width, size.height) != (s.width, s.height)
                {
                    (s.width, s.height) = (size.width, size.height);
                    self.changed(now);
                }
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                self.key(event_loop, &event.logical_key, now)
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.drag = (state == ElementState::Pressed).then_some(self.cursor);
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = position;
                if let Some(from) = self.drag {
                    let camera = &mut self.live.desc.camera.value;
                    orbit::orbit(
                        camera,
                        (position.x - from.x) as f32,
                        (position.y - from.y) as f32,
                    );
                    self.drag = Some(position);
                    self.changed(now);
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                orbit::zoom(&mut self.live.desc.camera.value, notches);
                self.changed(now);
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw(event_loop) {
                    self.fail(event_loop, e);
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        match self.mode {
            Mode::Gpu if self.dirty || self.accumulator.frames() < MAX_FRAMES => {
                event_loop.set_control_flow(ControlFlow::Poll);
                self.request_redraw();
            }
            Mode::Gpu => event_loop.set_control_flow(ControlFlow::Wait),
            Mode::Cpu(ref preview) => {
                // Look for a finished pass 30 times a second; redraw only
                // when one is there.
                if let Some(pass) = preview.latest() {
                    self.cpu_pass = Some(pass);
                    self.request_redraw();
                }
                let next = Instant::now() + Duration::from_millis(33);
                event_loop.set_control_flow(ControlFlow::WaitUntil(next));
            }
        }
    }
}
