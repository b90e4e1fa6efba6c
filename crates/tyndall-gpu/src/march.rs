//! The GPU renderer of single scattering: the scene uploaded once, then
//! frames dispatched and summed per pixel on the GPU, each frame with its
//! own film jitter and in-scattering samples, so the mean converges to the
//! CPU image of the same integrator. The fog segment's in-scattering is
//! the paper's ray march (jitter inside the pixel's interleaving stratum,
//! as on the CPU `march`) or unbiased interleaved equiangular sampling
//! (the CPU `single`'s estimator), as [`InScattering`] says.

use crate::device::{Gpu, GpuError, compute_pipelines};
use crate::maps;
use crate::readback::read_buffer;
use crate::scene_buffers::{GpuLight, GpuMaterial, GpuPrimitive, SceneBuffers};
use crate::shaders;
use bytemuck::Pod;
use tyndall::settings::{IntegratorKind, VisibilityMode};
use tyndall::{Image, RenderSettings, Rgb, Scene};
use wgpu::util::DeviceExt;

pub(crate) mod params;
mod update;

use params::{ESTIMATOR_MARCH, Params};
pub use update::{MapsRebuilt, Update};

/// A GPU render's parameters: those of the CPU `march` and `single` the
/// GPU honours (the name is the march's, which came first).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarchSettings {
    pub width: u32,
    pub height: u32,
    /// Step length `h` between lattice points (scene units; the march
    /// only).
    pub step: f32,
    /// Interleaving tile size `n` (1: none): of the march's jitter, or of
    /// the equiangular samples' offset.
    pub interleave: u32,
    /// Most reflective-layer bounces a camera path follows.
    pub max_bounces: u32,
    pub seed: u64,
    /// How march steps and surfaces see lights past geometry.
    pub visibility: GpuVisibility,
    /// How each fog segment's in-scattered light is estimated.
    pub in_scattering: InScattering,
}

/// The estimator of in-scattered light along each camera segment (the
/// single-scattering integrators of `tyndall::integrators`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InScattering {
    /// The paper's jittered fixed-step Riemann sum with interleaved
    /// sampling (`tyndall::integrators::march`): biased by its step,
    /// converges to the CPU `march` image of the same step.
    March,
    /// Unbiased single scattering (`tyndall::integrators::single`): per
    /// light, `volume_samples` stratified equiangular samples (Kulla &
    /// Fajardo 2012) over its reach and one distance sample per segment,
    /// combined by the balance heuristic, the CPU `single`'s estimator.
    /// The equiangular offset is interleaved over the `interleave`-sided
    /// pixel tile (Keller & Heidrich 2001) and shifted per frame by the
    /// golden-ratio sequence from a random start, so each pixel stays
    /// unbiased; converges to the CPU `single` image.
    Single { volume_samples: u32 },
}

impl From<&RenderSettings> for MarchSettings {
    /// The march settings of a CPU render's settings (the ones the GPU
    /// honours; callers refuse the others).
    fn from(settings: &RenderSettings) -> Self {
        Self {
            width: settings.width,
            height: settings.height,
            step: settings.step,
            interleave: settings.interleave,
            max_bounces: settings.max_bounces,
            seed: settings.seed,
            visibility: match settings.visibility {
                VisibilityMode::ShadowRays => GpuVisibility::ShadowRays,
                VisibilityMode::Maps { resolution } => GpuVisibility::Maps { resolution },
            },
            // `volpath` has no GPU estimator; callers refuse it.
            in_scattering: match settings.integrator {
                IntegratorKind::Single => InScattering::Single {
                    volume_samples: settings.volume_samples,
                },
                IntegratorKind::March | IntegratorKind::Volpath => InScattering::March,
            },
        }
    }
}

/// Visibility towards lights on the GPU, as `tyndall::settings::VisibilityMode`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GpuVisibility {
    /// An exact shadow ray per step and light.
    ShadowRays,
    /// Per-light depth and coloured transmittance maps of `resolution`²
    /// texels per face, rendered on the GPU before the frames.
    Maps { resolution: u32 },
}

/// A scene on the GPU with its shadow maps and running per-pixel sums.
pub struct GpuMarch {
    params: Params,
    params_buffer: wgpu::Buffer,
    /// Bindings 1–8 and 10–14 of `scene.wgsl`/`maps.wgsl`, in order;
    /// binding 9 (the layers) is added when the bind group is made.
    buffers: Vec<wgpu::Buffer>,
    layers: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    march_pipeline: wgpu::ComputePipeline,
    map_count_pipeline: wgpu::ComputePipeline,
    map_layers_pipeline: wgpu::ComputePipeline,
    resolve_pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    frames: u32,
    /// What the buffers now hold, to tell what an [`GpuMarch::update`]
    /// changes.
    uploaded: Uploaded,
}

/// Host copies of what is on the GPU: the scene's arrays, the maps'
/// faces, and how many glass layers the maps have taken.
struct Uploaded {
    scene: SceneBuffers,
    light_maps: Vec<maps::GpuLightMap>,
    faces: Vec<maps::GpuFace>,
    layers: LayerUse,
}

/// Glass layers of the shadow maps: handed out so far (the counter's
/// value), and by the last build of every map. A light's maps rendered
/// again take new layers after the others' (`GpuMarch::update`), leaving
/// its old ones unused until the next full build.
#[derive(Clone, Copy, Debug, Default)]
struct LayerUse {
    taken: u32,
    at_full_build: u32,
}

impl LayerUse {
    /// Whether more layers were taken since the last full build than it
    /// took (and more than a megabyte's worth): most of what lights
    /// rendered again left behind is then unused, and a full build,
    /// which packs the array again, is due. This bounds the array at
    /// about twice what the maps use.
    fn mostly_unused(self) -> bool {
        const SLACK: u32 = 1 << 16;
        self.taken - self.at_full_build > self.at_full_build.max(SLACK)
    }
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
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        })
}

/// A read-write storage buffer of `size` bytes (at least 16).
fn scratch(gpu: &Gpu, label: &str, size: u64) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Which bindings of the march's module are written by some kernel.
const READ_WRITE_BINDINGS: [u32; 7] = [4, 7, 8, 9, 10, 11, 13];

/// Index in [`GpuMarch::buffers`] of the BVH's nodes (binding 12), of
/// the counter of glass layers handed out (binding 13) and of the
/// emissive meshes' triangles (binding 14).
const BVH_NODES: usize = 10;
const LAYERS_TAKEN: usize = 11;
const LIGHT_TRIANGLES: usize = 12;

/// Bytes of a map texel's (first layer, count) span.
const SPAN_BYTES: u64 = 8;

/// Index in [`GpuMarch::buffers`] of the per-pixel sums (binding 4), of
/// their in-scattered part with the first-hit depths (binding 10) and of
/// the resolved image (binding 11).
const ACCUMULATION: usize = 3;
const FOG_ACCUMULATION: usize = 8;
const DISPLAY: usize = 9;

/// The per-pixel buffers of a `width × height` image, at their indices
/// in [`GpuMarch::buffers`]: the sums, their in-scattered part, the
/// resolved image (a `vec4<f32>` each).
fn pixel_buffers(gpu: &Gpu, width: u32, height: u32) -> [(usize, wgpu::Buffer); 3] {
    let bytes = width as u64 * height as u64 * 16;
    [
        (ACCUMULATION, scratch(gpu, "accumulation", bytes)),
        (
            FOG_ACCUMULATION,
            scratch(gpu, "in-scattered accumulation", bytes),
        ),
        (DISPLAY, scratch(gpu, "display", bytes)),
    ]
}

fn bind_group_layout(gpu: &Gpu) -> wgpu::BindGroupLayout {
    bind_group_layout_with(gpu, &[])
}

/// The march's layout (bindings 0–14) and, after it, storage bindings
/// `extra` (number, read-write).
fn bind_group_layout_with(gpu: &Gpu, extra: &[(u32, bool)]) -> wgpu::BindGroupLayout {
    let read_write =
        |binding: u32| READ_WRITE_BINDINGS.contains(&binding) || extra.contains(&(binding, true));
    let entries: Vec<_> = (0..15u32)
        .chain(extra.iter().map(|&(binding, _)| binding))
        .map(|binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: if binding == 0 {
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                }
            } else {
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage {
                        read_only: !read_write(binding),
                    },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                }
            },
            count: None,
        })
        .collect();
    gpu.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("march"),
            entries: &entries,
        })
}

/// What `scene` under `settings` becomes on the GPU — its arrays, the
/// uniforms at frame 0, the map faces and their texel count — made and
/// checked before anything is written ([`GpuMarch::new`],
/// [`GpuMarch::update`]).
struct Prepared {
    scene: SceneBuffers,
    params: Params,
    light_maps: Vec<maps::GpuLightMap>,
    faces: Vec<maps::GpuFace>,
    texels: u64,
}

impl Prepared {
    /// Keeps `previous`'s BVH if the geometry is the same.
    fn new(
        gpu: &Gpu,
        scene: &Scene,
        settings: &MarchSettings,
        previous: Option<&SceneBuffers>,
    ) -> Result<Self, GpuError> {
        let buffers = SceneBuffers::after(scene, previous)?;
        let params = Params::new(scene, settings, &buffers)?;
        let resolution = params.map_resolution;
        let (light_maps, faces) = if resolution > 0 {
            maps::faces(scene, resolution)
        } else {
            (Vec::new(), Vec::new())
        };
        let texels = map_texels(gpu, faces.len(), resolution)?;
        Ok(Self {
            scene: buffers,
            params,
            light_maps,
            faces,
            texels,
        })
    }
}

impl GpuMarch {
    /// Uploads `scene`, renders its shadow maps if asked for, and prepares
    /// an empty accumulation of `settings.width × settings.height` pixels.
    pub fn new(gpu: &Gpu, scene: &Scene, settings: &MarchSettings) -> Result<Self, GpuError> {
        let Prepared {
            scene: buffers,
            params,
            light_maps,
            faces,
            texels,
        } = Prepared::new(gpu, scene, settings, None)?;
        let map_resolution = params.map_resolution;
        let layout = bind_group_layout(gpu);
        let pipeline_layout = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("march"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        let [
            march_pipeline,
            map_count_pipeline,
            map_layers_pipeline,
            resolve_pipeline,
        ] = compute_pipelines(
            gpu,
            "march",
            &shaders::march(&params::wgsl_prelude()),
            Some(&pipeline_layout),
            [
                "march_frame",
                "map_count",
                "map_layers",
                "interleave_resolve",
            ],
        )?;
        let params_buffer = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("march params"),
                contents: bytemuck::bytes_of(&params),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            });
        let buffers_on_host = buffers;
        let buffers = &buffers_on_host;
        let [(_, accumulation), (_, fog_accumulation), (_, display)] =
            pixel_buffers(gpu, settings.width, settings.height);
        let buffers = vec![
            storage::<GpuPrimitive>(gpu, "primitives", &buffers.primitives),
            storage::<GpuMaterial>(gpu, "materials", &buffers.materials),
            storage::<GpuLight>(gpu, "lights", &buffers.lights),
            accumulation,
            storage(gpu, "faces", &faces),
            storage(gpu, "light maps", &light_maps),
            scratch(gpu, "map depths", texels * 4),
            scratch(gpu, "layer spans", texels * SPAN_BYTES),
            fog_accumulation,
            display,
            storage(gpu, "BVH nodes", &buffers.bvh_nodes),
            scratch(gpu, "layers taken", 4),
            storage(gpu, "light triangles", &buffers.light_triangles),
        ];
        let layers = scratch(gpu, "layers", 16);
        let bind_group = make_bind_group(gpu, &layout, &params_buffer, &buffers, &layers);
        let mut march = Self {
            params,
            params_buffer,
            buffers,
            layers,
            layout,
            march_pipeline,
            map_count_pipeline,
            map_layers_pipeline,
            resolve_pipeline,
            bind_group,
            frames: 0,
            uploaded: Uploaded {
                scene: buffers_on_host,
                light_maps,
                faces,
                layers: LayerUse::default(),
            },
        };
        if map_resolution > 0 {
            march.build_maps(gpu)?;
        }
        Ok(march)
    }

    /// Renders every light's depth and coloured transmittance map, all on
    /// the GPU: a first pass traces each texel for its depth and takes a
    /// span of the layer array for the glass it sees; then, the array
    /// grown if the 4-byte count read back says so, a second pass writes
    /// the layers. Waits for the GPU.
    pub fn build_maps(&mut self, gpu: &Gpu) -> Result<(), GpuError> {
        let r = self.params.map_resolution;
        let faces = self.uploaded.faces.len() as u32;
        if r == 0 || faces == 0 {
            return Ok(());
        }
        let groups = (r.div_ceil(8), r.div_ceil(8), faces);
        gpu.queue
            .write_buffer(&self.buffers[LAYERS_TAKEN], 0, &0u32.to_ne_bytes());
        self.dispatch(gpu, &self.map_count_pipeline, groups);
        let taken = self.read_layers_taken(gpu)?;
        self.reserve_layers(gpu, taken, 0)?;
        self.dispatch(gpu, &self.map_layers_pipeline, groups);
        self.uploaded.layers = LayerUse {
            taken,
            at_full_build: taken,
        };
        self.wait(gpu)
    }

    /// The glass layers handed out so far (waits for the GPU).
    fn read_layers_taken(&self, gpu: &Gpu) -> Result<u32, GpuError> {
        let bytes = read_buffer(gpu, &self.buffers[LAYERS_TAKEN], 4)?;
        Ok(u32::from_ne_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]))
    }

    /// Makes the layer array hold `needed` layers, keeping its first
    /// `keep`: a larger array when it is too small — of `needed` layers
    /// for a full build (`keep` = 0), of twice that when lights rendered
    /// again append (so that the next ones need not grow it again) — or
    /// an error past this GPU's storage buffer size.
    fn reserve_layers(&mut self, gpu: &Gpu, needed: u32, keep: u32) -> Result<(), GpuError> {
        const LAYER_BYTES: u64 = 16;
        let bytes = needed as u64 * LAYER_BYTES;
        if bytes <= self.layers.size() {
            return Ok(());
        }
        let limit = gpu.device.limits().max_storage_buffer_binding_size;
        if bytes > limit {
            return Err(GpuError::Unsupported(format!(
                "the shadow maps' {needed} glass layers exceed this GPU's storage buffer size ({limit} bytes); lower the resolution"
            )));
        }
        let capacity = if keep > 0 {
            (2 * bytes).min(limit)
        } else {
            bytes
        };
        let layers = scratch(gpu, "layers", capacity);
        if keep > 0 {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            encoder.copy_buffer_to_buffer(&self.layers, 0, &layers, 0, keep as u64 * LAYER_BYTES);
            gpu.queue.submit([encoder.finish()]);
        }
        self.layers = layers;
        self.bind_group = make_bind_group(
            gpu,
            &self.layout,
            &self.params_buffer,
            &self.buffers,
            &self.layers,
        );
        Ok(())
    }

    /// A layout and bind group of the march's bindings and, after them,
    /// the storage buffers `extra` (binding number, buffer, read-write):
    /// for kernels appended to the march module
    /// ([`crate::formula_probe::evaluate_in_scene`]).
    pub(crate) fn bindings_with(
        &self,
        gpu: &Gpu,
        extra: &[(u32, &wgpu::Buffer, bool)],
    ) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
        let kinds: Vec<_> = extra.iter().map(|&(b, _, rw)| (b, rw)).collect();
        let buffers: Vec<_> = extra.iter().map(|&(b, buffer, _)| (b, buffer)).collect();
        let layout = bind_group_layout_with(gpu, &kinds);
        let group = make_bind_group_with(
            gpu,
            &layout,
            &self.params_buffer,
            &self.buffers,
            &self.layers,
            &buffers,
        );
        (layout, group)
    }

    fn dispatch(&self, gpu: &Gpu, pipeline: &wgpu::ComputePipeline, groups: (u32, u32, u32)) {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.dispatch_workgroups(groups.0, groups.1, groups.2);
        }
        gpu.queue.submit([encoder.finish()]);
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
            self.dispatch(gpu, &self.march_pipeline, (w.div_ceil(8), h.div_ceil(8), 1));
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

    /// The mean of the frames so far per pixel (radiance, linear RGB): the
    /// estimate that converges to the CPU image.
    pub fn image(&self, gpu: &Gpu) -> Result<Image, GpuError> {
        self.read_image(gpu, ACCUMULATION)
    }

    /// Whether [`GpuMarch::display_image`] filters: a march whose
    /// interleaving tile shares out the lattice (n > 1), while fewer than
    /// (n²)² frames are summed. Until every pixel has taken every residue
    /// n² times over, a pixel's own sum holds fewer lattice cells than
    /// the filtered one's window; after that the unfiltered mean is
    /// shown, whose only error is noise that keeps falling.
    pub fn display_filters(&self) -> bool {
        let strata = self.params.interleave * self.params.interleave;
        self.params.estimator == ESTIMATOR_MARCH && strata > 1 && self.frames < strata * strata
    }

    /// Dispatches the discontinuity-buffer filter (`interleave_resolve`
    /// in `camera.wgsl`) into the display buffer when
    /// [`GpuMarch::display_filters`], without waiting; says whether it did.
    pub fn submit_resolve(&self, gpu: &Gpu) -> bool {
        if !self.display_filters() {
            return false;
        }
        let (w, h) = self.size();
        self.dispatch(
            gpu,
            &self.resolve_pipeline,
            (w.div_ceil(8), h.div_ceil(8), 1),
        );
        true
    }

    /// The image to show while the view is live: [`GpuMarch::image`], but
    /// while [`GpuMarch::display_filters`] with each pixel's in-scattered
    /// light averaged over its interleaving window's pixels on the same
    /// surface (Keller & Heidrich 2001's discontinuity buffer). That
    /// makes one frame of a march whose tile shares out the lattice look
    /// like one full lattice per pixel, at the price of blur across the
    /// window; it is not used for renders to files.
    pub fn display_image(&self, gpu: &Gpu) -> Result<Image, GpuError> {
        if self.submit_resolve(gpu) {
            self.read_image(gpu, DISPLAY)
        } else {
            self.image(gpu)
        }
    }

    fn size(&self) -> (u32, u32) {
        (
            self.params.half_extent_resolution[2] as u32,
            self.params.half_extent_resolution[3] as u32,
        )
    }

    /// Buffer `index` (sums or display: (rgb, weight) per pixel) divided out.
    fn read_image(&self, gpu: &Gpu, index: usize) -> Result<Image, GpuError> {
        let (w, h) = self.size();
        let bytes = read_buffer(gpu, &self.buffers[index], w as u64 * h as u64 * 16)?;
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

/// The texels of `face_count` map faces of `resolution`², or an error when
/// their depths would not fit one storage buffer of this GPU.
fn map_texels(gpu: &Gpu, face_count: usize, resolution: u32) -> Result<u64, GpuError> {
    let texels = face_count as u64 * resolution as u64 * resolution as u64;
    let limit = gpu.device.limits().max_storage_buffer_binding_size;
    // Also: the u32 counter of layers handed out must not wrap, though
    // every texel took the most layers a ray keeps and lights rendered
    // again appended up to the bound of `LayerUse::mostly_unused` (under
    // three full builds' worth and its slack: four covers both).
    let most_layers = texels * crate::scene_buffers::MAX_PANES as u64;
    if texels * SPAN_BYTES > limit || 4 * most_layers > u32::MAX as u64 {
        return Err(GpuError::Unsupported(format!(
            "shadow maps of {face_count} faces of {resolution}² texels exceed this GPU's storage buffer size ({limit} bytes); lower the resolution"
        )));
    }
    Ok(texels)
}

/// The bind group of bindings 0 (`params`), 1–8 (`buffers[..8]`), 9
/// (`layers`) and 10–14 (`buffers[8..]`).
fn make_bind_group(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    params: &wgpu::Buffer,
    buffers: &[wgpu::Buffer],
    layers: &wgpu::Buffer,
) -> wgpu::BindGroup {
    make_bind_group_with(gpu, layout, params, buffers, layers, &[])
}

/// [`make_bind_group`] with the buffers `extra` (binding number, buffer)
/// after it.
fn make_bind_group_with(
    gpu: &Gpu,
    layout: &wgpu::BindGroupLayout,
    params: &wgpu::Buffer,
    buffers: &[wgpu::Buffer],
    layers: &wgpu::Buffer,
    extra: &[(u32, &wgpu::Buffer)],
) -> wgpu::BindGroup {
    let all = std::iter::once(params)
        .chain(&buffers[..8])
        .chain(std::iter::once(layers))
        .chain(&buffers[8..]);
    let entries: Vec<_> = all
        .enumerate()
        .map(|(i, b)| (i as u32, b))
        .chain(extra.iter().copied())
        .map(|(binding, b)| wgpu::BindGroupEntry {
            binding,
            resource: b.as_entire_binding(),
        })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("march"),
        layout,
        entries: &entries,
    })
}

#[cfg(test)]
mod tests {
    use super::LayerUse;

    #[test]
    fn a_full_build_is_due_once_unused_layers_outnumber_used_ones() {
        let full = |taken, at_full_build| {
            LayerUse {
                taken,
                at_full_build,
            }
            .mostly_unused()
        };
        assert!(!full(1_000_000, 1_000_000), "just built");
        assert!(!full(2_000_000, 1_000_000), "as many unused as used");
        assert!(full(2_000_001, 1_000_000));
        assert!(!full(60_000, 0), "below the slack");
        assert!(full(70_000, 0));
    }
}
