//! The control panel: egui sliders over the same [`LiveScene`] the keys
//! change, drawn over the render.
//!
//! [`controls_ui`] lays the panel out and returns the [`Setting`]s the
//! user changed; the window applies them with [`LiveScene::set`], the
//! path every key takes too (a key's step becomes an absolute setting
//! first), so a slider and a key can never disagree on ranges or units.
//!
//! Drawing: the window presents through softbuffer after reading the
//! image back (it needs no Vulkan surface; see docs/viewer.md for the GPU
//! present path that would replace this), so [`Panel`] renders egui with egui-wgpu, on the march's own device,
//! into an offscreen RGBA texture cleared to transparent, reads it back
//! and composites it over the tone-mapped framebuffer on the CPU
//! ([`crate::framebuffer::composite_over`]). Compositing after readback,
//! rather than drawing the panel over a texture of the image on the GPU,
//! keeps the image path unchanged (the running mean is read back and
//! tone-mapped by the PNG writer's function) and keeps the panel out of
//! the image that `P` and `--screenshot` save: screenshots are of the
//! render alone.

use crate::controls::{
    LiveScene, MAX_ASYMMETRY, MAX_FOG_DENSITY, MAX_STEP, MIN_FOG_DENSITY, MIN_STEP,
    NEW_FOG_DENSITY, Setting, asymmetry, cutoff_range, direction, direction_angles,
    direction_from_angles, emission,
};
use anyhow::{Result, anyhow};
use tyndall::IntegratorKind;
use tyndall::description::LightDesc;
use tyndall::glass::GlassModel;
use tyndall_gpu::Gpu;
use winit::window::Window;

/// The texture format egui draws into: 8-bit RGBA without sRGB encoding,
/// so egui writes gamma-space (sRGB-encoded) colours, as the framebuffer
/// holds them.
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// Range of the exposure slider, in stops.
const EXPOSURE_SLIDER_STOPS: f32 = 10.0;
/// Range of the intensity sliders (the largest channel, W/sr or W/m²).
const EMISSION_SLIDER: std::ops::RangeInclusive<f32> = 1e-3..=1e7;

/// What the panel shows besides the controls.
#[derive(Clone, Copy, Debug, Default)]
pub struct Stats {
    pub fps: f64,
    /// Render time of the last frame (ms).
    pub frame_ms: f64,
    /// Frames in the mean on screen.
    pub frames: u32,
    /// Time from the last input to its frame (ms).
    pub latency_ms: Option<f64>,
}

/// What one pass of the panel asked for.
#[derive(Debug, Default)]
pub struct Outcome {
    /// The settings changed, in the order of the widgets.
    pub settings: Vec<Setting>,
    /// Each slider's label and screen rectangle (points), as laid out.
    pub sliders: Vec<(String, egui::Rect)>,
}

/// A slider over `value` in `range`; a change is recorded as `setting(v)`.
fn slider(
    ui: &mut egui::Ui,
    outcome: &mut Outcome,
    label: &str,
    mut value: f32,
    range: std::ops::RangeInclusive<f32>,
    logarithmic: bool,
    setting: impl FnOnce(f32) -> Setting,
) {
    let response = ui.add(
        egui::Slider::new(&mut value, range)
            .text(label)
            .logarithmic(logarithmic),
    );
    outcome.sliders.push((label.to_string(), response.rect));
    if response.changed() {
        outcome.settings.push(setting(value));
    }
}

/// Lays out the panel for `live` (its values as they are now) and
/// returns what the user changed.
pub fn controls_ui(ctx: &egui::Context, live: &LiveScene, stats: &Stats) -> Outcome {
    let mut outcome = Outcome::default();
    egui::Window::new("Controls (H hides)")
        .default_pos([8.0, 8.0])
        .default_open(true)
        .show(ctx, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                ui.label(format!(
                    "{:.1} fps, frame {:.1} ms, {} frames",
                    stats.fps, stats.frame_ms, stats.frames
                ));
                // Always a line, so the sliders below do not move when
                // the first latency arrives.
                ui.label(match stats.latency_ms {
                    Some(ms) => format!("input → frame {ms:.0} ms"),
                    None => "input → frame: no input yet".to_string(),
                });
                fog_controls(ui, &mut outcome, live);
                let desc = &live.desc;
                slider(
                    ui,
                    &mut outcome,
                    "march step",
                    desc.settings.step,
                    MIN_STEP..=MAX_STEP,
                    true,
                    Setting::Step,
                );
                slider(
                    ui,
                    &mut outcome,
                    "exposure (stops)",
                    desc.settings.exposure,
                    -EXPOSURE_SLIDER_STOPS..=EXPOSURE_SLIDER_STOPS,
                    false,
                    Setting::Exposure,
                );
                ui.horizontal(|ui| {
                    ui.label("glass");
                    for (model, name) in
                        [(GlassModel::Filter, "filter"), (GlassModel::Blend, "blend")]
                    {
                        if ui.radio(desc.glass.model == model, name).clicked()
                            && desc.glass.model != model
                        {
                            outcome.settings.push(Setting::GlassModel(model));
                        }
                    }
                });
                ui.horizontal(|ui| {
                    ui.label("in-scattering");
                    for (kind, name) in [
                        (IntegratorKind::March, "march"),
                        (IntegratorKind::Single, "single (equiangular)"),
                    ] {
                        let now = desc.settings.integrator;
                        if ui.radio(now == kind, name).clicked() && now != kind {
                            outcome.settings.push(Setting::Estimator(kind));
                        }
                    }
                });
                for (light, l) in desc.lights.iter().enumerate() {
                    light_controls(ui, &mut outcome, light, &l.value);
                }
            });
        });
    outcome
}

fn fog_controls(ui: &mut egui::Ui, outcome: &mut Outcome, live: &LiveScene) {
    let Some(fog) = live.desc.fog.as_ref().map(|f| f.value) else {
        if ui.button("add fog").clicked() {
            outcome.settings.push(Setting::Density(NEW_FOG_DENSITY));
        }
        return;
    };
    slider(
        ui,
        outcome,
        "fog density σt",
        fog.sigma_t,
        MIN_FOG_DENSITY..=MAX_FOG_DENSITY,
        true,
        Setting::Density,
    );
    // The albedo's largest channel; moving it scales all three (keeps the
    // colour).
    let albedo = fog.albedo;
    slider(
        ui,
        outcome,
        "fog albedo",
        albedo.max_element(),
        0.0..=1.0,
        false,
        move |v| {
            let largest = albedo.max_element();
            Setting::Albedo(if largest > 0.0 {
                albedo * (v / largest)
            } else {
                tyndall::Rgb::splat(v)
            })
        },
    );
    slider(
        ui,
        outcome,
        "HG asymmetry g",
        asymmetry(&fog.phase),
        -MAX_ASYMMETRY..=MAX_ASYMMETRY,
        false,
        Setting::Asymmetry,
    );
}

fn light_controls(ui: &mut egui::Ui, outcome: &mut Outcome, light: usize, l: &LightDesc) {
    let kind = match l {
        LightDesc::Point(_) => "point",
        LightDesc::Spot(_) => "spot",
        LightDesc::Directional(_) => "sun",
        LightDesc::Environment(_) => "environment",
    };
    ui.separator();
    ui.label(format!("light {} ({kind})", light + 1));
    let e = emission(l);
    slider(
        ui,
        outcome,
        &format!("light {} intensity", light + 1),
        e.max_element(),
        EMISSION_SLIDER,
        true,
        move |v| {
            let largest = e.max_element();
            Setting::Intensity {
                light,
                emission: if largest > 0.0 {
                    e * (v / largest)
                } else {
                    tyndall::Rgb::splat(v)
                },
            }
        },
    );
    if let LightDesc::Spot(s) = l {
        let (min, max) = cutoff_range(&s.profile);
        slider(
            ui,
            outcome,
            &format!("light {} cutoff (°)", light + 1),
            s.cos_cutoff.clamp(-1.0, 1.0).acos().to_degrees(),
            min..=max,
            false,
            move |degrees| Setting::Cutoff { light, degrees },
        );
    }
    if let Ok(d) = direction(l) {
        let (azimuth, elevation) = direction_angles(d);
        slider(
            ui,
            outcome,
            &format!("light {} azimuth (°)", light + 1),
            azimuth,
            -180.0..=180.0,
            false,
            move |a| Setting::Direction {
                light,
                direction: direction_from_angles(a, elevation),
            },
        );
        slider(
            ui,
            outcome,
            &format!("light {} elevation (°)", light + 1),
            elevation,
            -90.0..=90.0,
            false,
            move |e| Setting::Direction {
                light,
                direction: direction_from_angles(azimuth, e),
            },
        );
    }
}

/// The offscreen texture egui draws into and the buffer it is copied to.
struct Target {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    copy: wgpu::Buffer,
    width: u32,
    height: u32,
    /// Bytes per row of `copy` (padded to wgpu's copy alignment).
    row_bytes: u32,
}

/// The panel's egui state and its renderer on the march's device.
pub struct Panel {
    ctx: egui::Context,
    state: egui_winit::State,
    renderer: egui_wgpu::Renderer,
    target: Option<Target>,
    /// Shown over the render (`H` toggles).
    pub visible: bool,
}

impl Panel {
    pub fn new(gpu: &Gpu, window: &Window) -> Self {
        let ctx = egui::Context::default();
        let state = egui_winit::State::new(
            ctx.clone(),
            egui::ViewportId::ROOT,
            window,
            Some(window.scale_factor() as f32),
            None,
            Some(gpu.device.limits().max_texture_dimension_2d as usize),
        );
        let renderer = egui_wgpu::Renderer::new(
            &gpu.device,
            FORMAT,
            egui_wgpu::RendererOptions {
                dithering: false,
                ..Default::default()
            },
        );
        Self {
            ctx,
            state,
            renderer,
            target: None,
            visible: true,
        }
    }

    /// Gives `event` to egui; true when egui used it (a click or drag on
    /// the panel), so the view must not act on it too.
    pub fn on_window_event(&mut self, window: &Window, event: &winit::event::WindowEvent) -> bool {
        if !self.visible {
            return false;
        }
        self.state.on_window_event(window, event).consumed
    }

    /// Whether the pointer is over the panel or a slider is held.
    pub fn wants_pointer(&self) -> bool {
        self.visible && self.ctx.egui_wants_pointer_input()
    }

    /// Runs the panel for this frame and draws it: what the user changed
    /// and the panel's premultiplied RGBA pixels (window size, row-major),
    /// or nothing when the panel is hidden.
    pub fn frame(
        &mut self,
        gpu: &Gpu,
        window: &Window,
        live: &LiveScene,
        stats: &Stats,
    ) -> Result<(Outcome, Option<Vec<u8>>)> {
        if !self.visible {
            return Ok((Outcome::default(), None));
        }
        let input = self.state.take_egui_input(window);
        let mut outcome = Outcome::default();
        let output = self.ctx.run_ui(input, |ui| {
            outcome = controls_ui(ui.ctx(), live, stats);
        });
        self.state
            .handle_platform_output(window, output.platform_output.clone());
        let size = window.inner_size();
        let pixels = self.draw(gpu, output, size.width, size.height)?;
        Ok((outcome, pixels))
    }

    /// Draws `output` into the offscreen texture and reads it back.
    fn draw(
        &mut self,
        gpu: &Gpu,
        output: egui::FullOutput,
        width: u32,
        height: u32,
    ) -> Result<Option<Vec<u8>>> {
        if width == 0 || height == 0 {
            return Ok(None);
        }
        let target = match self.target.take() {
            Some(t) if (t.width, t.height) == (width, height) => t,
            _ => new_target(gpu, width, height),
        };
        for (id, deltas) in &output.textures_delta.set {
            for delta in deltas {
                self.renderer
                    .update_texture(&gpu.device, &gpu.queue, *id, delta);
            }
        }
        let jobs = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [width, height],
            pixels_per_point: output.pixels_per_point,
        };
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let extra =
            self.renderer
                .update_buffers(&gpu.device, &gpu.queue, &mut encoder, &jobs, &screen);
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("panel"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &target.view,
                    resolve_target: None,
                    depth_slice: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                ..Default::default()
            });
            self.renderer
                .render(&mut pass.forget_lifetime(), &jobs, &screen);
        }
        encoder.copy_texture_to_buffer(
            target.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &target.copy,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(target.row_bytes),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
        );
        gpu.queue
            .submit(extra.into_iter().chain([encoder.finish()]));
        for id in &output.textures_delta.free {
            self.renderer.free_texture(id);
        }
        let bytes = tyndall_gpu::readback::read_buffer(
            gpu,
            &target.copy,
            target.row_bytes as u64 * height as u64,
        )
        .map_err(|e| anyhow!("the control panel: {e}"))?;
        let row = width as usize * 4;
        let pixels = bytes
            .chunks_exact(target.row_bytes as usize)
            .flat_map(|r| &r[..row])
            .copied()
            .collect();
        self.target = Some(target);
        Ok(Some(pixels))
    }
}

fn new_target(gpu: &Gpu, width: u32, height: u32) -> Target {
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("panel"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    let row_bytes = (width * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let copy = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("panel copy"),
        size: row_bytes as u64 * height as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    Target {
        texture,
        view,
        copy,
        width,
        height,
        row_bytes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One pass of the panel with `events`, at 1024×768 points.
    fn pass(ctx: &egui::Context, live: &LiveScene, events: Vec<egui::Event>) -> Outcome {
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(1024.0, 768.0),
            )),
            events,
            ..Default::default()
        };
        let mut outcome = Outcome::default();
        let _ = ctx.run_ui(input, |ui| {
            outcome = controls_ui(ui.ctx(), live, &Stats::default());
        });
        outcome
    }

    fn press(pos: egui::Pos2, pressed: bool) -> egui::Event {
        egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Default::default(),
        }
    }

    /// Drags the slider labelled `label` by `dx` points; returns the
    /// settings the panel asked for.
    fn drag(live: &LiveScene, label: &str, dx: f32) -> Vec<Setting> {
        let ctx = egui::Context::default();
        // Two passes to settle the layout (egui sizes windows on the first).
        pass(&ctx, live, Vec::new());
        let laid_out = pass(&ctx, live, Vec::new());
        let (_, rect) = laid_out
            .sliders
            .iter()
            .find(|(l, _)| l == label)
            .unwrap_or_else(|| panic!("no slider `{label}` in {:?}", laid_out.sliders));
        // The slider's rail is on its left; its value text on the right.
        let from = egui::pos2(
            rect.left() + 0.25 * rect.width().min(100.0),
            rect.center().y,
        );
        let to = from + egui::vec2(dx, 0.0);
        let mut settings = Vec::new();
        for events in [
            vec![egui::Event::PointerMoved(from)],
            vec![press(from, true)],
            vec![egui::Event::PointerMoved(to)],
            vec![press(to, false)],
        ] {
            settings.extend(pass(&ctx, live, events).settings);
        }
        settings
    }

    /// A pointer drag on the fog-density slider changes σt in the scene
    /// the renderer builds, through the same `LiveScene::set` the keys
    /// use; dragging right raises it, left lowers it.
    #[test]
    fn dragging_the_density_slider_changes_the_rendered_scene() {
        let demo = tyndall_load::demo::load().expect("demo");
        let sigma = |live: &LiveScene| {
            crate::accumulator::build_scene(&live.desc)
                .expect("scene")
                .fog()
                .expect("fog")
                .sigma_t
        };
        for (dx, raises) in [(40.0, true), (-40.0, false)] {
            let mut live = LiveScene::new(demo.clone());
            let before = sigma(&live);
            let settings = drag(&live, "fog density σt", dx);
            assert!(!settings.is_empty(), "the drag changed nothing");
            for s in settings {
                assert!(matches!(s, Setting::Density(_)), "{s:?}");
                live.set(s).expect("set");
            }
            let after = sigma(&live);
            assert_eq!(after > before, raises, "σt {before} → {after} for dx {dx}");
            assert_ne!(after, before);
        }
    }

    /// A drag on a light's azimuth slider turns that light (and only it).
    #[test]
    fn dragging_a_light_slider_turns_that_light() {
        let demo = tyndall_load::demo::load().expect("demo");
        let mut live = LiveScene::new(demo.clone());
        let settings = drag(&live, "light 1 azimuth (°)", 30.0);
        assert!(!settings.is_empty(), "the drag changed nothing");
        for s in settings {
            live.set(s).expect("set");
        }
        let d = |desc: &tyndall::SceneDesc| direction(&desc.lights[0].value).expect("spot");
        let turned = d(&live.desc).angle_between(d(&demo));
        assert!(turned > 1f32.to_radians(), "turned {turned} rad");
        assert_eq!(
            format!("{:?}", live.desc.lights[1].value),
            format!("{:?}", demo.lights[1].value)
        );
    }
}
