// The physics formulas of Tyndall's single scattering, in WGSL: one
// function per equation, each a transcription of the Rust function named
// in its comment (crates/tyndall/src). tests/formulas.rs evaluates every
// function here on the GPU and compares it with the Rust one.

const INV_FOUR_PI: f32 = 0.07957747154594767;

// Spot profiles (tyndall::lights::SpotProfile).
const PROFILE_LINEAR: u32 = 0u;
const PROFILE_HARD: u32 = 1u;
const PROFILE_SMOOTH: u32 = 2u;

// Glass models (tyndall::glass::GlassModel).
const GLASS_FILTER: u32 = 0u;
const GLASS_BLEND: u32 = 1u;

// Henyey–Greenstein phase function (sr⁻¹) for the cosine between the
// propagation directions before and after scattering; isotropic 1/(4π)
// for g = 0 (tyndall::phase::PhaseFunction::eval).
fn phase_hg(g: f32, cos_theta: f32) -> f32 {
    if g == 0.0 {
        return INV_FOUR_PI;
    }
    let denom = 1.0 + g * g - 2.0 * g * cos_theta;
    return INV_FOUR_PI * (1.0 - g * g) / (denom * sqrt(max(denom, 0.0)));
}

// A spotlight's angular profile for the cosine of the angle off its axis:
// 0 outside the cutoff; linear in cos θ (the paper's eq. 5), hard, or a
// smoothstep between the cutoff and the inner cone
// (tyndall::lights::SpotLight::falloff).
fn spot_falloff(profile: u32, cos_cutoff: f32, cos_inner: f32, cos_theta: f32) -> f32 {
    if cos_theta <= cos_cutoff {
        return 0.0;
    }
    if profile == PROFILE_LINEAR {
        return 1.0 - (1.0 - cos_theta) / (1.0 - cos_cutoff);
    }
    if profile == PROFILE_HARD {
        return 1.0;
    }
    if cos_theta >= cos_inner {
        return 1.0;
    }
    let x = (cos_theta - cos_cutoff) / (cos_inner - cos_cutoff);
    return x * x * (3.0 - 2.0 * x);
}

// Per-channel transmittance of one crossing of a pane of colour c and
// opacity α under the filter model: (1 − α) + α·c
// (tyndall::glass::Glass::filter_transmittance).
fn glass_filter_transmittance(color: vec3<f32>, alpha: f32) -> vec3<f32> {
    return vec3<f32>(1.0 - alpha) + alpha * color;
}

// The tint of light of tint `before` after it crosses a pane: times the
// filter transmittance, or the paper's eq. 6 b₁ = b₀(1 − α) + c·α
// (tyndall::glass::GlassModel::tint_after).
fn glass_tint_after(model: u32, before: vec3<f32>, color: vec3<f32>, alpha: f32) -> vec3<f32> {
    if model == GLASS_FILTER {
        return before * glass_filter_transmittance(color, alpha);
    }
    return before * (1.0 - alpha) + color * alpha;
}

// Beer–Lambert transmittance exp(−σt·d) of homogeneous fog; exactly 1 for
// σt = 0 even over an infinite distance (tyndall::media::transmittance).
fn transmittance(sigma_t: f32, distance: f32) -> f32 {
    if sigma_t == 0.0 {
        return 1.0;
    }
    return exp(-sigma_t * distance);
}
