//! Tyndall: a renderer for light in participating media.
//!
//! Beams from spotlights in fog, volumetric shadows and light coloured by
//! stained glass, after Bonnecaze & Stuart, "Ray Tracing in Participating
//! Media" — done correctly and fast. The physical conventions shared by
//! every module are those of DESIGN §1: radiance is linear RGB, fog has a
//! grey extinction `sigma_t` and an RGB albedo, transmittance is
//! `exp(−sigma_t·d)`, lights are given by intensity (W/sr), irradiance or
//! radiance. General media ([`media::volume`]) add RGB extinction and
//! non-uniform density for the path tracer.
//!
//! Modules follow pbrt's decomposition: [`camera`], [`shapes`], [`accel`],
//! [`lights`], [`materials`], [`glass`], [`media`], [`phase`], [`sampler`],
//! [`sampling`], [`visibility`], [`integrators`], [`film`], [`scene`]
//! loading, the [`render()`] loop and render [`parts`]. Image files (PNG,
//! OpenEXR, part files) and image metrics are the `tyndall-image` crate's.

pub mod accel;
pub mod camera;
pub mod color;
pub mod exact_sum;
pub mod film;
pub mod glass;
pub mod integrators;
pub mod lights;
pub mod materials;
pub mod media;
pub mod parts;
pub mod phase;
pub mod ray;
pub mod region;
pub mod render;
pub mod sampler;
pub mod sampling;
pub mod scene;
pub mod shadow_maps;
pub mod shapes;
pub mod visibility;

pub use color::Rgb;
pub use film::Image;
pub use integrators::IntegratorKind;
pub use render::{Render, RenderSettings, RenderStats, render};
pub use scene::{Scene, SceneDescription, SceneError};
