//! Convergence to the reference images of independent renderers
//! (Mitsuba 3 and Cycles; scenes/reference/, from shared/reference/) at
//! reduced cost.
mod common;

use common::{mean_and_stderr, pixel_distances, render, repo};
use tyndall::IntegratorKind;
use tyndall::metrics::relative_mse;
use tyndall::scene::native;

/// The references' own relative MSE (shared/reference/README.md).
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
        let desc = native::load(&dir.join(format!("{name}.toml"))).expect("scene");
        let reference =
            tyndall::Image::read_exr(&dir.join(format!("{name}.exr"))).expect("reference");
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
            let to_ref = pixel_distances(&c1, &reference, &reference);
            let between = pixel_distances(&c1, &c2, &reference);
            // Per pixel, summed over channels: divide by 3 for relMSE units.
            let z: Vec<f64> = (0..to_ref.len())
                .map(|i| (to_ref[i] - 0.5 * between[i]) / 3.0)
                .collect();
            let (excess, stderr) = mean_and_stderr(&z);
            let bound = 2.0 * REFERENCE_ERROR + 4.0 * stderr;
            assert!(
                excess <= bound,
                "{name}, {kind:?}: relMSE {:.3e}, excess over noise {excess:.3e} > bound {bound:.3e}",
                relative_mse(&c1, &reference)
            );
        }
    }
}
