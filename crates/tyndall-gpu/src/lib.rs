//! Tyndall on the GPU (wgpu, WGSL): the paper's ray march of single
//! scattering (its §4.2, `tyndall::integrators::march`) as a compute
//! shader, headless, on any Vulkan device — a data-centre GPU or
//! lavapipe, Mesa's software Vulkan driver that CI uses.
//!
//! # Design
//!
//! - **Compute, not raster.** Every stage — the shadow maps (one
//!   invocation per texel), camera rays, the march along each pixel's ray,
//!   direct light on surfaces (one invocation per pixel and frame) — is a
//!   compute kernel (`shaders/maps.wgsl`, `shaders/march.wgsl`). The CPU
//!   march is a per-pixel loop; a compute kernel is that loop
//!   transcribed, so its estimator (lattice, jitter, interleaving strata,
//!   the budget of steps) is the CPU's step for step, and it runs without
//!   a window or render targets. A raster pass for primary visibility
//!   would need a second code path for reflections and glass, which
//!   follow the ray on from the first hit anyway; a rasterised shadow map
//!   keeps one depth per texel, where the coloured deep map needs every
//!   pane before the first opaque surface (a ray per texel finds them).
//! - **Visibility: the flat primitive list.** Camera and shadow rays test
//!   every primitive (spheres, quads, triangles) in a loop. The reference
//!   scenes have tens of primitives, so a BVH would cost more in upload
//!   and traversal state than it saves; its cost is linear in the
//!   primitive count, which a GPU BVH would make logarithmic for meshes.
//! - **Visibility: maps or rays, as on the CPU.** With
//!   [`GpuVisibility::Maps`] every light gets the CPU's deep coloured
//!   shadow map (`tyndall::shadow_maps`: same projections, texel rays,
//!   glass layers, percentage-closer filtering and bias), rendered on the
//!   GPU in two passes — depths and layer counts, offsets summed on the
//!   host, then the layers — and each march step or surface looks it up.
//!   With [`GpuVisibility::ShadowRays`] each lookup is an exact shadow
//!   ray instead. Either way the image converges to the CPU `march` image
//!   with the same `--visibility`.
//! - **One formula, two languages.** `shaders/formulas.wgsl` holds the
//!   physics (HG phase, spot profiles, glass tint under the filter and
//!   blend models, Beer–Lambert transmittance) once in WGSL, each
//!   function naming the Rust function it transcribes;
//!   [`formula_probe`] runs them on the GPU so tests compare both.
//! - **Accumulation.** Each frame adds one sample per pixel to a sum on
//!   the GPU with fresh random numbers (PCG hash of pixel, frame, seed):
//!   film position, the march's jitter inside the pixel's stratum, glossy
//!   directions. The mean converges to the CPU image's expectation.
//!
//! What a scene may hold: point, spot (all profiles) and directional
//! lights; opaque (Lambert + reflective layer), emissive, lamp-face and
//! thin-glass materials; homogeneous fog, everywhere or in a box; flat
//! shading. Area lights, dielectrics, heterogeneous volumes, smooth-shaded
//! (vertex-normal) meshes and textures are refused with
//! [`GpuError::Unsupported`] naming them.

pub mod device;
pub mod formula_probe;
mod maps;
pub mod march;
pub mod readback;
pub mod scene_buffers;
mod shaders;

pub use device::{AdapterSummary, Gpu, GpuError};
pub use march::{GpuMarch, GpuVisibility, MapsRebuilt, MarchSettings, Update, render};
