//! The WGSL sources, assembled from files: `formulas.wgsl` holds each
//! physics equation once and is prepended to every kernel that uses it;
//! the march kernels are one WGSL module assembled from one file per
//! concept, after a prelude generated in Rust (`march::params`).

const FORMULAS: &str = include_str!("shaders/formulas.wgsl");
const FORMULA_PROBE: &str = include_str!("shaders/formula_probe.wgsl");
const LIGHT_PROBE: &str = include_str!("shaders/light_probe.wgsl");
const MAPS: &str = include_str!("shaders/maps.wgsl");

/// The modules of the march kernels, in the order they are assembled:
/// the scene's buffers and kinds, random numbers, shapes, the BVH,
/// visibility (ray offsets and shadow rays), the fog, the lights, the
/// ray march, unbiased single scattering, and the camera path with the
/// entry points.
pub const MARCH_MODULES: [(&str, &str); 10] = [
    ("scene.wgsl", include_str!("shaders/scene.wgsl")),
    ("rng.wgsl", include_str!("shaders/rng.wgsl")),
    ("shapes.wgsl", include_str!("shaders/shapes.wgsl")),
    ("bvh.wgsl", include_str!("shaders/bvh.wgsl")),
    ("visibility.wgsl", include_str!("shaders/visibility.wgsl")),
    ("fog.wgsl", include_str!("shaders/fog.wgsl")),
    ("lights.wgsl", include_str!("shaders/lights.wgsl")),
    ("march.wgsl", include_str!("shaders/march.wgsl")),
    ("single.wgsl", include_str!("shaders/single.wgsl")),
    ("camera.wgsl", include_str!("shaders/camera.wgsl")),
];

/// The formula test kernels with the formulas they evaluate.
pub fn formula_probe() -> String {
    format!("{FORMULAS}\n{FORMULA_PROBE}")
}

/// The ray march and the shadow-map kernels, with the formulas they
/// evaluate (one module: they share the scene's bindings), after
/// `prelude` (the constants and uniform block generated in Rust).
pub fn march(prelude: &str) -> String {
    let mut source = format!("{FORMULAS}\n{prelude}\n");
    for (_, module) in MARCH_MODULES {
        source.push_str(module);
        source.push('\n');
    }
    source.push_str(MAPS);
    source
}

/// The light test kernels after the march module (the same source, so
/// the very functions the march runs), after `prelude`.
pub fn light_probe(prelude: &str) -> String {
    format!("{}\n{LIGHT_PROBE}", march(prelude))
}
