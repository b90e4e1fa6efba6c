// The physics formulas of Tyndall's single scattering, in WGSL: one
// function per equation, each a transcription of the Rust function named
// in its comment (crates/tyndall/src). tests/formulas.rs evaluates every
// function here on the GPU and compares it with the Rust one.

const PI: f32 = 3.14159265358979;
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

// One sample's term of single scattering's multi-sample balance
// heuristic, f·T/(n·p_e + p_d): f eq. 1 at the sample, T the camera-side
// transmittance to it, n equiangular samples of density p_e and the
// distance sample's density p_d there
// (tyndall::integrators::single::single_sample).
fn single_sample(f: vec3<f32>, camera_transmittance: f32, n: f32, pdf_e: f32, pdf_d: f32) -> vec3<f32> {
    return f * (camera_transmittance / (n * pdf_e + pdf_d));
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

// A unit vector perpendicular to unit `n` and a third completing the
// frame (Duff et al. 2017, "Building an orthonormal basis, revisited";
// glam's Vec3::any_orthonormal_pair).
fn orthonormal_pair(n: vec3<f32>) -> array<vec3<f32>, 2> {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return array<vec3<f32>, 2>(
        vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        vec3<f32>(b, s + n.y * n.y * a, -n.y),
    );
}

// A unit direction uniform in solid angle within the cone of half-angle
// θmax (cosine `cos_max`) around unit `axis`, for u ∈ [0, 1)²
// (tyndall::sampling::uniform_cone); cos_max = −1 gives the whole sphere.
fn uniform_cone(axis: vec3<f32>, cos_max: f32, u: vec2<f32>) -> vec3<f32> {
    let cos_t = 1.0 - u.x * (1.0 - cos_max);
    let sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    let phi = 2.0 * PI * u.y;
    let frame = orthonormal_pair(axis);
    return normalize(frame[0] * (sin_t * cos(phi)) + frame[1] * (sin_t * sin(phi)) + axis * cos_t);
}

// The density of uniform_cone: 1 / (2π(1 − cos θmax)).
fn uniform_cone_pdf(cos_max: f32) -> f32 {
    return 1.0 / (2.0 * PI * (1.0 - cos_max));
}

// A rectangle (corner, orthonormal edge directions x and y, lengths
// width and height) seen from `o`, for sampling directions uniformly in
// its solid angle (Ureña, Fajardo & King 2013, "An Area-Preserving
// Parametrization for Spherical Rectangles";
// tyndall::lights::SphericalRectangle). `valid` is false when `o` lies in
// the rectangle's plane or it subtends no solid angle.
struct SphericalRectangle {
    origin: vec3<f32>,
    x: vec3<f32>,
    y: vec3<f32>,
    z: vec3<f32>,
    z0: f32,
    x0: f32,
    x1: f32,
    y0: f32,
    y1: f32,
    b0: f32,
    b1: f32,
    k: f32,
    // sr
    solid_angle: f32,
    valid: bool,
}

fn spherical_rectangle_new(corner: vec3<f32>, x: vec3<f32>, y: vec3<f32>, width: f32, height: f32, o: vec3<f32>) -> SphericalRectangle {
    var z = cross(x, y);
    let d = corner - o;
    var z0 = dot(d, z);
    if z0 > 0.0 {
        z = -z;
        z0 = -z0;
    }
    let x0 = dot(d, x);
    let y0 = dot(d, y);
    let x1 = x0 + width;
    let y1 = y0 + height;
    var s = SphericalRectangle(o, x, y, z, z0, x0, x1, y0, y1, 0.0, 0.0, 0.0, 0.0, false);
    if z0 > -1e-7 * (1.0 + length(d)) {
        return s;
    }
    // Normals of the four great-circle edges, in the local frame.
    let n0 = normalize(vec3<f32>(0.0, z0, -y0));
    let n1 = normalize(vec3<f32>(-z0, 0.0, x1));
    let n2 = normalize(vec3<f32>(0.0, -z0, y1));
    let n3 = normalize(vec3<f32>(z0, 0.0, -x0));
    let g0 = acos(clamp(-dot(n0, n1), -1.0, 1.0));
    let g1 = acos(clamp(-dot(n1, n2), -1.0, 1.0));
    let g2 = acos(clamp(-dot(n2, n3), -1.0, 1.0));
    let g3 = acos(clamp(-dot(n3, n0), -1.0, 1.0));
    s.k = 2.0 * PI - g2 - g3;
    s.solid_angle = g0 + g1 - s.k;
    s.b0 = n0.z;
    s.b1 = n2.z;
    // Positive and finite (a NaN fails both comparisons; no rectangle
    // subtends 4π).
    s.valid = s.solid_angle > 0.0 && s.solid_angle < 4.0 * PI;
    return s;
}

// A point of the rectangle uniform in solid angle from its origin, for
// u ∈ [0, 1)² (SphericalRectangle::sample).
fn spherical_rectangle_sample(s: SphericalRectangle, u: vec2<f32>) -> vec3<f32> {
    let au = u.x * s.solid_angle + s.k;
    let fu = (cos(au) * s.b0 - s.b1) / sin(au);
    let cu = clamp(sign_of(fu) / sqrt(fu * fu + s.b0 * s.b0), -1.0, 1.0);
    let xu = clamp(-(cu * s.z0) / sqrt(max(1.0 - cu * cu, 1e-12)), s.x0, s.x1);
    let d = sqrt(xu * xu + s.z0 * s.z0);
    let h0 = s.y0 / sqrt(d * d + s.y0 * s.y0);
    let h1 = s.y1 / sqrt(d * d + s.y1 * s.y1);
    let hv = h0 + u.y * (h1 - h0);
    let hv2 = hv * hv;
    var yv = s.y1;
    if hv2 < 1.0 - 1e-6 {
        yv = hv * d / sqrt(1.0 - hv2);
    }
    return s.origin + s.x * xu + s.y * clamp(yv, s.y0, s.y1) + s.z * s.z0;
}

// 1 with the sign of `v` (−1 for −0.0), as Rust's 1.0f32.copysign(v).
fn sign_of(v: f32) -> f32 {
    return select(1.0, -1.0, (bitcast<u32>(v) >> 31u) != 0u);
}

// A point of the triangle v0, v0 + e1, v0 + e2 uniform by area for
// u ∈ [0, 1)² (tyndall::shapes::Triangle::point).
fn triangle_point(v0: vec3<f32>, e1: vec3<f32>, e2: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let s = sqrt(u.x);
    return v0 + e1 * (s * (1.0 - u.y)) + e2 * (s * u.y);
}

// ---- a glossy layer's GGX lobe (tyndall::materials::Ggx) ----

// The GGX distribution at a microfacet normal of cosine cos_h:
// α²/(π·(cos²θ_h·(α² − 1) + 1)²).
fn ggx_distribution(alpha: f32, cos_h: f32) -> f32 {
    let a2 = alpha * alpha;
    let d = cos_h * cos_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// Smith's Λ for a direction of cosine cos (> 0): (√(1 + α²·tan²θ) − 1)/2.
fn ggx_lambda(alpha: f32, cos: f32) -> f32 {
    let tan2 = max(1.0 - cos * cos, 0.0) / (cos * cos);
    return 0.5 * (sqrt(1.0 + alpha * alpha * tan2) - 1.0);
}

// A direction towards the light for light leaving towards `outgoing` at
// `normal`, for u ∈ [0, 1)²: a visible normal from its spherical cap,
// `outgoing` reflected about it; the zero vector below the surface
// (Ggx::sample).
fn ggx_sample(alpha: f32, outgoing: vec3<f32>, normal: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let frame = orthonormal_pair(normal);
    let o = vec3<f32>(dot(outgoing, frame[0]), dot(outgoing, frame[1]), dot(outgoing, normal));
    let o_std = normalize(vec3<f32>(alpha * o.x, alpha * o.y, o.z));
    let phi = 2.0 * PI * u.x;
    let z = (1.0 - u.y) * (1.0 + o_std.z) - o_std.z;
    let sin_t = sqrt(clamp(1.0 - z * z, 0.0, 1.0));
    let h_std = vec3<f32>(sin_t * cos(phi), sin_t * sin(phi), z) + o_std;
    let h_raw = vec3<f32>(alpha * h_std.x, alpha * h_std.y, max(h_std.z, 0.0));
    if dot(h_raw, h_raw) <= 0.0 {
        return vec3<f32>(0.0);
    }
    let hl = normalize(h_raw);
    let h = frame[0] * hl.x + frame[1] * hl.y + normal * hl.z;
    let incident = 2.0 * dot(outgoing, h) * h - outgoing;
    if dot(incident, normal) > 0.0 {
        return incident;
    }
    return vec3<f32>(0.0);
}

// The single-scattering lobe's f·cos θ_i for reflectance 1:
// D(h)·G₂/(4·cos θ_o), 0 below the surface (Ggx::eval).
fn ggx_eval(alpha: f32, outgoing: vec3<f32>, normal: vec3<f32>, incident: vec3<f32>) -> f32 {
    let cos_o = dot(outgoing, normal);
    let cos_i = dot(incident, normal);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return 0.0;
    }
    let sum = outgoing + incident;
    if dot(sum, sum) <= 0.0 {
        return 0.0;
    }
    let h = normalize(sum);
    let g2 = 1.0 / (1.0 + ggx_lambda(alpha, cos_o) + ggx_lambda(alpha, cos_i));
    return ggx_distribution(alpha, dot(h, normal)) * g2 / (4.0 * cos_o);
}

// A sample's weight for reflectance 1, G₂/G₁(o) (Ggx::weight).
fn ggx_weight(alpha: f32, outgoing: vec3<f32>, normal: vec3<f32>, incident: vec3<f32>) -> f32 {
    let lo = ggx_lambda(alpha, max(dot(outgoing, normal), 1e-7));
    let li = ggx_lambda(alpha, max(dot(incident, normal), 1e-7));
    return (1.0 + lo) / (1.0 + lo + li);
}

// A layer's reflectance f with its multiple scattering restored, its
// single-scattering albedo e: f·(1 + f·(1 − e)/e)
// (tyndall::materials::compensated).
fn compensated(f: vec3<f32>, e: f32) -> vec3<f32> {
    return f * (vec3<f32>(1.0) + f * ((1.0 - e) / e));
}
