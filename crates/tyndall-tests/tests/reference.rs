//! Convergence to the reference images of independent renderers
//! (Mitsuba 3 and Cycles; scenes/reference/, see its REFERENCE-README.md) at
//! reduced cost.
mod common;

use common::{mean_and_stderr, pixel_distances, pool_inflation, render, repo};
use tyndall::Image;
use tyndall::IntegratorKind;
use tyndall_image::metrics::relative_mse;

/// The references' own relative MSE (scenes/reference/REFERENCE-README.md; docs/physics.md §6).
const REFERENCE_ERROR: f64 = 1e-4;

/// For two independent renders C₁, C₂ and the reference R (all relative
/// to R), the per-pixel term `z = d(C₁, R) − d(C₁, C₂)/2` has expectation
/// (reference error + squared bias): `d(C₁, R)` holds C's variance, the
/// reference's error and the bias; `d(C₁, C₂)/2` holds C's variance. The
/// test accepts a mean of `z` (a relMSE excess over noise) up to twice the
/// references' stated error plus 4 standard errors of that mean. Measured:
/// the excess is ≈ 1·10⁻⁴ (the references' own error) for every scene and
/// integrator, and a light 5 % too bright raises it to 3.3·10⁻⁴ and fails;
/// a convention error (phase normalisation, cone angle, intensity unit)
/// adds ≥ 10⁻² .
#[test]
fn integrators_converge_to_references() {
    for name in ["fog-spot-empty", "fog-spot-sphere", "fog-spot-glass-pair"] {
        let dir = repo().join("scenes/reference");
        let desc = common::load_native(&dir.join(format!("{name}.toml"))).expect("scene");
        let reference =
            tyndall_image::read_exr(&dir.join(format!("{name}.exr"))).expect("reference");
        // The references' max_depth 2 is one scattering event: volpath's
        // max_depth 1.
        for kind in IntegratorKind::ALL {
            let shot = |seed: u64| {
                render(&desc, |s| {
                    s.spp = 32;
                    s.integrator = kind;
                    s.step = 0.1;
                    s.max_depth = 1;
                    s.seed = seed;
                })
            };
            let (c1, c2) = (shot(1), shot(2));
            let (excess, stderr) = excess_over_noise(&c1, &c2, &reference);
            let bound = 2.0 * REFERENCE_ERROR + 4.0 * stderr;
            assert!(
                excess <= bound,
                "{name}, {kind:?}: relMSE {:.3e}, excess over noise {excess:.3e} > bound {bound:.3e}",
                relative_mse(&c1, &reference)
            );
        }
    }
}

/// `volpath` against the multiple-scattering references (Mitsuba 3,
/// scenes/reference/REFERENCE-README.md): surface interreflection in a Cornell-like
/// box (unlimited, and one indirect bounce), a fog-filled room
/// (unlimited, two scattering events, and in chromatic fog), a voxel grid
/// of smoke under a spot, and a sphere and block under
/// uniform and mapped skies with and without fog; and against Cycles 5 on an
/// emitting, scattering flame (scenes/reference/fire-cycles/).
///
/// Rendered at a quarter of the references' resolution: a reference pixel
/// is the box-filtered mean over its footprint, so the mean of each 4×4
/// block of it is exactly the reference of the larger pixel, with a
/// sixteenth of the noise. Two checks per scene:
/// - the image mean within 0.3 % of the reference's, plus 4 standard
///   errors of the two renders' mean (estimated from their difference);
/// - the relMSE excess over the render's own noise (as in
///   [`integrators_converge_to_references`]) within twice the reference's
///   own error (its `.ref.json`, an upper bound at the coarser resolution)
///   plus 4 standard errors.
///
/// Before the shadow-ray fix of issue 8 the box with one bounce was 2.5 %
/// dark and failed the first check by far.
#[test]
fn volpath_converges_to_multiple_scattering_references() {
    // (scene, volpath max_depth, spp)
    let scenes = [
        ("cornell-surfaces", None, 16),
        ("cornell-surfaces-depth3", Some(2), 16),
        ("fog-room-multi", None, 16),
        ("fog-room-depth2", Some(2), 16),
        // The same room in chromatic fog (σt and albedo per channel: a
        // uniform volume's closed-form flights by spectral MIS).
        ("fog-room-chromatic", None, 16),
        // The Cornell box in dense fog filling all space (issue 25's
        // cornell-fog-multi: long paths at albedo 0.95).
        ("cornell-fog-multi", None, 16),
        // A 64³ voxel grid of smoke under a hard spot (issue 25's
        // smoke-grid row), read from the OpenVDB file that holds the
        // voxels Mitsuba read as an array (scenes/reference/smoke-grid/).
        ("smoke-grid/smoke-grid", None, 16),
        // Lit only by Mitsuba's `constant` and `envmap` environments, with
        // and without a box of fog (scenes/reference/environment/).
        ("environment/env-constant", None, 16),
        ("environment/env-constant-fog", None, 16),
        ("environment/env-map", None, 16),
        ("environment/env-map-fog", None, 16),
        // Cycles 5's Principled Volume blackbody on the fire's half-float
        // grids (scenes/reference/fire-cycles/), under Tyndall's
        // `blackbody_law = "cycles"`.
        ("fire-cycles/fire-cycles", None, 1024),
    ];
    let dir = repo().join("scenes/reference");
    for (name, max_depth, spp) in scenes {
        let desc = common::load_native(&dir.join(format!("{name}.toml"))).expect("scene");
        let full = tyndall_image::read_exr(&dir.join(format!("{name}.exr"))).expect("reference");
        let reference = full.box_downsample(4);
        let reference_error = own_error(&dir.join(format!("{name}.ref.json")));
        let settings = |seed: u64| {
            let mut s = desc.settings;
            s.width = reference.width();
            s.height = reference.height();
            s.spp = spp;
            s.seed = seed;
            if let Some(depth) = max_depth {
                s.max_depth = depth;
            }
            s
        };
        let shot = |seed: u64| render(&desc, |s| *s = settings(seed));
        // Pixels of a pass share its light subpaths: standard errors of
        // means over the image grow by at most this factor.
        let inflation = pool_inflation(&desc, &settings(1), reference.pixels().len());
        let (c1, c2) = (shot(1), shot(2));

        let mean = |im: &Image| {
            im.pixels()
                .iter()
                .map(|p| (p.x + p.y + p.z) as f64)
                .sum::<f64>()
                / (3 * im.pixels().len()) as f64
        };
        let (m1, m2, m_ref) = (mean(&c1), mean(&c2), mean(&reference));
        // Var(m1 − m2) = 2·Var(m): the standard error of (m1 + m2)/2 is
        // |m1 − m2|/2 in expectation of its square; take it from the pixel
        // differences instead, which estimate it with many more degrees
        // of freedom.
        let diffs: Vec<f64> = c1
            .pixels()
            .iter()
            .zip(c2.pixels())
            .map(|(a, b)| ((a.x + a.y + a.z) - (b.x + b.y + b.z)) as f64 / 3.0)
            .collect();
        let (_, stderr_diff) = mean_and_stderr(&diffs);
        let stderr_mean = inflation * stderr_diff / 2.0;
        let m = 0.5 * (m1 + m2);
        let bound = 3e-3 * m_ref + 4.0 * stderr_mean;
        assert!(
            (m - m_ref).abs() <= bound,
            "{name}: mean {m:.5} vs reference {m_ref:.5} ({:+.3} %), bound {bound:.2e}",
            100.0 * (m / m_ref - 1.0)
        );

        let (excess, stderr) = excess_over_noise(&c1, &c2, &reference);
        let bound = 2.0 * reference_error + 4.0 * inflation * stderr;
        assert!(
            excess <= bound,
            "{name}: relMSE {:.3e}, excess over noise {excess:.3e} > bound {bound:.3e}",
            relative_mse(&c1, &reference)
        );
    }
}

/// The relMSE of render `c1` against `reference` in excess of its own
/// noise, and the standard error of that excess: the mean over pixels of
/// `d(c1, R) − d(c1, c2)/2` (see [`integrators_converge_to_references`]),
/// with `c2` an independent render of the same settings.
fn excess_over_noise(c1: &Image, c2: &Image, reference: &Image) -> (f64, f64) {
    let to_ref = pixel_distances(c1, reference, reference);
    let between = pixel_distances(c1, c2, reference);
    // Per pixel, summed over channels: divide by 3 for relMSE units.
    let z: Vec<f64> = (0..to_ref.len())
        .map(|i| (to_ref[i] - 0.5 * between[i]) / 3.0)
        .collect();
    mean_and_stderr(&z)
}

/// The reference's own estimated relMSE against the truth,
/// `est_relMSE_ref_vs_truth` in its `.ref.json`.
fn own_error(path: &std::path::Path) -> f64 {
    let text = std::fs::read_to_string(path).expect("reference metadata");
    let key = "\"est_relMSE_ref_vs_truth\":";
    let start = text.find(key).expect("est_relMSE_ref_vs_truth") + key.len();
    let rest = text[start..].trim_start();
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || "+-.eE".contains(c)))
        .unwrap_or(rest.len());
    rest[..end].parse().expect("a number")
}
