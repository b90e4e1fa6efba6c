//! Why a render could not start.

use crate::media::tracking::MAX_VOLUMES;
use crate::region::RegionError;
use crate::settings::{MAX_MARCH_STEPS, SettingError};

/// Why a render could not start.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum RenderError {
    #[error(transparent)]
    Setting(#[from] SettingError),
    #[error(
        "fog albedo {0} exceeds 1 in some channel: that is not physical, and the `{1}` integrator only accepts physical media (the `march` integrator accepts it)"
    )]
    NonPhysicalAlbedo(String, &'static str),
    #[error(
        "the scene has {0} volume(s) ([[media]]), which only the `volpath` integrator renders; `{1}` estimates homogeneous [fog] only: use --integrator volpath"
    )]
    VolumesNeedVolpath(usize, &'static str),
    #[error(
        "medium #{0} (in [[media]] order, counted from 0) emits light (`emission` or `temperature_grid`), which only the `volpath` integrator renders; `{1}` cannot: use --integrator volpath"
    )]
    EmissiveMediumNeedsVolpath(usize, &'static str),
    #[error("the scene has {0} volumes; at most {MAX_VOLUMES} are supported")]
    TooManyVolumes(usize),
    #[error(
        "march step {step} would take up to {steps:.3e} steps per ray over the longest fog segment ({length:.3e} units), each visiting {lights} light(s): at most {MAX_MARCH_STEPS} steps × lights are allowed, so use a step of at least {min_step:.3e}"
    )]
    MarchSteps {
        step: f32,
        length: f64,
        steps: f64,
        lights: usize,
        min_step: f64,
    },
    #[error(
        "the render would need about {needed} for its images and maps ({what}), more than the {limit} limit: lower the image size or the shadow-map resolution"
    )]
    Memory {
        needed: String,
        what: String,
        limit: String,
    },
    #[error("could not start the worker threads: {0}")]
    ThreadPool(String),
    #[error(transparent)]
    Region(#[from] RegionError),
    #[error("cannot resume: {0}")]
    Resume(String),
    #[error(
        "the radiance's components and light groups (the emission, direct, indirect, volume and light_groups AOVs) are not split for renders that trace light paths (`volpath` with a dielectric and a point or spot light: the caustics); the other AOVs are"
    )]
    ComponentsWithLightPaths,
    #[error(
        "the scene has alpha coverage (glTF alphaMode MASK or BLEND), which shadow maps do not see: use shadow rays (visibility = \"rays\", the default)"
    )]
    CoverageNeedsShadowRays,
}
