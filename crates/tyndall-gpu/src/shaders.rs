//! The WGSL sources, assembled from files: `formulas.wgsl` holds each
//! physics equation once and is prepended to every kernel that uses it.

const FORMULAS: &str = include_str!("shaders/formulas.wgsl");
const FORMULA_PROBE: &str = include_str!("shaders/formula_probe.wgsl");
const MARCH: &str = include_str!("shaders/march.wgsl");
const MAPS: &str = include_str!("shaders/maps.wgsl");

/// The formula test kernels with the formulas they evaluate.
pub fn formula_probe() -> String {
    format!("{FORMULAS}\n{FORMULA_PROBE}")
}

/// The ray march and the shadow-map kernels, with the formulas they
/// evaluate (one module: they share the scene's bindings).
pub fn march() -> String {
    format!("{FORMULAS}\n{MARCH}\n{MAPS}")
}
