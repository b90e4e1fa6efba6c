//! The GPU device: found headless (no window, no surface), so the same
//! code runs on a real GPU and on lavapipe, Mesa's software Vulkan driver
//! that CI installs.

use std::fmt;

/// Why no GPU device could be opened.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter exists on this machine (no Vulkan driver: on Debian,
    /// `apt-get install mesa-vulkan-drivers libvulkan1` provides lavapipe).
    #[error(
        "no GPU adapter found (install a Vulkan driver; on Debian `apt-get install mesa-vulkan-drivers libvulkan1` gives the software one, lavapipe): {0}"
    )]
    NoAdapter(String),
    /// An adapter exists but refused a device with the limits we need.
    #[error("the GPU adapter {adapter} refused a device: {message}")]
    Device { adapter: String, message: String },
    /// The scene uses something the GPU renderer does not implement.
    #[error("the GPU renderer cannot render this scene: {0}")]
    Unsupported(String),
    /// A shader failed to compile or validate (a bug in Tyndall).
    #[error("the shader {label} did not compile: {message}")]
    Shader { label: String, message: String },
    /// Reading results back from the GPU failed.
    #[error("reading back from the GPU failed: {0}")]
    Readback(String),
}

/// An opened device with its queue and a description of the adapter.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter: AdapterSummary,
}

/// What the adapter is, for logs and benchmark reports.
#[derive(Clone, Debug)]
pub struct AdapterSummary {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
}

impl fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} ({}, {}, {})",
            self.name, self.backend, self.device_type, self.driver
        )
    }
}

impl Gpu {
    /// Opens the highest-performance adapter, hardware or software
    /// (lavapipe counts: `force_fallback_adapter` is not needed for it,
    /// it is a regular Vulkan device of type CPU).
    pub fn new() -> Result<Self, GpuError> {
        pollster::block_on(Self::open())
    }

    async fn open() -> Result<Self, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: wgpu::Backends::VULKAN,
            ..wgpu::InstanceDescriptor::new_without_display_handle()
        });
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let info = adapter.get_info();
        let summary = AdapterSummary {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
            driver: format!("{} {}", info.driver, info.driver_info),
        };
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("tyndall"),
                required_limits: adapter.limits(),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::Device {
                adapter: summary.to_string(),
                message: e.to_string(),
            })?;
        Ok(Self {
            device,
            queue,
            adapter: summary,
        })
    }
}

/// Compiles WGSL `source` into one compute pipeline per entry point, with
/// `layout` (or one derived from the shader for `None`), returning
/// compilation and validation errors instead of letting wgpu panic.
pub(crate) fn compute_pipelines<const N: usize>(
    gpu: &Gpu,
    label: &str,
    source: &str,
    layout: Option<&wgpu::PipelineLayout>,
    entry_points: [&str; N],
) -> Result<[wgpu::ComputePipeline; N], GpuError> {
    let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = gpu
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
    let pipelines = entry_points.map(|entry_point| {
        gpu.device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry_point),
                layout,
                module: &module,
                entry_point: Some(entry_point),
                compilation_options: Default::default(),
                cache: None,
            })
    });
    match pollster::block_on(scope.pop()) {
        None => Ok(pipelines),
        Some(e) => Err(GpuError::Shader {
            label: label.to_string(),
            message: e.to_string(),
        }),
    }
}
