//! The WGSL sources, assembled from files: `formulas.wgsl` holds each
//! physics equation once and is prepended to every kernel that uses it.

const FORMULAS: &str = include_str!("shaders/formulas.wgsl");
const FORMULA_PROBE: &str = include_str!("shaders/formula_probe.wgsl");
const MARCH: &str = include_str!("shaders/march.wgsl");

/// The formula test kernels with the formulas they evaluate.
pub fn formula_probe() -> String {
    format!("{FORMULAS}\n{FORMULA_PROBE}")
}

/// The shadow-mapped ray march with the formulas it evaluates.
pub fn march() -> String {
    format!("{FORMULAS}\n{MARCH}")
}
