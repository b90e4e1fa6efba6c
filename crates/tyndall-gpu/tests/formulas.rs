//! One formula, two languages (issue 14): every physics function of
//! `shaders/formulas.wgsl` is evaluated by a compute shader on many inputs
//! and compared with the Rust function it transcribes.
//!
//! Tolerances follow from f32 rounding (ε = 2⁻²³): both sides round each
//! operation (WGSL allows 2.5 ULP for a division, `exp` 3 + 2|x| ULP, and
//! may fuse a multiply-add), so the two results differ by at most the sum
//! of both sides' error bounds, stated per test.

mod support;

use glam::{Vec2, Vec3};
use tyndall::color::Rgb;
use tyndall::glass::{Glass, GlassModel};
use tyndall::lights::{QuadLight, SpotLight, SpotProfile};
use tyndall::media::transmittance;
use tyndall::phase::PhaseFunction;
use tyndall::ray::Ray;
use tyndall::sampling::{EquiangularSampler, ExponentialSampler, uniform_cone, uniform_cone_pdf};
use tyndall::shapes::Quad;
use tyndall::testing::single_sample;
use tyndall_gpu::formula_probe::{Formula, evaluate};

const EPS: f32 = f32::EPSILON;

/// WGSL's bound on `atan2`'s error: 4096 ULP.
const ATAN_ULP: f32 = 4096.0;

/// WGSL's bound on `sin` and `cos` inside [−π, π]: absolute 2⁻¹¹ (`tan`
/// inherits its bound from `sin(x)/cos(x)`).
const SIN_COS_ABSOLUTE: f32 = 1.0 / 2048.0;

/// The stand-in for an infinite distance on the GPU (`INFINITE` of
/// `march.wgsl`).
const INFINITE: f32 = 3.0e38;

/// A deterministic spread of numbers in [0, 1): the golden-ratio sequence.
fn spread(i: usize) -> f32 {
    (i as f64 * 0.618_033_988_749_895).fract() as f32
}

#[test]
fn hg_phase_matches_rust() {
    let Some(gpu) = support::gpu_or_skip("hg_phase_matches_rust") else {
        return;
    };
    let mut items = Vec::new();
    for gi in 0..37 {
        let g = -0.9 + 1.8 * gi as f32 / 36.0;
        for ci in 0..=200 {
            let cos = -1.0 + 2.0 * ci as f32 / 200.0;
            items.push([[g, cos, 0.0, 0.0], [0.0; 4]]);
        }
    }
    let out = evaluate(&gpu, Formula::Phase, &items).expect("GPU evaluation");
    for (item, o) in items.iter().zip(&out) {
        let (g, cos) = (item[0][0], item[0][1]);
        let rust = PhaseFunction::from_asymmetry(g).eval(cos);
        // The denominator d = 1 + g² − 2g·cos is rounded three times with
        // terms of size S = 1 + g² + 2|g·cos|: relative error 3ε·S/d, which
        // d^{3/2} multiplies by 1.5; about 10ε more for the sqrt, products
        // and division. Two implementations: twice that.
        let d = 1.0 + g * g - 2.0 * g * cos;
        let s = 1.0 + g * g + 2.0 * (g * cos).abs();
        let tolerance = 2.0 * (4.5 * EPS * s / d + 10.0 * EPS) * rust;
        assert!(
            (o[0] - rust).abs() <= tolerance,
            "g = {g}, cos θ = {cos}: GPU {} vs Rust {rust} (tolerance {tolerance})",
            o[0]
        );
    }
}

#[test]
fn spot_profiles_match_rust() {
    let Some(gpu) = support::gpu_or_skip("spot_profiles_match_rust") else {
        return;
    };
    let mut items = Vec::new();
    let mut spots = Vec::new();
    for (p, profile_code) in [(0usize, 0.0f32), (1, 1.0), (2, 2.0)] {
        for cutoff_deg in [5.0f32, 15.0, 30.0, 45.0, 60.0, 89.0] {
            let cos_cutoff = cutoff_deg.to_radians().cos();
            let cos_inner = (0.5 * cutoff_deg).to_radians().cos();
            let profile = [
                SpotProfile::Linear,
                SpotProfile::Hard,
                SpotProfile::Smooth { cos_inner },
            ][p];
            let spot = SpotLight {
                gobo: None,
                luminaire: None,
                position: Vec3::ZERO,
                direction: -Vec3::Y,
                cos_cutoff,
                profile,
                intensity: Vec3::ONE,
            };
            for i in 0..400 {
                // Angles from the axis out to 1.2× the cutoff, plus the
                // exact cutoff and inner cosines (the branches' edges).
                let cos = match i {
                    0 => cos_cutoff,
                    1 => cos_inner,
                    _ => (1.2 * cutoff_deg * spread(i)).to_radians().cos(),
                };
                items.push([[profile_code, cos_cutoff, cos_inner, cos], [0.0; 4]]);
                spots.push((spot.clone(), cos));
            }
        }
    }
    let out = evaluate(&gpu, Formula::SpotFalloff, &items).expect("GPU evaluation");
    for ((spot, cos), o) in spots.iter().zip(&out) {
        let rust = spot.falloff(*cos);
        // Values in [0, 1]: a quotient of two differences (≤ 4.5ε
        // relative), then at most a smoothstep (slope ≤ 1.5) and a
        // subtraction: ≤ 10ε absolute per side, 20ε for two; the branch
        // tests are exact comparisons of the same numbers.
        let tolerance = 20.0 * EPS;
        assert!(
            (o[0] - rust).abs() <= tolerance,
            "{:?} cutoff {}: cos θ = {cos}: GPU {} vs Rust {rust}",
            spot.profile,
            spot.cos_cutoff,
            o[0]
        );
    }
}

#[test]
fn glass_tint_matches_rust_under_both_models() {
    let Some(gpu) = support::gpu_or_skip("glass_tint_matches_rust_under_both_models") else {
        return;
    };
    let mut items = Vec::new();
    let mut cases = Vec::new();
    for (model, code) in [(GlassModel::Filter, 0.0f32), (GlassModel::Blend, 1.0)] {
        for i in 0..2000 {
            let before = Vec3::new(spread(7 * i), spread(7 * i + 1), spread(7 * i + 2));
            let glass = Glass {
                color: Vec3::new(spread(7 * i + 3), spread(7 * i + 4), spread(7 * i + 5)),
                alpha: spread(7 * i + 6),
            };
            items.push([
                [before.x, before.y, before.z, code],
                [glass.color.x, glass.color.y, glass.color.z, glass.alpha],
            ]);
            cases.push((model, before, glass));
        }
    }
    let out = evaluate(&gpu, Formula::GlassTint, &items).expect("GPU evaluation");
    let mut seen = [false; 2];
    for ((model, before, glass), o) in cases.iter().zip(&out) {
        let rust = model.tint_after(*before, glass);
        let gpu_tint = Vec3::new(o[0], o[1], o[2]);
        // All terms in [0, 1], at most four roundings per side: 8ε.
        let tolerance = 8.0 * EPS;
        assert!(
            (gpu_tint - rust).abs().max_element() <= tolerance,
            "{model:?}, before {before}, {glass:?}: GPU {gpu_tint} vs Rust {rust}"
        );
        seen[(*model == GlassModel::Blend) as usize] = true;
    }
    assert_eq!(seen, [true, true]);
}

/// Single scattering's per-sample balance-heuristic term against
/// `tyndall::integrators::single::single_sample` (as `tyndall::testing::single_sample`), over densities and
/// sample counts from sparse to dense: a product n·p_e (which WGSL may
/// fuse with the sum), a sum, a division (2.5 ULP in WGSL) and a product,
/// each within 1 ULP in Rust: 8ε relative in all, both sides.
#[test]
fn single_sample_matches_rust() {
    let Some(gpu) = support::gpu_or_skip("single_sample_matches_rust") else {
        return;
    };
    let mut items = Vec::new();
    for i in 0..4000 {
        let f = Vec3::new(
            spread(5 * i),
            2.0 * spread(5 * i + 1),
            0.1 * spread(5 * i + 2),
        );
        let camera = spread(5 * i + 3);
        let n = [1.0, 8.0, 64.0][i % 3];
        // Densities from 10⁻³ to 10³ per unit length; p_e is 0 where a
        // light has no equiangular sampler.
        let scale = |s: f32| 10f32.powf(6.0 * s - 3.0);
        let pdf_e = if i % 7 == 0 {
            0.0
        } else {
            scale(spread(5 * i + 4))
        };
        let pdf_d = scale(spread(3 * i + 11));
        items.push([[f.x, f.y, f.z, camera], [n, pdf_e, pdf_d, 0.0]]);
    }
    let out = evaluate(&gpu, Formula::SingleSample, &items).expect("GPU evaluation");
    for (item, o) in items.iter().zip(&out) {
        let [a, b] = *item;
        let rust = single_sample(Vec3::new(a[0], a[1], a[2]), a[3], b[0], b[1], b[2]);
        for c in 0..3 {
            let tolerance = 8.0 * EPS * rust[c];
            assert!(
                (o[c] - rust[c]).abs() <= tolerance,
                "{item:?}, channel {c}: GPU {} vs Rust {}",
                o[c],
                rust[c]
            );
        }
    }
}

#[test]
fn transmittance_matches_rust() {
    let Some(gpu) = support::gpu_or_skip("transmittance_matches_rust") else {
        return;
    };
    let mut items = Vec::new();
    for i in 0..4000 {
        let sigma_t = if i % 50 == 0 {
            0.0
        } else {
            2.0 * spread(2 * i)
        };
        let distance = 40.0 * spread(2 * i + 1);
        items.push([[sigma_t, distance, 0.0, 0.0], [0.0; 4]]);
    }
    let out = evaluate(&gpu, Formula::Transmittance, &items).expect("GPU evaluation");
    for (item, o) in items.iter().zip(&out) {
        let (sigma_t, distance) = (item[0][0], item[0][1]);
        let rust = transmittance(sigma_t, distance);
        // x = σt·d is rounded (relative error |x|ε in e^x on each side),
        // WGSL's exp is within 3 + 2|x| ULP, Rust's within 1 ULP.
        let x = sigma_t * distance;
        let tolerance = ((4.0 + 4.0 * x) * EPS) * rust;
        assert!(
            (o[0] - rust).abs() <= tolerance,
            "σt = {sigma_t}, d = {distance}: GPU {} vs Rust {rust}",
            o[0]
        );
    }
}

#[test]
fn equiangular_sampler_matches_rust() {
    let Some(gpu) = support::gpu_or_skip("equiangular_sampler_matches_rust") else {
        return;
    };
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    let mut items = Vec::new();
    for i in 0..4000 {
        // The emitter's foot Δ on the ray and distance D from it.
        let delta = -5.0 + 20.0 * spread(6 * i);
        let distance = 0.05 + 5.0 * spread(6 * i + 1);
        let angle = std::f32::consts::TAU * spread(6 * i + 2);
        let y = Vec3::new(delta, distance * angle.cos(), distance * angle.sin());
        // Every fourth interval ends at ∞ (a camera ray leaving the
        // scene); the others keep |θ| ≤ atan 2.5 < 1.2, where cos θ ≥ 0.37
        // keeps tan's error bound finite and first order.
        let a = delta - 2.5 * distance + 4.0 * distance * spread(6 * i + 3);
        let b = if i % 4 == 0 {
            INFINITE
        } else {
            a + (0.05 + 0.95 * spread(6 * i + 4)) * (delta + 2.5 * distance - a)
        };
        let u = spread(6 * i + 5);
        let t = if b == INFINITE {
            a - 0.5 + 40.0 * spread(7 * i)
        } else {
            a - 0.5 + (b - a + 1.0) * spread(7 * i)
        };
        items.push([[y.x, y.y, y.z, u], [a, b, t, 0.0]]);
    }
    let out = evaluate(&gpu, Formula::Equiangular, &items).expect("GPU evaluation");
    for (item, o) in items.iter().zip(&out) {
        let y = Vec3::new(item[0][0], item[0][1], item[0][2]);
        let (u, a, b, t) = (item[0][3], item[1][0], item[1][1], item[1][2]);
        let rust_b = if b == INFINITE { f32::INFINITY } else { b };
        let sampler = EquiangularSampler::new(&ray, y, a, rust_b).expect("a < b");
        assert_eq!(o[3], 1.0, "y {y}, [{a}, {b}]: GPU sampler empty");
        let delta = y.x;
        let distance = glam::Vec2::new(y.y, y.z).length();
        let theta_a = ((a - delta) / distance).atan();
        let theta_b = ((rust_b - delta) / distance).atan();
        let width = theta_b - theta_a;
        // θ on each side: the argument (a − Δ)/D rounded with D (sqrt of a
        // sum, 4ε and 2.5 ULP for WGSL's sqrt) — about 8ε relative, which
        // atan's slope |x|/(1 + x²) ≤ ½ makes 4ε absolute — then atan2
        // (WGSL 4096 ULP ≤ 4096ε|θ|, Rust 1 ULP). Both θ, both sides:
        let theta_error = (ATAN_ULP + 1.0) * EPS * (theta_a.abs() + theta_b.abs()) + 16.0 * EPS;
        // The density D/((θb − θa)(D² + x²)): its width relative error
        // θ_error/width, the rest about 12 roundings a side (WGSL's
        // division 2.5 ULP).
        let pdf_tolerance = theta_error / width + 30.0 * EPS;
        let rust_pdf = sampler.pdf(t);
        if t < a || t > b {
            assert_eq!(o[2], 0.0, "pdf outside [{a}, {b}] at {t}");
            assert_eq!(rust_pdf, 0.0);
        } else {
            assert!(
                (o[2] - rust_pdf).abs() <= pdf_tolerance * rust_pdf,
                "y {y}, [{a}, {b}], t {t}: GPU pdf {} vs Rust {rust_pdf} (relative tolerance {pdf_tolerance})",
                o[2]
            );
        }
        let (gpu_t, gpu_pdf) = (o[0], o[1]);
        assert!(
            gpu_t >= a && gpu_t <= b,
            "sample {gpu_t} outside [{a}, {b}]"
        );
        if b == INFINITE {
            // tan near π/2 is unbounded; the density at the GPU's own
            // sample is checked instead of the sample.
            let rust_at_gpu_t = sampler.pdf(gpu_t);
            assert!(
                (gpu_pdf - rust_at_gpu_t).abs() <= pdf_tolerance * rust_at_gpu_t,
                "y {y}, [{a}, ∞), u {u}: GPU pdf at its sample {gpu_t} {gpu_pdf} vs Rust {rust_at_gpu_t}"
            );
            continue;
        }
        let (rust_t, _) = sampler.sample(u);
        // t = Δ + D·tan θ, θ = θa + u·width (θ_error plus 4ε|θ|):
        // tan = sin/cos with both within 2⁻¹¹ on the GPU moves by at most
        // 2⁻¹¹(1 + |tan θ|)/(|cos θ| − 2⁻¹¹), and θ's error by
        // θ_error/cos²θ (first order: cos θ ≥ 0.37 ≫ the errors); then
        // D's 4ε and the sum's rounding of |Δ| + |t| on each side.
        let theta = theta_a + u * width;
        let (sin, cos) = theta.sin_cos();
        let tan = sin / cos;
        let tan_error = SIN_COS_ABSOLUTE * (1.0 + tan.abs()) / (cos.abs() - SIN_COS_ABSOLUTE)
            + 1.01 * (theta_error + 4.0 * EPS * theta.abs()) / (cos * cos)
            + 2.0 * EPS * tan.abs();
        let t_tolerance = distance * (tan_error + 8.0 * EPS * tan.abs())
            + 4.0 * EPS * (delta.abs() + rust_t.abs());
        assert!(
            (gpu_t - rust_t).abs() <= t_tolerance,
            "y {y}, [{a}, {b}], u {u}: GPU sample {gpu_t} vs Rust {rust_t} (tolerance {t_tolerance})"
        );
    }
}

#[test]
fn exponential_sampler_matches_rust() {
    let Some(gpu) = support::gpu_or_skip("exponential_sampler_matches_rust") else {
        return;
    };
    let mut items = Vec::new();
    for i in 0..4000 {
        let sigma_t = if i % 50 == 0 {
            0.0
        } else {
            0.01 + 3.0 * spread(5 * i)
        };
        let a = 5.0 * spread(5 * i + 1);
        // Every fourth interval ends at ∞ (a camera ray leaving the scene);
        // the others have optical depths from 10⁻⁴ (the series branch) up.
        let b = if i % 4 == 0 {
            INFINITE
        } else {
            a + 0.01 * 3000f32.powf(spread(5 * i + 2))
        };
        let u = spread(5 * i + 3);
        let t = if b == INFINITE {
            a - 0.5 + 40.0 * spread(5 * i + 4)
        } else {
            a - 0.5 + (b - a + 1.0) * spread(5 * i + 4)
        };
        items.push([[sigma_t, a, b, u], [t, 0.0, 0.0, 0.0]]);
    }
    let out = evaluate(&gpu, Formula::Exponential, &items).expect("GPU evaluation");
    for (item, o) in items.iter().zip(&out) {
        let [sigma_t, a, b, u] = item[0];
        let t = item[1][0];
        let rust_b = if b == INFINITE { f32::INFINITY } else { b };
        let Some(sampler) = ExponentialSampler::new(sigma_t, a, rust_b) else {
            assert_eq!(sigma_t, 0.0, "Rust sampler empty for σ = {sigma_t}");
            assert_eq!(o[3], 0.0, "σ = 0: GPU sampler not empty");
            continue;
        };
        assert_eq!(o[3], 1.0, "σ = {sigma_t}, [{a}, {b}]: GPU sampler empty");
        // The mass m = 1 − e^{−x}, x = σ(b − a): Rust's exp_m1 1 ULP; the
        // GPU's Taylor series below 0.1 about 12 roundings, above it
        // exp's 3 + 2x ULP of e^{−x} relative to 1 − e^{−x}; x's own
        // rounding (2ε relative) moves m by at most 2ε relative.
        let x = (sigma_t * (rust_b - a)).min(88.0);
        let mass_error = if x < 0.1 {
            12.0 * EPS
        } else {
            (3.0 + 2.0 * x) * EPS * (-x).exp() / -(-x).exp_m1() + 2.0 * EPS
        } + 3.0 * EPS;
        // The density σ·e^{−y}/m, y = σ(t − a): exp's 3 + 2y ULP (GPU)
        // and 1 ULP (Rust), y's rounding 2yε, m's error, and a division
        // (2.5 ULP) and product a side.
        let pdf_tolerance = |y: f32| (4.0 + 4.0 * y + 8.0) * EPS + mass_error;
        let rust_pdf = sampler.pdf(t);
        if t < a || t > rust_b {
            assert_eq!(o[2], 0.0, "pdf outside [{a}, {b}] at {t}");
        } else {
            let tolerance = pdf_tolerance(sigma_t * (t - a)) * rust_pdf;
            assert!(
                (o[2] - rust_pdf).abs() <= tolerance,
                "σ = {sigma_t}, [{a}, {b}], t {t}: GPU pdf {} vs Rust {rust_pdf} (tolerance {tolerance})",
                o[2]
            );
        }
        // The sample t = a − L/σ, L = ln(1 − u·m): the GPU's ln_1p is a
        // series below |u·m| = 0.01 (about 10 roundings), above it
        // log(1 + y) (the sum rounded: ε absolute; WGSL's log: absolute
        // 2⁻²¹ inside [0.5, 2], 3 ULP outside), Rust's 1 ULP; m's error
        // moves L by u·m·mass_error/(1 − u·m); then the division and the
        // sum, rounded to ε of |L|/σ and of |t| a side.
        let (rust_t, _) = sampler.sample(u);
        let um = u * -(-x).exp_m1();
        let l = (-um).ln_1p();
        let log_error = if um < 0.01 {
            10.0 * EPS * l.abs()
        } else if 1.0 - um >= 0.5 {
            EPS / (1.0 - um) + 1.0 / 2_097_152.0
        } else {
            EPS / (1.0 - um) + 3.0 * EPS * l.abs()
        };
        let l_error = log_error + EPS * l.abs() + um * mass_error / (1.0 - um);
        let t_tolerance = (l_error + 2.0 * EPS * l.abs()) / sigma_t + 2.0 * EPS * rust_t.abs();
        assert!(
            (o[0] - rust_t).abs() <= t_tolerance,
            "σ = {sigma_t}, [{a}, {b}], u {u}: GPU sample {} vs Rust {rust_t} (tolerance {t_tolerance})",
            o[0]
        );
    }
}

#[test]
fn uniform_cone_matches_rust() {
    let Some(gpu) = support::gpu_or_skip("uniform_cone_matches_rust") else {
        return;
    };
    let mut items = Vec::new();
    for i in 0..4000 {
        let axis = uniform_cone(Vec3::Z, -1.0, Vec2::new(spread(4 * i), spread(4 * i + 1)));
        let cos_max = -1.0 + 1.999 * spread(4 * i + 2);
        // φ = 2π·u.y within [0, π], where WGSL bounds sin and cos.
        let u = Vec2::new(spread(4 * i + 3), 0.5 * spread(5 * i));
        items.push([[axis.x, axis.y, axis.z, cos_max], [u.x, u.y, 0.0, 0.0]]);
    }
    let out = evaluate(&gpu, Formula::UniformCone, &items).expect("GPU evaluation");
    for (item, o) in items.iter().zip(&out) {
        let axis = Vec3::new(item[0][0], item[0][1], item[0][2]);
        let cos_max = item[0][3];
        let u = Vec2::new(item[1][0], item[1][1]);
        let rust = uniform_cone(axis, cos_max, u);
        let gpu_direction = Vec3::new(o[0], o[1], o[2]);
        // sin θ·cos φ and sin θ·sin φ each within 2⁻¹¹ (WGSL's sin and
        // cos) plus a few roundings; the frame (Duff et al.) and cos θ
        // are the same roundings a side, about 8ε per component; the sum
        // of three terms and the normalisation (the length off 1 by as
        // much) at most double it.
        let tolerance = 2.0 * (2.0 * SIN_COS_ABSOLUTE + 16.0 * EPS);
        assert!(
            (gpu_direction - rust).abs().max_element() <= tolerance,
            "axis {axis}, cos θmax {cos_max}, u {u}: GPU {gpu_direction} vs Rust {rust}"
        );
        // 1/(2π(1 − cos θmax)): the same three roundings a side and
        // WGSL's division (2.5 ULP).
        let pdf = uniform_cone_pdf(cos_max);
        assert!(
            (o[3] - pdf).abs() <= 8.0 * EPS * pdf,
            "cos θmax {cos_max}: GPU density {} vs Rust {pdf}",
            o[3]
        );
    }
}

/// The spherical rectangle's solid angle against the Rust one (through
/// `QuadLight::sample_incident`, whose density is its inverse), and its
/// samples on the rectangle. Where in the rectangle a sample lands, for
/// each u, is checked through the images (tests/images.rs,
/// `every_area_light_matches_cpu_march`, which a sampler drawing v
/// quadratically, or a solid angle 10 % off, fails).
#[test]
fn spherical_rectangle_matches_rust() {
    let Some(gpu) = support::gpu_or_skip("spherical_rectangle_matches_rust") else {
        return;
    };
    let mut items = Vec::new();
    for i in 0..4000 {
        let (width, height) = (0.5 + 1.5 * spread(7 * i), 0.3 + 1.2 * spread(7 * i + 1));
        let side = if i % 2 == 0 { 1.0 } else { -1.0 };
        let o = Vec3::new(
            -1.0 + (width + 2.0) * spread(7 * i + 2),
            -1.0 + (height + 2.0) * spread(7 * i + 3),
            side * (0.2 + 1.8 * spread(7 * i + 4)),
        );
        let u = Vec2::new(spread(7 * i + 5), spread(7 * i + 6));
        items.push([[o.x, o.y, o.z, u.x], [u.y, width, height, 0.0]]);
    }
    let out = evaluate(&gpu, Formula::SphericalRectangle, &items).expect("GPU evaluation");
    let mut checked = 0;
    for (item, o) in items.iter().zip(&out) {
        let origin = Vec3::new(item[0][0], item[0][1], item[0][2]);
        let u = Vec2::new(item[0][3], item[1][0]);
        let (width, height) = (item[1][1], item[1][2]);
        let quad = Quad::new(
            Vec3::ZERO,
            Vec3::new(width, 0.0, 0.0),
            Vec3::new(0.0, height, 0.0),
            false,
        )
        .expect("a rectangle");
        let light = QuadLight::new(quad, Rgb::ONE, true);
        assert!(light.is_rectangle());
        let (_, pdf) = light.sample_incident(origin, u).expect("a sample");
        let rust_solid_angle = 1.0 / pdf;
        assert!(o[3] > 0.0, "o {origin}: GPU rectangle invalid");
        // Far from a small rectangle the angles below near π and the
        // bound loosens as 1/sin: keep solid angles of 0.05 sr and up.
        if rust_solid_angle < 0.05 {
            continue;
        }
        checked += 1;
        // Ω = Σ gᵢ − 2π over the four angles between the great circles
        // through the edges, each an arc cosine of −nᵢ·nᵢ₊₁: the
        // argument (normalised cross products and a dot) within 8ε a side,
        // which acos's slope turns into 8ε/sin g; WGSL's acos inherits
        // atan2's 4096 ULP (≤ 4096ε·g), Rust's Abramowitz & Stegun
        // 2·10⁻⁸; then five sums of terms up to 2π. The angles come from
        // the geometry here, in f64.
        let corners = [
            Vec3::ZERO,
            Vec3::new(width, 0.0, 0.0),
            Vec3::new(width, height, 0.0),
            Vec3::new(0.0, height, 0.0),
        ]
        .map(|c| (c - origin).as_dvec3());
        let normal = |k: usize| corners[k].cross(corners[(k + 1) % 4]).normalize();
        let tolerance: f64 = (0..4)
            .map(|k| {
                let g = (-normal(k).dot(normal((k + 1) % 4)))
                    .clamp(-1.0, 1.0)
                    .acos();
                ATAN_ULP as f64 * EPS as f64 * g + 2.0 * 8.0 * EPS as f64 / g.sin() + 2e-8
            })
            .sum::<f64>()
            + 5.0 * EPS as f64 * std::f64::consts::TAU;
        assert!(
            ((o[3] - rust_solid_angle) as f64).abs() <= tolerance,
            "o {origin}, {width} × {height}: GPU solid angle {} vs Rust {rust_solid_angle} (tolerance {tolerance:.2e})",
            o[3]
        );
        // On the rectangle: the sample is o + x·xu + y·yv − o_z·ẑ with xu,
        // yv clamped to the edges' offsets from o, one rounding a
        // coordinate.
        let slack = |a: f32, b: f32| 2.0 * EPS * (a.abs() + b);
        let sample = Vec3::new(o[0], o[1], o[2]);
        assert!(
            sample.x >= -slack(origin.x, width)
                && sample.x <= width + slack(origin.x, width)
                && sample.y >= -slack(origin.y, height)
                && sample.y <= height + slack(origin.y, height)
                && sample.z.abs() <= 2.0 * EPS * origin.z.abs(),
            "o {origin}, {width} × {height}, u {u}: GPU sample {sample} off the rectangle"
        );
    }
    assert!(checked > 2000, "only {checked} solid angles checked");
}

/// GGX's single-scattering `f·cos θ_i` (`ggx_eval`) for views from the
/// normal to 80° off it and light from every direction above, over
/// roughness 0.05 to 1. Each side rounds the half vector and the cosines
/// by a few ε (δ ≈ 8ε); the distribution's denominator
/// `d = cos²θ_h(α² − 1) + 1` loses them to cancellation where it is small
/// (a sharp lobe at its peak): `D` within `2·(2δ + ε)/d` relative, Smith's
/// Λ and G₂ within 16ε: each side within `(2(2δ + ε)/d + 16ε)`, the two
/// within twice that, plus 8ε of the value's scale. Directions within
/// 10⁻⁵ of the horizon are left out (the sides may round to either side).
#[test]
fn ggx_eval_matches_rust() {
    let Some(gpu) = support::gpu_or_skip("ggx_eval_matches_rust") else {
        return;
    };
    let mut items = Vec::new();
    for k in 0..4000 {
        let alpha = 0.05 + 0.95 * spread(k);
        let (t, phi) = (
            80f32.to_radians() * spread(k + 7),
            std::f32::consts::TAU * spread(k + 13),
        );
        let outgoing = Vec3::new(t.sin() * phi.cos(), t.cos(), t.sin() * phi.sin());
        let (s, psi) = (1.5 * spread(k + 29), std::f32::consts::TAU * spread(k + 31));
        let incident = Vec3::new(s.sin() * psi.cos(), s.cos(), s.sin() * psi.sin());
        items.push([
            [outgoing.x, outgoing.y, outgoing.z, alpha],
            [incident.x, incident.y, incident.z, 0.0],
        ]);
    }
    let out = evaluate(&gpu, Formula::GgxEval, &items).expect("GPU evaluation");
    let mut compared = 0;
    for (item, o) in items.iter().zip(&out) {
        let outgoing = Vec3::new(item[0][0], item[0][1], item[0][2]);
        let incident = Vec3::new(item[1][0], item[1][1], item[1][2]);
        let alpha = item[0][3];
        if outgoing.y.abs() < 1e-5 || incident.y.abs() < 1e-5 {
            continue;
        }
        let rust =
            tyndall::materials::Ggx::new(alpha)
                .expect("rough")
                .eval(outgoing, Vec3::Y, incident);
        let h = (outgoing + incident).normalize();
        let d = h.y * h.y * (alpha * alpha - 1.0) + 1.0;
        let delta = 8.0 * EPS;
        let relative = 2.0 * (2.0 * (2.0 * delta + EPS) / d + 16.0 * EPS);
        let scale = 1.0 / (std::f32::consts::PI * alpha * alpha * outgoing.y);
        let tolerance = relative * rust + 8.0 * EPS * scale;
        assert!(
            (o[0] - rust).abs() <= tolerance,
            "outgoing {outgoing}, incident {incident}, α {alpha}: GPU {} vs Rust {rust} (tolerance {tolerance:.2e})",
            o[0]
        );
        compared += 1;
    }
    assert!(compared > 3900, "{compared} compared");
}
