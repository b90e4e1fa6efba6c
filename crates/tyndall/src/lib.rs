//! Tyndall: a renderer for light in participating media.
//!
//! Beams from spotlights in fog, volumetric shadows and light coloured by
//! stained glass, after Bonnecaze & Stuart, "Ray Tracing in Participating
//! Media" — done correctly and fast. The physical conventions shared by
//! every module are those of docs/physics.md: radiance is linear RGB, fog has a
//! grey extinction `sigma_t` and an RGB albedo, transmittance is
//! `exp(−sigma_t·d)`, lights are given by intensity (W/sr), irradiance or
//! radiance. General media ([`media::volume`]) add RGB extinction and
//! non-uniform density for the path tracer.
//!
//! Modules follow pbrt's decomposition: [`camera`], [`shapes`], [`accel`],
//! [`lights`], [`materials`], [`glass`], [`media`], [`phase`], [`film`]
//! with its [`aov`]s and first-surface [`guides`],
//! the [`description`] of a scene that loaders produce, the runtime
//! [`scene`] built from it, the render [`settings`], the [`render()`] loop
//! and render [`parts`]. The integrators, samplers and visibility are the
//! renderer's internals (docs/architecture.md); [`testing`] exposes what
//! the integration tests need of them. Scene files are the `tyndall-load`
//! crate's; image files (PNG, OpenEXR, part files) and image metrics the
//! `tyndall-image` crate's.

pub mod accel;
pub mod aov;
pub mod camera;
pub mod color;
pub mod coverage;
pub mod description;
pub mod distribution;
pub mod exact_sum;
pub mod film;
pub mod footprint;
pub mod glass;
pub mod guides;
pub(crate) mod integrators;
pub mod light_groups;
pub mod lights;
pub mod limits;
pub mod materials;
pub mod media;
pub mod parts;
pub mod phase;
pub mod ray;
pub mod region;
pub mod render;
pub(crate) mod sampler;
pub mod sampling;
pub mod scene;
pub mod settings;
pub(crate) mod shadow_maps;
pub mod shapes;
pub mod texture;
pub(crate) mod visibility;

pub use color::Rgb;
pub use description::{DescError, SceneDesc};
pub use film::Image;
pub use render::{Render, RenderStats, render};
pub use scene::Scene;
pub use settings::{IntegratorKind, RenderSettings};
pub use visibility::RayCounts;

/// How the CPU's shadow maps choose and orient their faces, for
/// renderers that build the same maps (the GPU path).
pub mod shadow_map_layout {
    pub use crate::shadow_maps::{CUBE_FACES, is_narrow};
}

/// The ray march's constants, for renderers and benchmarks that march
/// the same way (the GPU path).
pub mod ray_march {
    pub use crate::integrators::MAX_GLASS_CROSSINGS;
    pub use crate::integrators::march::MAX_OPTICAL_DEPTH;
}

/// What the integration tests (crate `tyndall-tests`) need beyond the
/// library's API: one radiance estimate along a chosen ray, the light
/// tracer on its own, the shadow maps against shadow rays, the samplers.
/// Not for applications: these are the renderer's internals and may
/// change at any time.
#[doc(hidden)]
pub mod testing {
    pub use crate::integrators::light_tracer::{self, LightPaths, has_caustics};
    /// The Rust twins the GPU's WGSL functions are probed against.
    pub mod twins {
        pub use crate::integrators::lighting::twins::{
            direct_lighting, light_arriving, scattered_radiance,
        };
        pub use crate::integrators::march::twins::in_scattered as march_in_scattered;
    }
    pub use crate::integrators::march::interleaved_stratum;
    pub use crate::integrators::single::single_sample;
    pub use crate::integrators::{Integrator, LightSubpaths, PixelPosition};
    pub use crate::sampler::{PixelSampler, RandomStream};
    pub use crate::shadow_maps::{MapScene, ShadowMaps};
    pub use crate::visibility::Visibility;
}
