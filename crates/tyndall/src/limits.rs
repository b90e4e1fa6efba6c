//! Limits on what a scene may ask for, so that hostile or corrupt input
//! is refused with a clear message instead of crashing, hanging or
//! exhausting memory. Every limit is listed in docs/scene-format.md
//! ("Limits"); the render-setting limits are in [`crate::settings`], the
//! file-size limits in `tyndall-load`.

/// Largest absolute value of any coordinate (positions, corners, centres,
/// radii, mesh vertices after placement). Shapes square products of
/// coordinates (a triangle's or quad's edge cross product has components
/// ~|x|², its squared length ~|x|⁴): at 10⁹ they stay within f32's range
/// (10³⁸), above about 4·10⁹ they overflow and a shape looks degenerate.
/// The BVH (obvhs) panicked on primitives about 10¹⁹ across; it was
/// checked against a linear scan with primitives from 10⁻³ to this size
/// (tests/hostile_input.rs).
pub const MAX_COORDINATE: f32 = 1e9;

/// Largest emitted quantity (radiance, intensity, power, irradiance, per
/// channel): above this, products with areas and solid angles overflow
/// f32 and samples turn infinite.
pub const MAX_EMISSION: f32 = 1e20;

/// Largest ratio between the largest and the smallest channel of a
/// medium's RGB extinction. Spectral tracking draws tentative collisions
/// at the largest channel's rate; once the path's throughput sits in the
/// weak channels, about this many of them pass per real event (issue 11:
/// `sigma_t = [1, 1e9, 1]` did not finish an 8×8 image; a channel of 0
/// beside non-zero ones never ends a walk through an unbounded medium).
pub const MAX_CHANNEL_RATIO: f32 = 1000.0;

/// Smallest non-zero extinction (per unit length) of a medium that fills
/// all space: its mean free path, 1/σt, must stay within
/// [`MAX_COORDINATE`]. Found by fuzzing: `sigma_t = 1e-30` with no `box`
/// put scattering events ~10³⁰ away, where squared distances overflow f32,
/// and every `volpath` sample was NaN.
pub const MIN_UNBOUNDED_EXTINCTION: f32 = 1.0 / MAX_COORDINATE;

/// Largest fog extinction (per unit length): with the largest albedo,
/// the scattering coefficient `albedo·sigma_t` stays far inside f32.
pub const MAX_FOG_EXTINCTION: f32 = 1e20;

/// Largest fog albedo. Above 1 it is not physical and only `march`
/// renders it (the paper's figures used up to 10); found by fuzzing,
/// `albedo = 3e38` made the scattered radiance infinite.
pub const MAX_FOG_ALBEDO: f32 = 100.0;

/// Checks fog's extinction: 0, or between [`MIN_UNBOUNDED_EXTINCTION`]
/// (found by fuzzing: a denormal `sigma_t = 1e-45` in a fog box made
/// `volpath` samples NaN) and [`MAX_FOG_EXTINCTION`].
pub fn check_fog_extinction(sigma_t: f32) -> Result<(), String> {
    let ok = sigma_t == 0.0 || (MIN_UNBOUNDED_EXTINCTION..=MAX_FOG_EXTINCTION).contains(&sigma_t);
    if !ok {
        return Err(format!(
            "fog `sigma_t` must be 0 or between {MIN_UNBOUNDED_EXTINCTION:e} and {MAX_FOG_EXTINCTION:e} per unit length, got {sigma_t}"
        ));
    }
    Ok(())
}

/// Checks fog's albedo against [`MAX_FOG_ALBEDO`].
pub fn check_fog_albedo(albedo: crate::color::Rgb) -> Result<(), String> {
    if !(albedo.is_finite() && albedo.max_element() <= MAX_FOG_ALBEDO) {
        return Err(format!(
            "fog `albedo` {:?} is too large: at most {MAX_FOG_ALBEDO} (above 1 it is not physical; the paper's figures used up to 10)",
            albedo.to_array()
        ));
    }
    Ok(())
}

/// Largest optical depth of a non-uniform medium's majorant across its
/// box: the largest extinction (sigma_t times the largest density) times
/// the box's diagonal. Tracking takes about this many tentative
/// collisions to cross the box where the density is far below its bound.
pub const MAX_MAJORANT_DEPTH: f32 = 1e5;

/// Most lights a scene may hold. `march` and the GPU path visit every
/// light at each march step, and `single` and `volpath` every area light
/// and sun at each vertex (point and spot lights they choose by the light
/// tree, [`crate::lights::LightTree`]), so a render's cost can grow with
/// their number; 1024 keeps an 8×8, 1 spp render within seconds.
pub const MAX_LIGHTS: usize = 1024;

/// A byte count for messages: "12.3 GiB", "640 KiB", "17 bytes".
pub fn describe_bytes(n: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if n < 1024 {
        return format!("{n} bytes");
    }
    let mut value = n as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.1} {}", UNITS[unit])
}

/// Checks that every coordinate of `v` is finite and within
/// [`MAX_COORDINATE`]; the error names `what`.
pub fn check_coordinates(what: &str, v: glam::Vec3) -> Result<(), String> {
    if !v.is_finite() {
        return Err(format!(
            "{what} must be finite numbers, got {:?}",
            v.to_array()
        ));
    }
    if v.abs().max_element() > MAX_COORDINATE {
        return Err(format!(
            "{what} {:?} is too far out: coordinates must be within ±{MAX_COORDINATE:e}",
            v.to_array()
        ));
    }
    Ok(())
}

/// Hottest blackbody temperature a medium may reach, kelvin: beyond it
/// the visible radiance grows only linearly (Rayleigh–Jeans) and no
/// flame comes near.
pub const MAX_TEMPERATURE_K: f32 = 1.0e5;

/// Checks that every channel of an emitted quantity is at most
/// [`MAX_EMISSION`].
pub fn check_emission(what: &str, c: crate::color::Rgb) -> Result<(), String> {
    if !(c.is_finite() && c.max_element() <= MAX_EMISSION) {
        return Err(format!(
            "{what} {:?} is too large: emitted quantities must be at most {MAX_EMISSION:e} per channel",
            c.to_array()
        ));
    }
    Ok(())
}

/// Checks a medium's RGB extinction against [`MAX_CHANNEL_RATIO`].
pub fn check_extinction_channels(sigma_t: crate::color::Rgb) -> Result<(), String> {
    let (lo, hi) = (sigma_t.min_element(), sigma_t.max_element());
    if hi > 0.0 && hi > lo * MAX_CHANNEL_RATIO {
        return Err(format!(
            "`sigma_t` {:?} has channels more than {MAX_CHANNEL_RATIO} times apart: tracking draws collisions at the largest channel's rate, so the weakest would take about {:.1e} null collisions per real one; keep the channels within a factor {MAX_CHANNEL_RATIO} (a channel of 0 only if all are 0)",
            sigma_t.to_array(),
            if lo > 0.0 { hi / lo } else { f32::INFINITY }
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_counts_read_well() {
        assert_eq!(describe_bytes(17), "17 bytes");
        assert_eq!(describe_bytes(3 << 30), "3.0 GiB");
    }
}
