//! Photometric units of glTF's KHR_lights_punctual to Tyndall's radiometric
//! ones.
//!
//! glTF gives point and spot lights in candela (lm/sr) and directional
//! lights in lux (lm/m²). Tyndall's lights are radiometric: intensity in
//! W/sr, irradiance in W/m² (docs/physics.md §3.1). A luminous efficacy converts
//! between them; we use the one Blender's glTF exporter uses in its
//! default "Standard" lighting mode (`PBR_WATTS_TO_LUMENS = 683` in
//! `io_scene_gltf2/blender/com/conversion.py`), so that a light exported
//! from Blender has the power it had in Blender:
//!
//! - point and spot lights of power `P` (W): Blender writes
//!   `I_v = P/(4π) · 683` cd; we read `I = I_v / 683 = P/(4π)` W/sr (a
//!   Blender spot is specified as if it were a point light, so the same
//!   formula holds and its cone does not concentrate the power);
//! - sun lights of strength `E` (W/m²): Blender writes `E_v = E · 683` lx;
//!   we read `E = E_v / 683` W/m².
//!
//! Blender's "Unitless" (COMPAT) and "Raw" modes write other numbers; they
//! cannot be told apart from the file, so such files render at another
//! brightness (docs/scene-format.md says so).

/// Luminous efficacy assumed for every light, lm/W (Blender's
/// `PBR_WATTS_TO_LUMENS`: the peak efficacy of photopic vision at 555 nm).
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Radiant intensity (W/sr) of a luminous intensity `candela` (lm/sr).
pub fn candela_to_watts_per_sr(candela: f32) -> f32 {
    candela / LUMENS_PER_WATT
}

/// Irradiance (W/m²) of an illuminance `lux` (lm/m²).
pub fn lux_to_watts_per_m2(lux: f32) -> f32 {
    lux / LUMENS_PER_WATT
}
