//! Render settings: how to render a scene — image size, sampling,
//! integrator and its parameters — as plain data.
//!
//! A leaf of the crate: scene descriptions carry settings and loaders fill
//! them, and nothing here depends on anything else in the crate (the
//! integrators implement what these settings name). The
//! ranges each setting accepts are checked here, once
//! ([`RenderSettings::check_ranges`]), for every loader and the API; the
//! checks that need the scene are in [`mod@crate::render`].

/// `max_depth` meaning "no limit".
pub const UNLIMITED_DEPTH: u32 = u32::MAX;

/// Default equiangular samples per light per camera ray (`single`).
pub const DEFAULT_VOLUME_SAMPLES: u32 = 8;

/// Largest accepted image side, in pixels.
pub const MAX_IMAGE_SIDE: u32 = 1 << 15;

/// Most samples per pixel accepted (2²⁰).
pub const MAX_SPP: u32 = 1 << 20;

/// How to render: image size, sampling and method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    pub seed: u64,
    /// Worker threads; `None` uses every core.
    pub threads: Option<usize>,
    pub integrator: IntegratorKind,
    /// March step length (scene units) for [`IntegratorKind::March`].
    pub step: f32,
    /// Equiangular samples per light per camera ray for
    /// [`IntegratorKind::Single`] (stratified along the ray).
    pub volume_samples: u32,
    /// Side of the interleaved-sampling tile for [`IntegratorKind::March`]
    /// (1: off).
    pub interleave: u32,
    /// Shadow rays or shadow maps.
    pub visibility: VisibilityMode,
    /// Most reflections followed from a camera ray by `march` and `single`
    /// (glass crossings do not count).
    pub max_bounces: u32,
    /// Most scattering events of a `volpath` path ([`UNLIMITED_DEPTH`]:
    /// no limit, Russian roulette ends paths).
    pub max_depth: u32,
    /// Exposure in stops applied when writing display images (PNG).
    pub exposure: f32,
    /// The estimators `volpath` combines (all by default; a subset is for
    /// checking and measuring them, see [`Strategies`]).
    pub strategies: Strategies,
    /// Also sum the first-surface guides (albedo, normal, depth,
    /// position: the AOVs and the denoiser's guides, module
    /// `crate::guides`) beside the radiance. They change no sample.
    pub guides: bool,
    /// Also sum the radiance's components (emission, direct, indirect,
    /// volume: `crate::aov::Component`) beside it. They change no sample.
    /// Not for renders that trace light paths (caustics).
    pub components: bool,
    /// Also sum the radiance of each light group (the scene's
    /// `crate::light_groups::LightGroups`) beside it. They change no
    /// sample. Not for renders that trace light paths (caustics).
    pub light_groups: bool,
    /// The samples per pixel the camera rays' cones are made for, over
    /// which textures are filtered: `max(1/8, 1/√n)` of a pixel
    /// ([`crate::footprint::camera_spread_scale`]). `None`: `spp`. A
    /// progressive view, looked at after every pass, gives 1.
    pub footprint_spp: Option<u32>,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 360,
            spp: 16,
            seed: 0,
            threads: None,
            integrator: IntegratorKind::Single,
            step: 0.1,
            volume_samples: DEFAULT_VOLUME_SAMPLES,
            interleave: 1,
            visibility: VisibilityMode::ShadowRays,
            max_bounces: 4,
            max_depth: UNLIMITED_DEPTH,
            exposure: 0.0,
            strategies: Strategies::ALL,
            guides: false,
            components: false,
            light_groups: false,
            footprint_spp: None,
        }
    }
}

/// Default shadow-map resolution (texels per side of each face).
pub const DEFAULT_MAP_RESOLUTION: u32 = 512;

/// How visibility towards lights is computed, as chosen by settings.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VisibilityMode {
    /// Exact: a shadow ray through the BVH per query.
    #[default]
    ShadowRays,
    /// Shadow and transmittance maps of `resolution`² texels per face.
    Maps { resolution: u32 },
}

impl VisibilityMode {
    pub fn name(&self) -> &'static str {
        match self {
            VisibilityMode::ShadowRays => "rays",
            VisibilityMode::Maps { .. } => "maps",
        }
    }
}

/// Most march steps one camera ray may take (`march`), counted once per
/// light (each step visits every light): settings whose longest fog
/// segment over the step, times the lights, exceeds it are refused up
/// front. At 8×8 pixels and 1 spp this bounds a render to about 8.4 M
/// light visits (about a second on one core).
pub const MAX_MARCH_STEPS: u64 = 1 << 17;

/// Most equiangular samples per light per camera ray.
pub const MAX_VOLUME_SAMPLES: u32 = 1024;

/// Widest interleaved-sampling tile, in pixels.
pub const MAX_INTERLEAVE: u32 = 16;

/// Shadow-map resolutions accepted, texels per side.
pub const MAP_RESOLUTIONS: std::ops::RangeInclusive<u32> = 16..=16384;

/// Exposures accepted, in stops.
pub const EXPOSURES: std::ops::RangeInclusive<f32> = -64.0..=64.0;

/// A setting out of its range: which one (by its name in scene files and
/// on the command line, with `_` for `-`) and why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct SettingError {
    pub setting: &'static str,
    pub message: String,
}

impl RenderSettings {
    /// Checks every setting against its range, in one place for every
    /// loader and the API.
    pub fn check_ranges(&self) -> Result<(), SettingError> {
        let fail = |setting: &'static str, message: String| Err(SettingError { setting, message });
        for (setting, v) in [("width", self.width), ("height", self.height)] {
            if !(1..=MAX_IMAGE_SIDE).contains(&v) {
                return fail(
                    setting,
                    format!("`{setting}` must be between 1 and {MAX_IMAGE_SIDE} pixels, got {v}"),
                );
            }
        }
        if self.spp == 0 {
            return fail("spp", "`spp` (samples per pixel) must be at least 1".into());
        }
        if self.spp > MAX_SPP {
            return fail(
                "spp",
                format!(
                    "`spp` (samples per pixel) must be at most {MAX_SPP}, got {}",
                    self.spp
                ),
            );
        }
        if self.max_depth == 0 {
            return fail(
                "max_depth",
                "`max_depth` must be at least 1 (1 = single scattering)".into(),
            );
        }
        if !(1..=MAX_VOLUME_SAMPLES).contains(&self.volume_samples) {
            return fail(
                "volume_samples",
                format!(
                    "`volume_samples` must be between 1 and {MAX_VOLUME_SAMPLES}, got {}",
                    self.volume_samples
                ),
            );
        }
        if !(1..=MAX_INTERLEAVE).contains(&self.interleave) {
            return fail(
                "interleave",
                format!(
                    "`interleave` must be a tile side between 1 and {MAX_INTERLEAVE} pixels, got {}",
                    self.interleave
                ),
            );
        }
        if let VisibilityMode::Maps { resolution } = self.visibility {
            check_map_resolution(resolution)?;
        }
        if !(self.step > 0.0 && self.step.is_finite()) {
            return fail(
                "step",
                format!("`step` must be a positive length, got {}", self.step),
            );
        }
        if !EXPOSURES.contains(&self.exposure) {
            return fail(
                "exposure",
                format!(
                    "`exposure` must be a number of stops in [−64, 64], got {}",
                    self.exposure
                ),
            );
        }
        if self.threads == Some(0) {
            return fail("threads", "`threads` must be at least 1".into());
        }
        Ok(())
    }
}

/// Checks a shadow-map resolution (texels per side) against
/// [`MAP_RESOLUTIONS`].
pub fn check_map_resolution(resolution: u32) -> Result<(), SettingError> {
    if MAP_RESOLUTIONS.contains(&resolution) {
        return Ok(());
    }
    Err(SettingError {
        setting: "shadow_map_resolution",
        message: format!(
            "`shadow_map_resolution` must be between {} and {} texels, got {resolution}",
            MAP_RESOLUTIONS.start(),
            MAP_RESOLUTIONS.end()
        ),
    })
}

/// The integrators, selectable by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorKind {
    /// The paper's ray march: fixed step, jittered start.
    March,
    /// Unbiased single scattering: equiangular + distance sampling, MIS.
    Single,
    /// Volumetric path tracing: multiple scattering, NEE with MIS.
    Volpath,
}

impl IntegratorKind {
    pub const ALL: [IntegratorKind; 3] = [
        IntegratorKind::March,
        IntegratorKind::Single,
        IntegratorKind::Volpath,
    ];

    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::March => "march",
            IntegratorKind::Single => "single",
            IntegratorKind::Volpath => "volpath",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The paper's figures use albedo 5 and 10; only the ray march accepts
    /// such non-physical fog (with a warning).
    pub fn accepts_non_physical_albedo(self) -> bool {
        matches!(self, IntegratorKind::March)
    }
}

/// The estimators `volpath` combines by the balance heuristic, each of
/// which can produce the last connection of a path to a light on its own.
/// A strategy that is off contributes nothing and its density leaves every
/// other strategy's weight, so any subset that can still produce every
/// path renders the same image (the tests render each alone against the
/// others, which checks that the weights of every path sum to one):
///
/// - surfaces: `surface_nee` (light sampling) or `surface_hits` (BSDF
///   sampling that hits an area light);
/// - fog and volume events: `medium_nee` (light sampling at free-flight
///   events), `medium_hits` (phase sampling that hits an area light),
///   `equiangular` (samples along each fog segment towards each light)
///   and `connections` (light-vertex connections, fog scenes with area
///   lights only).
///
/// Point, spot and directional lights are reached only by light sampling
/// (`surface_nee`, `medium_nee`) and `equiangular`; single scattering from
/// an area light not by `connections` alone (the camera is no connecting
/// vertex).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Strategies {
    pub surface_nee: bool,
    pub surface_hits: bool,
    pub medium_nee: bool,
    pub medium_hits: bool,
    pub equiangular: bool,
    /// Equiangular sampling towards area lights also on segments after
    /// the first scattering event (with `equiangular`; towards point and
    /// spot lights it always runs there). Off by default: on those
    /// segments NEE, phase sampling and the light-vertex connections
    /// already cover area lights, and the extra samples cost more time
    /// than they save error (docs/benchmarks.md).
    pub later_area_equiangular: bool,
    pub connections: bool,
    /// Next event estimation towards emitting media (from volume events
    /// and Lambertian surfaces), MIS-weighted against emission found
    /// by tracking.
    pub emission_nee: bool,
    /// Emission of media found by tracking along directions sampled at
    /// vertices that also ran `emission_nee`. (Along camera rays, and
    /// where NEE cannot reach, found emission always counts in full.)
    pub emission_hits: bool,
}

impl Strategies {
    /// Every strategy: the default.
    pub const ALL: Self = Self {
        surface_nee: true,
        surface_hits: true,
        medium_nee: true,
        medium_hits: true,
        equiangular: true,
        later_area_equiangular: false,
        connections: true,
        emission_nee: true,
        emission_hits: true,
    };

    /// No strategy; switch on the ones wanted.
    pub const NONE: Self = Self {
        surface_nee: false,
        surface_hits: false,
        medium_nee: false,
        medium_hits: false,
        equiangular: false,
        later_area_equiangular: false,
        connections: false,
        emission_nee: false,
        emission_hits: false,
    };
}

impl Default for Strategies {
    fn default() -> Self {
        Self::ALL
    }
}
