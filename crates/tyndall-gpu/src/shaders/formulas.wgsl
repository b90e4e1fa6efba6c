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

// ---- sampling distances along a ray (tyndall::sampling) ----

// 1 − e^{−x} for x ≥ 0 (−expm1(−x)), accurate for small x where
// 1 − exp(−x) cancels: its Taylor series below 0.1 (the first term left
// out, x⁶/720, is 1.4e-8 of the result at most).
fn one_minus_exp_neg(x: f32) -> f32 {
    if x < 0.1 {
        return x * (1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0 - x / 120.0))));
    }
    return 1.0 - exp(-x);
}

// ln(1 + y) for y > −1 (ln_1p), accurate for small |y| where 1 + y
// rounds: its Taylor series below 0.01 (the first term left out, y⁶/6,
// is 2e-11 of the result at most).
fn ln_one_plus(y: f32) -> f32 {
    if abs(y) < 0.01 {
        return y * (1.0 - y * (0.5 - y * (1.0 / 3.0 - y * (0.25 - y * 0.2))));
    }
    return log(1.0 + y);
}

// tyndall::sampling::MIN_EQUIANGULAR_DISTANCE.
const MIN_EQUIANGULAR_DISTANCE: f32 = 1e-5;

// Equiangular sampling (Kulla & Fajardo 2012) of t ∈ [a, b] on the ray
// o + t·ω for an emitter at y: Δ = (y − o)·ω is the emitter's foot on the
// ray, D ≥ MIN_EQUIANGULAR_DISTANCE its distance from the ray, θ the
// angle seen from y, uniform between θa = atan((a − Δ)/D) and θb; the
// density is D / ((θb − θa)(D² + (t − Δ)²))
// (tyndall::sampling::EquiangularSampler). `valid` is false for an
// empty interval (the Rust `new` returns None).
struct Equiangular {
    delta: f32,
    distance: f32,
    theta_a: f32,
    theta_b: f32,
    a: f32,
    b: f32,
    valid: bool,
}

fn equiangular_new(origin: vec3<f32>, direction: vec3<f32>, y: vec3<f32>, a: f32, b: f32) -> Equiangular {
    if !(a < b) {
        return Equiangular(0.0, 1.0, 0.0, 0.0, a, b, false);
    }
    let delta = dot(y - origin, direction);
    let distance = max(length(y - (origin + direction * delta)), MIN_EQUIANGULAR_DISTANCE);
    // atan2(x, D) = atan(x/D) for D > 0, without x/D overflowing when b
    // stands for ∞ (a camera ray that leaves the scene).
    let theta_a = atan2(a - delta, distance);
    let theta_b = atan2(b - delta, distance);
    return Equiangular(delta, distance, theta_a, theta_b, a, b, theta_b > theta_a);
}

// The distance for u ∈ [0, 1) (EquiangularSampler::sample).
fn equiangular_sample(s: Equiangular, u: f32) -> f32 {
    let theta = s.theta_a + u * (s.theta_b - s.theta_a);
    return clamp(s.delta + s.distance * tan(theta), s.a, s.b);
}

// The density at t, 0 outside [a, b] or for an empty sampler
// (EquiangularSampler::pdf).
fn equiangular_pdf(s: Equiangular, t: f32) -> f32 {
    if !s.valid || t < s.a || t > s.b {
        return 0.0;
    }
    let x = t - s.delta;
    return s.distance / ((s.theta_b - s.theta_a) * (s.distance * s.distance + x * x));
}

// Distance sampling of t ∈ [a, b] proportionally to the transmittance
// from a: density σ·e^{−σ(t−a)}/m with m = 1 − e^{−σ(b−a)}; b may be
// INFINITE (tyndall::sampling::ExponentialSampler). `valid` is false for
// σ ≤ 0 or an empty interval.
struct Exponential {
    sigma_t: f32,
    a: f32,
    b: f32,
    mass: f32,
    valid: bool,
}

fn exponential_new(sigma_t: f32, a: f32, b: f32) -> Exponential {
    if !(sigma_t > 0.0 && a < b) {
        return Exponential(sigma_t, a, b, 0.0, false);
    }
    // Past σ(b − a) = 88, 1 − e^{−σ(b−a)} is 1 in f32; the cap keeps the
    // product finite when b stands for ∞.
    let mass = one_minus_exp_neg(sigma_t * min(b - a, 88.0 / sigma_t));
    return Exponential(sigma_t, a, b, mass, mass > 0.0);
}

// The distance for u ∈ [0, 1) (ExponentialSampler::sample).
fn exponential_sample(s: Exponential, u: f32) -> f32 {
    return clamp(s.a - ln_one_plus(-u * s.mass) / s.sigma_t, s.a, s.b);
}

// The density at t, 0 outside [a, b] or for an empty sampler
// (ExponentialSampler::pdf).
fn exponential_pdf(s: Exponential, t: f32) -> f32 {
    if !s.valid || t < s.a || t > s.b {
        return 0.0;
    }
    return s.sigma_t * exp(-s.sigma_t * (t - s.a)) / s.mass;
}
