//! Integrators: how the radiance along a camera ray is estimated.
//!
//! [`volpath`] traces full paths with multiple scattering. The two
//! single-scattering integrators share the camera path
//! ([`Integrator::radiance`]): the ray is followed through thin glass,
//! dielectrics and specular reflections; on each
//! segment the in-scattered fog radiance is added (docs/physics.md §5.1),
//!
//! ```text
//! L = T(0, s_hit)·L_surface + ∫₀^{s_hit} T(0, s)·σs·Σ_lights L_in(x(s)) ds,
//! ```
//!
//! and surfaces are shaded with direct lighting. They differ in how they
//! estimate the integral: [`march`] by the paper's jittered fixed-step
//! Riemann sum, [`single`] by equiangular and distance sampling combined
//! with MIS. Both evaluate the integrand through `scattered_radiance`,
//! the paper's eq. 1 in one place.
//!
//! The modules: [`integrator`] (the dispatch), `camera_path` (the
//! single-scattering integrators' shared path), and what every integrator
//! shares, `lighting` (light sampling, eq. 1, connections, direct
//! lighting), `surfaces` (surface hits, solid dielectrics), `scatterer`
//! (a connection's vertex) and `path_radiance` (a sample's radiance and
//! its components).

mod camera_path;
pub mod integrator;
pub mod light_tracer;
pub(crate) mod lighting;
pub mod march;
pub(crate) mod path_radiance;
mod scatterer;
pub mod single;
mod surfaces;
pub mod volpath;

pub use integrator::Integrator;
pub use volpath::LightSubpaths;

// The pieces the integrators share, where `volpath` and the light tracer
// import them from (`super::…`).
pub(crate) use lighting::{
    MediumQuery, TRACKING_STREAM, light_arriving, lights_along, lights_at, media_transmittance,
    sample_light, scattered_light, surface_direct_lighting,
};
pub(crate) use scatterer::Scatterer;
pub use surfaces::MAX_GLASS_CROSSINGS;
pub(crate) use surfaces::{SolidDepth, SurfaceHit, refract_or_reflect};

/// The pixel a camera sample belongs to, for methods that correlate
/// neighbouring pixels (interleaved sampling).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelPosition {
    pub x: u32,
    pub y: u32,
}
