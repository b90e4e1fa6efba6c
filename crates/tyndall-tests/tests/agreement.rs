//! `march` with a small step and `single` converge to the same image, and
//! images do not depend on the thread count.
mod common;

use common::{excess_disagreement, render, repo};
use tyndall::IntegratorKind;

/// Both integrators are unbiased estimators of the same image. For
/// independent renders A₁, A₂ (march) and B₁, B₂ (single) and a common
/// denominator r, the per-pixel term
/// `z = d(A₁, B₁) − (d(A₁, A₂) + d(B₁, B₂))/2`, with `d` the relative
/// squared difference, has expectation 0 when the two agree (each `d` is
/// the sum of the two renders' variances) and the squared bias where they
/// do not. So the mean of `z` over the image, divided by its standard
/// error, is approximately standard normal without bias: the test fails
/// above 4 (a false alarm once in 30 000 runs) and any bias visible in
/// the image pushes it far above.
#[test]
fn march_and_single_agree_on_fig7() {
    let desc = common::load_native(&repo().join("scenes/fig07-spot-sphere.toml")).expect("scene");
    let shot = |kind: IntegratorKind, seed: u64| {
        render(&desc, |s| {
            s.width = 96;
            s.height = 72;
            s.spp = 16;
            s.integrator = kind;
            s.step = 0.05;
            s.seed = seed;
        })
    };
    let (a1, a2) = (
        shot(IntegratorKind::March, 1),
        shot(IntegratorKind::March, 2),
    );
    let (b1, b2) = (
        shot(IntegratorKind::Single, 3),
        shot(IntegratorKind::Single, 4),
    );
    let (mean, stderr) = excess_disagreement([&a1, &a2], [&b1, &b2], 1.0);
    assert!(
        mean <= 4.0 * stderr,
        "march vs single: excess {mean:.3e} is {:.1} standard errors",
        mean / stderr
    );
    // The check has power: the beam is there, and a 5 % bias would show.
    let (bmean, bstderr) = excess_disagreement([&a1, &a2], [&b1, &b2], 1.05);
    assert!(
        bmean > 4.0 * bstderr,
        "a 5 % bias should be detected: {:.1} standard errors",
        bmean / bstderr
    );
}

#[test]
fn image_is_identical_for_one_and_two_threads() {
    let desc = common::demo().expect("demo");
    for kind in IntegratorKind::ALL {
        let shot = |threads: usize| {
            render(&desc, |s| {
                s.width = 48;
                s.height = 27;
                s.spp = 2;
                s.integrator = kind;
                s.step = 0.2;
                s.threads = Some(threads);
            })
        };
        assert_eq!(shot(1), shot(2), "{kind:?}");
    }
}
