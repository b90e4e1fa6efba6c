//! One formula, two languages (issue 14): every physics function of
//! `shaders/formulas.wgsl` is evaluated by a compute shader on many inputs
//! and compared with the Rust function it transcribes.
//!
//! Tolerances follow from f32 rounding (ε = 2⁻²³): both sides round each
//! operation (WGSL allows 2.5 ULP for a division, `exp` 3 + 2|x| ULP, and
//! may fuse a multiply-add), so the two results differ by at most the sum
//! of both sides' error bounds, stated per test.

mod support;

use glam::Vec3;
use tyndall::glass::{Glass, GlassModel};
use tyndall::lights::{SpotLight, SpotProfile};
use tyndall::media::transmittance;
use tyndall::phase::PhaseFunction;
use tyndall_gpu::formula_probe::{Formula, evaluate};

const EPS: f32 = f32::EPSILON;

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
                spots.push((spot, cos));
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
