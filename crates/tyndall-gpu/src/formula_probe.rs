//! Evaluates the WGSL physics functions (`shaders/formulas.wgsl`) on the
//! GPU for a list of inputs, so tests can compare them with the Rust
//! functions they transcribe ("one formula, two languages", issue 14),
//! and the scene-dependent light functions of `shaders/lights.wgsl` on
//! lights as the march uploads them, or in a whole scene as a
//! [`GpuMarch`] binds it (issue 26).

use crate::device::{Gpu, GpuError, compute_pipelines};
use crate::march::GpuMarch;
use crate::march::params::wgsl_prelude;
use crate::readback::read_buffer;
use crate::scene_buffers::{GpuLight, GpuLightTriangle};
use crate::shaders;
use wgpu::util::DeviceExt;

/// A WGSL function of `formulas.wgsl` that [`evaluate`] can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Formula {
    /// `phase_hg(g, cos θ)`: input `[g, cos θ, _, _], _`; output `x`.
    Phase,
    /// `spot_falloff(profile, cos_cutoff, cos_inner, cos θ)`: input
    /// `[profile, cos_cutoff, cos_inner, cos θ], _` with profile 0
    /// linear, 1 hard, 2 smooth; output `x`.
    SpotFalloff,
    /// `glass_tint_after(model, before, colour, α)`: input
    /// `[before.rgb, model], [colour.rgb, α]` with model 0 filter, 1
    /// blend; output `rgb`.
    GlassTint,
    /// `transmittance(σt, d)`: input `[σt, d, _, _], _`; output `x`.
    Transmittance,
    /// `single_sample(f, T, n, p_e, p_d)`: input `[f.rgb, T], [n, p_e,
    /// p_d, _]`; output `rgb`.
    SingleSample,
    /// `equiangular_new` on the ray from the origin along +x, then
    /// `equiangular_sample` and `equiangular_pdf`: input
    /// `[y.xyz, u], [a, b, t, _]`; output `[sample(u), pdf(sample(u)),
    /// pdf(t), valid]` with valid 1 or 0.
    Equiangular,
    /// `exponential_new`, `exponential_sample` and `exponential_pdf`:
    /// input `[σt, a, b, u], [t, _, _, _]`; output `[sample(u),
    /// pdf(sample(u)), pdf(t), valid]` with valid 1 or 0.
    Exponential,
    /// `uniform_cone` and `uniform_cone_pdf`: input `[axis.xyz,
    /// cos θmax], [u.x, u.y, _, _]`; output `[direction.xyz, density]`.
    UniformCone,
    /// `spherical_rectangle_new` for the rectangle with its corner at the
    /// origin and edges `width`·x̂, `height`·ŷ seen from `o`, then
    /// `spherical_rectangle_sample`: input `[o.xyz, u.x], [u.y, width,
    /// height, _]`; output `[sample.xyz, solid angle]`, all 0 when the
    /// rectangle is invalid from `o`.
    SphericalRectangle,
    /// `ggx_eval(α, outgoing, +y, incident)`: input `[outgoing.xyz, α],
    /// [incident.xyz, _]`; output `x`.
    GgxEval,
}

impl Formula {
    fn entry_point(self) -> &'static str {
        match self {
            Formula::Phase => "probe_phase",
            Formula::SpotFalloff => "probe_spot",
            Formula::GlassTint => "probe_glass",
            Formula::Transmittance => "probe_transmittance",
            Formula::SingleSample => "probe_single_sample",
            Formula::Equiangular => "probe_equiangular",
            Formula::Exponential => "probe_exponential",
            Formula::UniformCone => "probe_uniform_cone",
            Formula::SphericalRectangle => "probe_spherical_rectangle",
            Formula::GgxEval => "probe_ggx_eval",
        }
    }
}

/// Runs `formula` on the GPU for each item (two input vec4s each) and
/// returns one output vec4 per item.
pub fn evaluate(
    gpu: &Gpu,
    formula: Formula,
    items: &[[[f32; 4]; 2]],
) -> Result<Vec<[f32; 4]>, GpuError> {
    if items.is_empty() {
        return Ok(Vec::new());
    }
    let device = &gpu.device;
    let [pipeline] = compute_pipelines(
        gpu,
        "formula probe",
        &shaders::formula_probe(),
        None,
        [formula.entry_point()],
    )?;
    let input = probe_input(gpu, bytemuck::cast_slice(items));
    let size = (items.len() * 16) as u64;
    let output = probe_output(gpu, size);
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: output.as_entire_binding(),
            },
        ],
    });
    run_probe(gpu, &pipeline, &bind_group, items.len(), &output, size)
}

/// A scene-dependent WGSL function of `lights.wgsl` that
/// [`evaluate_lights`] can run on a light of the uploaded list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightFormula {
    /// `spot_reach(light, ray, t0, t1)`: input `[origin.xyz, t0],
    /// [direction.xyz, t1], [light, _, _, _]`; output `[lo, hi, 1, _]`,
    /// or 0 where the ray misses the cone, then `0`.
    SpotReach,
    /// `incident(light, x, light_point_at(light, u))`: input `[x.xyz, _],
    /// _, [light, u.x, u.y, _]`; output `[direction.xyz, distance],
    /// [irradiance.rgb, valid]` with valid 1 or 0.
    Incident,
    /// `sample_incident(light, x)` with its two random numbers `u =
    /// k/2²⁴`: input `[x.xyz, _], [k.x, k.y, _, _], [light, _, _, _]`
    /// (k integers below 2²⁴); output as [`LightFormula::Incident`].
    SampleIncident,
}

impl LightFormula {
    fn entry_point(self) -> &'static str {
        match self {
            LightFormula::SpotReach => "probe_spot_reach",
            LightFormula::Incident => "probe_incident",
            LightFormula::SampleIncident => "probe_sample_incident",
        }
    }
}

/// Runs `formula` on the GPU for each item (three input vec4s each, the
/// light's index in `lights` the first number of the third) with `lights`
/// and their emissive triangles bound as the march binds them, and
/// returns two output vec4s per item.
pub fn evaluate_lights(
    gpu: &Gpu,
    formula: LightFormula,
    lights: &[GpuLight],
    triangles: &[GpuLightTriangle],
    items: &[[[f32; 4]; 3]],
) -> Result<Vec<[[f32; 4]; 2]>, GpuError> {
    if items.is_empty() {
        return Ok(Vec::new());
    }
    let device = &gpu.device;
    let [pipeline] = compute_pipelines(
        gpu,
        "light probe",
        &shaders::light_probe(&wgsl_prelude()),
        None,
        [formula.entry_point()],
    )?;
    let init = |label, contents: &[u8]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let one_light = [GpuLight::default()];
    let one_triangle = [GpuLightTriangle::default()];
    let lights = init(
        "probe lights",
        bytemuck::cast_slice(if lights.is_empty() {
            &one_light
        } else {
            lights
        }),
    );
    let triangles = init(
        "probe light triangles",
        bytemuck::cast_slice(if triangles.is_empty() {
            &one_triangle
        } else {
            triangles
        }),
    );
    let input = probe_input(gpu, bytemuck::cast_slice(items));
    let size = (items.len() * 32) as u64;
    let output = probe_output(gpu, size);
    let mut entries = vec![
        wgpu::BindGroupEntry {
            binding: 3,
            resource: lights.as_entire_binding(),
        },
        wgpu::BindGroupEntry {
            binding: 20,
            resource: input.as_entire_binding(),
        },
        wgpu::BindGroupEntry {
            binding: 21,
            resource: output.as_entire_binding(),
        },
    ];
    // Only the incident kernels read mesh lights' triangles (an
    // automatic layout holds the bindings its entry point uses).
    if formula != LightFormula::SpotReach {
        entries.push(wgpu::BindGroupEntry {
            binding: 14,
            resource: triangles.as_entire_binding(),
        });
    }
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    run_probe(gpu, &pipeline, &bind_group, items.len(), &output, size)
}

/// A WGSL function of the march module that reads the scene — camera,
/// fog, geometry, lights — which [`evaluate_in_scene`] runs with a
/// [`GpuMarch`]'s own bindings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneFormula {
    /// `scattered_radiance(i, light, light_point_at(light, u), x, view)`:
    /// input `[x.xyz, _], [view.xyz, _], [light, u.x, u.y, _]`; output
    /// `[radiance.rgb, _]`, then `0`.
    ScatteredRadiance,
    /// `light_arriving(i, light, x, on_surface, normal, inc)` with `inc =
    /// incident(light, x, light_point_at(light, u))`: input `[x.xyz,
    /// on_surface (0 or 1)], [normal.xyz, _], [light, u.x, u.y, _]`;
    /// output `[arriving.rgb, valid]` with valid 1 where `inc` is (0 and
    /// no light otherwise), then `0`.
    LightArriving,
    /// One sample of `single_in_scattered(ray, t_hit, 0, 1)`, its random
    /// numbers from the PCG stream of `seed`: input `[origin.xyz, t_hit],
    /// [direction.xyz, _], [seed, _, _, _]` (an integer below 2²⁴);
    /// output `[radiance.rgb, _]`, then `0`. Items of different seeds are
    /// independent samples, to be averaged.
    SingleInScattered,
    /// One sample of the camera path `radiance(ray, 0, 1)`, its random
    /// numbers from the PCG stream of `seed`: input `[origin.xyz, _],
    /// [direction.xyz, _], [seed, _, _, _]` (an integer below 2²⁴);
    /// output `[radiance.rgb, _]`, then `0`.
    Radiance,
    /// `direct_lighting(diffuse, specular, roughness, albedo, incoming,
    /// x, normal)`: input `[x.xyz, roughness], [normal.xyz, n + specular],
    /// [diffuse.rgb, albedo]` (a grey specular layer below 1, its GGX
    /// lobe's albedo towards the viewer; the ray arriving along
    /// `normalize((0.2 + 0.5·n)·t − normal)`, n an integer, t the first of
    /// glam's `any_orthonormal_pair(normal)`); output `[radiance.rgb, _]`,
    /// then `0`. For scenes of delta lights (an area light's points draw
    /// random numbers).
    DirectLighting,
    /// `camera_ray(film, lens)`: input `[film.xy, lens.xy], _, _`;
    /// output `[origin.xyz, _], [direction.xyz, _]`.
    CameraRay,
    /// `fog_interval(ray, t0, t1)`: input `[origin.xyz, t0],
    /// [direction.xyz, t1], _`; output `[a, b, 1, _]`, or 0 where the
    /// interval holds no fog, then `0`.
    FogInterval,
    /// `nearest_hit(ray)` and `geometric_normal` there: input
    /// `[origin.xyz, _], [direction.xyz, _], _`; output `[t, 1, the
    /// primitive's material, _], [normal.xyz, _]`, or both 0 for a miss.
    NearestHit,
    /// `reflect_layer(roughness, incoming, normal)` with its two random
    /// numbers `u = k/2²⁴`: input `[incoming.xyz, roughness],
    /// [normal.xyz, _], [k.x, k.y, _, _]` (k integers below 2²⁴); output
    /// `[direction.xyz, _]` (0 below the surface), then `0`.
    Reflect,
    /// The march's `in_scattered(ray, t_hit, 0, 1)` (the whole lattice)
    /// with jitter `k/2²⁴`: input `[origin.xyz, t_hit], [direction.xyz,
    /// _], [k, _, _, _]` (k an integer below 2²⁴); output `[radiance.rgb,
    /// _]`, then `0`. For scenes of delta lights (an area light's points
    /// draw further random numbers).
    InScattered,
}

impl SceneFormula {
    fn entry_point(self) -> &'static str {
        match self {
            SceneFormula::ScatteredRadiance => "probe_scattered_radiance",
            SceneFormula::LightArriving => "probe_light_arriving",
            SceneFormula::SingleInScattered => "probe_single_in_scattered",
            SceneFormula::Radiance => "probe_radiance",
            SceneFormula::DirectLighting => "probe_direct_lighting",
            SceneFormula::CameraRay => "probe_camera_ray",
            SceneFormula::FogInterval => "probe_fog_interval",
            SceneFormula::NearestHit => "probe_nearest_hit",
            SceneFormula::Reflect => "probe_reflect",
            SceneFormula::InScattered => "probe_in_scattered",
        }
    }
}

/// Runs `formula` on the GPU for each item (three input vec4s, the light's
/// index the first number of the third) in the scene `march` has
/// uploaded, bound as the march binds it, and returns two output vec4s
/// per item.
pub fn evaluate_in_scene(
    gpu: &Gpu,
    march: &GpuMarch,
    formula: SceneFormula,
    items: &[[[f32; 4]; 3]],
) -> Result<Vec<[[f32; 4]; 2]>, GpuError> {
    if items.is_empty() {
        return Ok(Vec::new());
    }
    let device = &gpu.device;
    let input = probe_input(gpu, bytemuck::cast_slice(items));
    let size = (items.len() * 32) as u64;
    let output = probe_output(gpu, size);
    let (layout, bind_group) =
        march.bindings_with(gpu, &[(20, &input, false), (21, &output, true)]);
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("scene probe"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let [pipeline] = compute_pipelines(
        gpu,
        "scene probe",
        &shaders::light_probe(&wgsl_prelude()),
        Some(&pipeline_layout),
        [formula.entry_point()],
    )?;
    run_probe(gpu, &pipeline, &bind_group, items.len(), &output, size)
}

/// A probe's input buffer holding `bytes`.
fn probe_input(gpu: &Gpu, bytes: &[u8]) -> wgpu::Buffer {
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("probe inputs"),
            contents: bytes,
            usage: wgpu::BufferUsages::STORAGE,
        })
}

/// A probe's output buffer of `size` bytes, to be read back.
fn probe_output(gpu: &Gpu, size: u64) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("probe outputs"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Runs a probe kernel over `count` cases (workgroups of 64) and reads
/// back its `size`-byte `output` buffer as `T`s.
fn run_probe<T: bytemuck::Pod>(
    gpu: &Gpu,
    pipeline: &wgpu::ComputePipeline,
    bind_group: &wgpu::BindGroup,
    count: usize,
    output: &wgpu::Buffer,
    size: u64,
) -> Result<Vec<T>, GpuError> {
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups((count as u32).div_ceil(64), 1, 1);
    }
    gpu.queue.submit([encoder.finish()]);
    let bytes = read_buffer(gpu, output, size)?;
    Ok(bytemuck::pod_collect_to_vec(&bytes))
}
