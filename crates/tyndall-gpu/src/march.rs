//! The GPU ray march: the scene uploaded once, then frames dispatched and
//! summed per pixel on the GPU, each frame with its own film jitter and
//! march jitter (inside the pixel's interleaving stratum, as on the CPU),
//! so the mean converges to the CPU `march` image.

use crate::device::{Gpu, GpuError, compute_pipeline};
use crate::readback::read_buffer;
use crate::scene_buffers::{GpuLight, GpuMaterial, GpuPrimitive, SceneBuffers};
use crate::shaders;
use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};
use tyndall::camera::{CameraSpec, FieldOfView};
use tyndall::glass::GlassModel;
use tyndall::settings::MAX_MARCH_STEPS;
use tyndall::{Image, Rgb, Scene};
use wgpu::util::DeviceExt;

/// The march's parameters: those of the CPU `march` the GPU honours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarchSettings {
    pub width: u32,
    pub height: u32,
    /// Step length `h` between lattice points (scene units).
    pub step: f32,
    /// Interleaving tile size `n` (1: none).
    pub interleave: u32,
    /// Most reflective-layer bounces a camera path follows.
    pub max_bounces: u32,
    pub seed: u64,
}

/// The uniform block of `march.wgsl` (`Params`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct Params {
    camera_position: [f32; 4],
    camera_forward: [f32; 4],
    camera_right: [f32; 4],
    camera_up: [f32; 4],
    half_extent_resolution: [f32; 4],
    fog_albedo_sigma_t: [f32; 4],
    fog_min: [f32; 4],
    fog_max: [f32; 4],
    background_g: [f32; 4],
    step: f32,
    interleave: u32,
    seed: u32,
    frame: u32,
    primitive_count: u32,
    light_count: u32,
    glass_model: u32,
    opaque_to_camera: u32,
    max_bounces: u32,
    step_budget: u32,
    pad: [u32; 2],
}

fn v4(v: Vec3, w: f32) -> [f32; 4] {
    [v.x, v.y, v.z, w]
}

/// The camera frame of `tyndall::camera::Camera::new`: forward, right, up
/// and the image plane's half-extent at distance 1.
fn camera_frame(spec: &CameraSpec, width: u32, height: u32) -> (Vec3, Vec3, Vec3, Vec2) {
    let forward = (spec.look_at - spec.position).normalize();
    let right = forward.cross(spec.up).normalize();
    let up = right.cross(forward);
    let aspect = width as f32 / height as f32;
    let tan_y = match spec.fov {
        FieldOfView::Vertical(deg) => (0.5 * deg.to_radians()).tan(),
        FieldOfView::ShorterSide(deg) => {
            let t = (0.5 * deg.to_radians()).tan();
            if aspect >= 1.0 { t } else { t / aspect }
        }
    };
    (forward, right, up, Vec2::new(tan_y * aspect, tan_y))
}

/// A scene on the GPU with its running per-pixel sums.
pub struct GpuMarch {
    params: Params,
    params_buffer: wgpu::Buffer,
    accumulation: wgpu::Buffer,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    frames: u32,
}

/// A storage buffer holding `items`, or one zeroed item for an empty list
/// (WGSL arrays cannot be empty; the counts in `Params` say what is used).
fn storage<T: Pod + Default>(gpu: &Gpu, label: &str, items: &[T]) -> wgpu::Buffer {
    let one = [T::default()];
    let items = if items.is_empty() { &one[..] } else { items };
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(items),
            usage: wgpu::BufferUsages::STORAGE,
        })
}

impl GpuMarch {
    /// Uploads `scene` and prepares an empty accumulation of
    /// `settings.width × settings.height` pixels.
    pub fn new(gpu: &Gpu, scene: &Scene, settings: &MarchSettings) -> Result<Self, GpuError> {
        let buffers = SceneBuffers::new(scene)?;
        if !(settings.step > 0.0 && settings.step.is_finite()) {
            return Err(GpuError::Unsupported(format!(
                "march step {} (must be positive and finite)",
                settings.step
            )));
        }
        let (forward, right, up, half_extent) =
            camera_frame(scene.camera(), settings.width, settings.height);
        let glass = scene.glass();
        let mut params = Params {
            camera_position: v4(scene.camera().position, 0.0),
            camera_forward: v4(forward, 0.0),
            camera_right: v4(right, 0.0),
            camera_up: v4(up, 0.0),
            half_extent_resolution: [
                half_extent.x,
                half_extent.y,
                settings.width as f32,
                settings.height as f32,
            ],
            background_g: v4(scene.background(), 0.0),
            step: settings.step,
            interleave: settings.interleave.max(1),
            seed: (settings.seed ^ (settings.seed >> 32)) as u32,
            primitive_count: buffers.primitives.len() as u32,
            light_count: buffers.lights.len() as u32,
            glass_model: match glass.model {
                GlassModel::Filter => 0,
                GlassModel::Blend => 1,
            },
            opaque_to_camera: glass.opaque_to_camera as u32,
            max_bounces: settings.max_bounces,
            // The CPU march's cap: MAX_MARCH_STEPS over the lights.
            step_budget: (MAX_MARCH_STEPS / buffers.lights.len().max(1) as u64)
                .min(u32::MAX as u64) as u32,
            ..Default::default()
        };
        if let Some(fog) = scene.fog() {
            let g = match fog.phase {
                tyndall::phase::PhaseFunction::Isotropic => 0.0,
                tyndall::phase::PhaseFunction::HenyeyGreenstein { g } => g,
            };
            params.fog_albedo_sigma_t = v4(fog.albedo, fog.sigma_t);
            params.background_g[3] = g;
            let (min, max, bounded) = fog
                .bounds
                .map_or((Vec3::ZERO, Vec3::ZERO, 0.0), |b| (b.min, b.max, 1.0));
            params.fog_min = v4(min, 1.0);
            params.fog_max = v4(max, bounded);
        }
        let device = &gpu.device;
        let pipeline = compute_pipeline(gpu, "march", &shaders::march(), "march_frame")?;
        let params_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("march params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let primitives = storage::<GpuPrimitive>(gpu, "primitives", &buffers.primitives);
        let materials = storage::<GpuMaterial>(gpu, "materials", &buffers.materials);
        let lights = storage::<GpuLight>(gpu, "lights", &buffers.lights);
        let pixels = settings.width as u64 * settings.height as u64;
        let accumulation = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("accumulation"),
            size: pixels * 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let entries = [
            &params_buffer,
            &primitives,
            &materials,
            &lights,
            &accumulation,
        ];
        let entries: Vec<_> = entries
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("march"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        Ok(Self {
            params,
            params_buffer,
            accumulation,
            pipeline,
            bind_group,
            frames: 0,
        })
    }

    /// Frames summed so far.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Submits `count` more frames, each with its own random numbers
    /// (film jitter, march jitter within the pixel's stratum, glossy
    /// directions), without waiting for them.
    pub fn submit_frames(&mut self, gpu: &Gpu, count: u32) {
        let (w, h) = (
            self.params.half_extent_resolution[2] as u32,
            self.params.half_extent_resolution[3] as u32,
        );
        for _ in 0..count {
            self.params.frame = self.frames;
            gpu.queue
                .write_buffer(&self.params_buffer, 0, bytemuck::bytes_of(&self.params));
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.bind_group, &[]);
                pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
            }
            gpu.queue.submit([encoder.finish()]);
            self.frames += 1;
        }
    }

    /// Waits for the submitted frames to finish.
    pub fn wait(&self, gpu: &Gpu) -> Result<(), GpuError> {
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Readback(e.to_string()))
    }

    /// The mean of the frames so far per pixel (radiance, linear RGB).
    pub fn image(&self, gpu: &Gpu) -> Result<Image, GpuError> {
        let (w, h) = (
            self.params.half_extent_resolution[2] as u32,
            self.params.half_extent_resolution[3] as u32,
        );
        let bytes = read_buffer(gpu, &self.accumulation, w as u64 * h as u64 * 16)?;
        let sums: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&bytes);
        let pixels = sums
            .iter()
            .map(|s| {
                if s[3] > 0.0 {
                    Rgb::new(s[0], s[1], s[2]) / s[3]
                } else {
                    Rgb::ZERO
                }
            })
            .collect();
        Ok(Image::from_pixels(w, h, pixels))
    }
}

/// Renders `scene` headless: `frames` frames summed, their mean returned.
pub fn render(
    gpu: &Gpu,
    scene: &Scene,
    settings: &MarchSettings,
    frames: u32,
) -> Result<Image, GpuError> {
    let mut march = GpuMarch::new(gpu, scene, settings)?;
    march.submit_frames(gpu, frames);
    march.wait(gpu)?;
    march.image(gpu)
}
