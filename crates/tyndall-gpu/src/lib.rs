//! Tyndall on the GPU (wgpu, WGSL): single scattering as a compute
//! shader — the paper's ray march (its §4.2, `tyndall::integrators::march`)
//! or unbiased interleaved equiangular sampling
//! (`tyndall::integrators::single`) — headless, on any Vulkan device — a
//! data-centre GPU or lavapipe, Mesa's software Vulkan driver that CI uses.
//!
//! # Design
//!
//! - **Compute, not raster.** Every stage — the shadow maps (one
//!   invocation per texel), camera rays, the march along each pixel's ray,
//!   direct light on surfaces (one invocation per pixel and frame) — is a
//!   compute kernel (`shaders/maps.wgsl` and the march modules, `shaders.rs`). The CPU
//!   march is a per-pixel loop; a compute kernel is that loop
//!   transcribed, so its estimator (lattice, jitter, interleaving strata,
//!   the budget of steps) is the CPU's step for step, and it runs without
//!   a window or render targets. A raster pass for primary visibility
//!   would need a second code path for reflections and glass, which
//!   follow the ray on from the first hit anyway; a rasterised shadow map
//!   keeps one depth per texel, where the coloured deep map needs every
//!   pane before the first opaque surface (a ray per texel finds them).
//! - **Primary visibility: a GPU BVH.** Camera, reflection, shadow and
//!   map-texel rays all walk one binary BVH (`bvh.rs`: built on the host
//!   by obvhs, as the CPU's, and flattened depth first with skip links,
//!   so the walk needs no stack). Rasterisation would serve only the
//!   camera's first hit; the tree serves every ray and keeps meshes at
//!   about log N box tests a ray. On the demo (52 primitives) it took a
//!   frame of the 4×4-shared 64-step march from 101 to 80 ms and its
//!   shadow maps from 1.1 s to 0.3 s on lavapipe (320×180,
//!   docs/benchmarks.md), against the flat list it replaced.
//! - **Visibility: maps or rays, as on the CPU.** With
//!   [`GpuVisibility::Maps`] every light gets the CPU's deep coloured
//!   shadow map (`tyndall::shadow_maps`: same projections, texel rays,
//!   glass layers, percentage-closer filtering and bias), rendered on the
//!   GPU in two passes — each texel's depth and its span of the layer
//!   array, taken from an atomic counter, then the layers, traced again
//!   only for texels that see glass — with nothing between them but a
//!   4-byte read of the counter (the array grows when it must), and each
//!   march step or surface looks it up.
//!   With [`GpuVisibility::ShadowRays`] each lookup is an exact shadow
//!   ray instead. Either way the image converges to the CPU `march` image
//!   with the same `--visibility`.
//! - **One formula, two languages.** `shaders/formulas.wgsl` holds the
//!   physics (HG phase, spot profiles, glass tint under the filter and
//!   blend models, Beer–Lambert transmittance, the samplers) once in WGSL, each
//!   function naming the Rust function it transcribes;
//!   [`formula_probe`] runs them on the GPU so tests compare both.
//! - **Two estimators, one camera path.** [`InScattering`] picks how the
//!   fog segment of each camera ray (up to its first surface, then past
//!   glass and reflections) gathers in-scattered light: the march's
//!   jittered Riemann sum, or the CPU `single`'s estimator transcribed —
//!   per light, `n` stratified equiangular samples (Kulla & Fajardo 2012)
//!   over its reach (a spot's cone, clipped as on the CPU; none for a
//!   sun, which has no emitting point) plus the ray's one distance sample,
//!   combined by the balance heuristic. The GPU uses the same MIS as the
//!   CPU, so each frame is an unbiased estimate of the CPU `single`
//!   image's expectation. Both estimators evaluate eq. 1 through one
//!   function (`scattered_radiance` in `lights.wgsl`) with the same
//!   visibility (maps or rays) and formulas, and the surfaces are lit by
//!   the same code. The samplers (`equiangular_*`, `exponential_*`) are
//!   transcribed once, in `formulas.wgsl`, and probed against
//!   `tyndall::sampling`.
//! - **Interleaved, still unbiased.** The equiangular offset `u` of a
//!   pixel lies in its stratum of the `interleave²` strata of the pixel
//!   tile (Keller & Heidrich 2001; the march's Bayer order), jittered,
//!   then shifted modulo 1 by a per-frame, per-light offset from the
//!   golden-ratio sequence started at a random point. Within a frame
//!   neighbouring pixels share out the light's angle; over frames a pixel's
//!   offsets spread evenly; and each offset is uniform on [0, 1) in every
//!   pixel, so no pixel is biased towards its stratum (a fixed stratum per
//!   pixel, as the march has, would bias an unbiased estimator pixel by
//!   pixel). The CPU `single` does not interleave; the GPU images match it
//!   pixel for pixel within noise.
//! - **The march's tile shares out its lattice.** With an `n × n` tile
//!   the march's pixel of stratum `s` keeps the CPU's jitter in stratum
//!   `s` of `n²` and evaluates only the lattice cells `k ≡ r (mod n²)`,
//!   each weighted `n²·h`, where `r = (s + frame + ρ) mod n²` (ρ random
//!   per seed): in a frame the tile's pixels take every residue once, over
//!   `n²` frames a pixel does, and in any frame `r` is uniform, so each
//!   pixel's expectation is the CPU march's with the same step and
//!   interleave, at `1/n²` of the lattice per pixel and frame (Keller &
//!   Heidrich 2001; Tóth & Umenhoffer 2009 use it for real-time shafts).
//!   What a young image lacks, the viewer's display gets back from the
//!   tile: [`GpuMarch::display_image`] averages each pixel's in-scattered
//!   light over the `n × n` window around it, over the pixels whose mean
//!   first-hit depth is within 5 % of its own (Keller & Heidrich's
//!   discontinuity buffer), until `(n²)²` frames are summed; files and
//!   [`GpuMarch::image`] always hold the unfiltered mean.
//! - **Accumulation.** Each frame adds one sample per pixel to a sum on
//!   the GPU with fresh random numbers: the film position and the first
//!   in-scattering number (the march's jitter inside the pixel's stratum,
//!   or `single`'s distance sample) are frame f's point of the R₃
//!   quasirandom sequence (Roberts 2018) under a random rotation per
//!   pixel, so a pixel's frames are stratified as the CPU's Sobol samples
//!   are; later dimensions (later segments, glossy directions) are a PCG
//!   hash of pixel, frame and seed (`single`'s equiangular offsets are
//!   stratified over frames by their own golden-ratio rotation). Each
//!   frame's sample is uniform, so the mean converges to the CPU image's
//!   expectation. Against PCG in every dimension this cut fig. 3's noise
//!   between two 16-frame renders (`tests/images.rs`) from 4.1·10⁻⁵ to
//!   5.4·10⁻⁶ relMSE (march) and from 4.2·10⁻⁵ to 5.7·10⁻⁶ (`single`);
//!   the CPU's is still ~10⁻⁷, where the Sobol sequence stratifies a
//!   sample's first 24 dimensions.
//!
//! - **Every light kind, sampled as on the CPU.** Point, spot (all
//!   profiles) and directional lights, and the area lights: quads,
//!   spheres and emissive meshes (every emissive shape). A march step or
//!   equiangular sample connects to a point of an area light uniform by
//!   area (a mesh picks its triangle from its cumulative area table by
//!   binary search), surfaces to a point uniform in the solid angle of a
//!   rectangle (Ureña, Fajardo & King 2013) or of the cone a sphere
//!   subtends — the CPU's `Light::sample_point` and `sample_li`,
//!   transcribed in the march modules and `formulas.wgsl`. Area lights have no
//!   shadow map on either side: with maps on they keep shadow rays.
//!
//! What a scene may hold besides: opaque (Lambert + reflective layer),
//! emissive, lamp-face and thin-glass materials; homogeneous fog,
//! everywhere or in a box; flat shading. Dielectrics, heterogeneous
//! volumes, smooth-shaded (vertex-normal) meshes and textures are refused
//! with [`GpuError::Unsupported`] naming them.

mod bvh;
pub mod device;
pub mod formula_probe;
mod maps;
pub mod march;
pub mod readback;
pub mod scene_buffers;
mod shaders;

pub use device::{AdapterSummary, Gpu, GpuError};
pub use march::{
    GpuMarch, GpuVisibility, InScattering, MapsRebuilt, MarchSettings, Update, render,
};
