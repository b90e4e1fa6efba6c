//! Double scattering in an infinite medium against quadrature.
//!
//! An isotropic point light of intensity I (W/sr) in homogeneous fog that
//! fills all space, isotropic phase, nothing else. With
//! `G(r) = e^{−σt·r}/r²` the uncollided fluence is `φ₀ = I·G(r)`; light
//! scattered once has emission `σs·φ₀/4π` per unit volume and solid
//! angle, so its fluence is the convolution
//! `φ₁(r) = σs·I/(4π) · (G ⊛ G)(r)`, and for radial functions
//!
//! `(G ⊛ G)(r) = (2π/r) ∫₀^∞ (e^{−σt·s}/s)·[E₁(σt|r − s|) − E₁(σt(r + s))] ds`
//!
//! (the inner radial integral `∫ u·G(u) du` over `|r − s| ≤ u ≤ r + s` is
//! a difference of exponential integrals). Along a camera ray `x(t)` the
//! radiance of light scattered exactly once and exactly twice is
//! `L₁ = ∫ e^{−σt·t}·σs/(4π)·φ₀(|x(t)|) dt` and
//! `L₂ = ∫ e^{−σt·t}·σs/(4π)·φ₁(|x(t)|) dt`. Nothing here shares code
//! with the renderer: it checks volpath's second fog events (free flight
//! after a phase-sampled turn, NEE and equiangular samples on the second
//! segment, and their MIS) against numbers computed independently.
mod common;

use common::scene;
use glam::Vec3;
use std::f64::consts::PI;
use tyndall::IntegratorKind;
use tyndall::ray::Ray;

const SIGMA_T: f64 = 1.0;
const ALBEDO: f64 = 0.8;
const INTENSITY: f64 = 10.0;
/// The camera ray passes this far from the light.
const MISS_DISTANCE: f64 = 1.0;
/// The camera stands this far before the light along the ray.
const LEAD: f64 = 2.0;

/// The exponential integral `E₁(x) = ∫₁^∞ e^{−x·t}/t dt` for x > 0: its
/// power series below 1, a continued fraction (modified Lentz) above.
fn e1(x: f64) -> f64 {
    const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;
    if x <= 1.0 {
        // E₁(x) = −γ − ln x − Σ_{k≥1} (−x)^k / (k·k!)
        let mut sum = 0.0;
        let mut term = 1.0;
        for k in 1..60 {
            term *= -x / k as f64;
            sum += term / k as f64;
            if term.abs() < 1e-18 {
                break;
            }
        }
        -EULER_GAMMA - x.ln() - sum
    } else {
        // E₁(x) = e^{−x} · 1/(x + 1 − 1²/(x + 3 − 2²/(x + 5 − …)))
        let tiny = 1e-300;
        let mut b = x + 1.0;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..200 {
            let a = -((i * i) as f64);
            b += 2.0;
            d = 1.0 / (a * d + b);
            c = b + a / c;
            let delta = c * d;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        h * (-x).exp()
    }
}

/// Composite Simpson's rule of `f` over `[0, 1]` with `n` (even) intervals.
fn simpson01(f: impl Fn(f64) -> f64, n: usize) -> f64 {
    let h = 1.0 / n as f64;
    let mut s = f(0.0) + f(1.0);
    for i in 1..n {
        s += f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

/// `(G ⊛ G)(r)`. The integrand has a logarithmic singularity at s = r and
/// tends to a finite limit at s = 0; the substitutions `r − s = r·v³` and
/// `s − r = L·v³` (the tail cut where e^{−σt·s} < e^{−40}) make both parts
/// smooth enough for Simpson's rule.
fn g_conv_g(r: f64) -> f64 {
    let integrand = |s: f64| {
        if s <= 0.0 {
            // The limit s → 0: (1/s)·2s·σt·(e^{−σt·r}/(σt·r)) = 2e^{−σt·r}/r.
            return 2.0 * (-SIGMA_T * r).exp() / r;
        }
        let near = (SIGMA_T * (r - s).abs()).max(1e-300);
        (-SIGMA_T * s).exp() / s * (e1(near) - e1(SIGMA_T * (r + s)))
    };
    let n = 400;
    let inner = simpson01(
        |v| {
            if v == 0.0 {
                return 0.0; // the log singularity times 3r·v² vanishes
            }
            integrand(r - r * v * v * v) * 3.0 * r * v * v
        },
        n,
    );
    let tail = 40.0 / SIGMA_T;
    let outer = simpson01(
        |v| {
            if v == 0.0 {
                return 0.0;
            }
            integrand(r + tail * v * v * v) * 3.0 * tail * v * v
        },
        n,
    );
    2.0 * PI / r * (inner + outer)
}

/// `(L₁, L₂)` along the camera ray: quadrature over t, with x(t) at
/// distance `sqrt(h² + (t − LEAD)²)` from the light.
fn expected() -> (f64, f64) {
    let sigma_s = ALBEDO * SIGMA_T;
    let distance = |t: f64| (MISS_DISTANCE * MISS_DISTANCE + (t - LEAD) * (t - LEAD)).sqrt();
    let g = |r: f64| (-SIGMA_T * r).exp() / (r * r);
    let t_max = 40.0 / SIGMA_T;
    // t = t_max·v² puts more nodes near the camera and the light.
    let over_t =
        |f: &dyn Fn(f64) -> f64, n: usize| simpson01(|v| f(t_max * v * v) * 2.0 * t_max * v, n);
    let l1 = over_t(
        &|t| (-SIGMA_T * t).exp() * sigma_s / (4.0 * PI) * INTENSITY * g(distance(t)),
        4000,
    );
    let l2 = over_t(
        &|t| {
            let phi1 = sigma_s * INTENSITY / (4.0 * PI) * g_conv_g(distance(t));
            (-SIGMA_T * t).exp() * sigma_s / (4.0 * PI) * phi1
        },
        600,
    );
    (l1, l2)
}

/// The quadrature itself against a case it can be checked on: E₁ against
/// tabulated values, and `G ⊛ G` against the identity
/// `∫ (G ⊛ G) dV = (∫ G dV)² = (4π/σt)²`.
#[test]
fn quadrature_checks_itself() {
    // Abramowitz & Stegun table 5.1.
    for (x, value) in [
        (0.5, 0.559_773_594_8),
        (1.0, 0.219_383_934_4),
        (2.0, 0.048_900_510_7),
    ] {
        assert!((e1(x) - value).abs() < 1e-9, "E1({x}) = {}", e1(x));
    }
    // ∫ 4π r² (G ⊛ G)(r) dr over r = 40·v² (Simpson).
    let total = simpson01(
        |v| {
            let r = 40.0 * v * v;
            if r == 0.0 {
                return 0.0;
            }
            4.0 * PI * r * r * g_conv_g(r) * 80.0 * v
        },
        800,
    );
    let exact = (4.0 * PI / SIGMA_T).powi(2);
    assert!(
        (total / exact - 1.0).abs() < 2e-3,
        "∫ G⊛G = {total}, expected {exact}"
    );
}

#[test]
fn volpath_double_scattering_matches_quadrature() {
    let desc = scene(&format!(
        r#"
        [camera]
        position = [0, {MISS_DISTANCE}, {lead}]
        look_at = [0, {MISS_DISTANCE}, 0]
        up = [0, 1, 0]
        fov_y_deg = 1
        [fog]
        sigma_t = {SIGMA_T}
        albedo = {ALBEDO}
        g = 0
        [[lights]]
        type = "point"
        position = [0, 0, 0]
        intensity = {INTENSITY}
        "#,
        lead = -LEAD,
    ));
    let (l1, l2) = expected();
    assert!(l2 > 0.2 * l1, "the test needs double scattering to matter");
    let ray = Ray::new(Vec3::new(0.0, MISS_DISTANCE as f32, -LEAD as f32), Vec3::Z);
    // Samples: 2²⁰ paths put the standard error of L₁ + L₂ at ~0.4 % of
    // L₂ (second events near the light are the variance), so the 5σ
    // bound resolves errors of ~2 % in double scattering.
    for (max_depth, expected, n) in [(1, l1, 4096), (2, l1 + l2, 1 << 20)] {
        let mut settings = desc.settings;
        settings.integrator = IntegratorKind::Volpath;
        settings.max_depth = max_depth;
        let (mean, stderr) = common::estimate_ray_with(&desc, settings, ray, n);
        let err = (mean.x as f64 - expected).abs();
        assert!(
            err <= 5.0 * stderr.x as f64,
            "max_depth {max_depth}: {} ± {} vs quadrature {expected} (L1 {l1}, L2 {l2})",
            mean.x,
            stderr.x
        );
    }
}
