//! The radiance's components (AOVs, issue 24: emission, direct, indirect,
//! volume; docs/physics.md §6.2): they sum to the beauty, and each is the
//! same light whichever integrator computes it — `single` and `volpath`
//! classify their contributions by separate code, and agree region by
//! region within their noise on the light scattered once at a surface
//! (`direct`) and once in fog (`volume`).

mod common;

use common::{Loaded, region_means, repo};
use std::ops::ControlFlow;
use tyndall::aov::{Component, Components};
use tyndall::region::RenderRegion;
use tyndall::render::render_region;
use tyndall::{Image, IntegratorKind, RenderSettings};

/// The image and its components of a render of `desc` with `settings`.
fn split(desc: &Loaded, settings: RenderSettings) -> (Image, Components) {
    let settings = RenderSettings {
        components: true,
        threads: Some(2),
        ..settings
    };
    let sums = common::accumulate(desc, &settings);
    (sums.resolve(), sums.resolve_components().expect("kept"))
}

fn reference(name: &str) -> Loaded {
    common::load_native(&repo().join(format!("scenes/reference/{name}.toml"))).expect("scene")
}

/// Per pixel and channel the components add up to the beauty, to the
/// f32 rounding of a sample's sum: at most 64 contributions per sample
/// (each rounding by ε relative) is a relative bound of 64·ε.
#[test]
fn the_components_sum_to_the_beauty() {
    let cases = [
        (common::demo().expect("demo"), IntegratorKind::March),
        (common::demo().expect("demo"), IntegratorKind::Single),
        (common::demo().expect("demo"), IntegratorKind::Volpath),
        (reference("cornell-surfaces"), IntegratorKind::Volpath),
        (reference("fog-room-multi"), IntegratorKind::Volpath),
        (reference("fog-spot-glass-pair"), IntegratorKind::Single),
    ];
    for (desc, kind) in cases {
        let settings = RenderSettings {
            width: 40,
            height: 30,
            spp: 2,
            integrator: kind,
            step: 0.25,
            ..desc.settings
        };
        let (beauty, parts) = split(&desc, settings);
        let named: Vec<(String, &Image)> = Component::ALL
            .iter()
            .map(|&c| (format!("{c:?}"), parts.get(c)))
            .collect();
        common::assert_parts_sum_to(&beauty, &named, &format!("{kind:?}"));
        let lit =
            Component::ALL.map(|c| parts.get(c).pixels().iter().any(|p| p.max_element() > 0.0));
        // Every scene has lit surfaces; those with fog have volume light.
        let foggy = desc.scene.fog().is_some();
        assert!(
            lit[Component::Direct.index()] && lit[Component::Volume.index()] == foggy,
            "{kind:?}: {lit:?}"
        );
    }
}

/// Two independent renders of each of `a` and `b`, compared region by
/// region on `component`: within 5 standard errors (and 0.2 % of the
/// region, for the box-filter's f32 rounding) in each of 8×6 regions.
fn assert_components_agree(
    desc: &Loaded,
    a: RenderSettings,
    b: RenderSettings,
    component: Component,
    what: &str,
) {
    let shot = |s: RenderSettings, seed| {
        split(desc, RenderSettings { seed, ..s })
            .1
            .get(component)
            .clone()
    };
    let ra = region_means(&shot(a, 1), &shot(a, 2), (8, 6));
    let rb = region_means(&shot(b, 3), &shot(b, 4), (8, 6));
    let lit = ra.iter().filter(|(m, _)| *m > 1e-4).count();
    assert!(
        lit >= 8,
        "{what}: only {lit} regions hold {component:?} light"
    );
    for (i, ((ma, va), (mb, vb))) in ra.iter().zip(&rb).enumerate() {
        let bound = 5.0 * (va + vb).sqrt();
        assert!(
            (ma - mb).abs() <= bound,
            "{what}, region {i}: {component:?} {ma:.5} vs {mb:.5} (bound {bound:.2e})"
        );
    }
}

/// The light a spot scatters once in fog (`volume`) and once on the floor
/// and sphere (`direct`): `single` against `volpath` of unlimited depth
/// (whose deeper light goes to `volume` and `indirect`, not to these).
#[test]
fn single_and_volpath_agree_on_direct_and_single_scattered_light() {
    let desc = reference("fog-spot-sphere");
    let base = RenderSettings {
        width: 48,
        height: 36,
        ..desc.settings
    };
    let single = RenderSettings {
        integrator: IntegratorKind::Single,
        spp: 64,
        ..base
    };
    let volpath = RenderSettings {
        integrator: IntegratorKind::Volpath,
        max_depth: 1,
        spp: 64,
        ..base
    };
    assert_components_agree(&desc, single, volpath, Component::Direct, "fog-spot-sphere");
    assert_components_agree(&desc, single, volpath, Component::Volume, "fog-spot-sphere");
    // At depth 1, and in single scattering off diffuse surfaces, nothing
    // scatters twice.
    let (_, parts) = split(&desc, volpath);
    assert!(
        parts
            .get(Component::Indirect)
            .pixels()
            .iter()
            .all(|p| *p == tyndall::Rgb::ZERO)
    );
    let (_, parts) = split(&desc, single);
    assert!(
        parts
            .get(Component::Indirect)
            .pixels()
            .iter()
            .all(|p| *p == tyndall::Rgb::ZERO)
    );
}

/// Interreflection in the Cornell box: `volpath`'s direct light at
/// unlimited depth is the light of its depth-1 render, and its indirect
/// light is what depth adds (the depth-1 render has none).
#[test]
fn volpath_direct_light_is_its_one_bounce_light() {
    let desc = reference("cornell-surfaces");
    let base = RenderSettings {
        width: 48,
        height: 36,
        spp: 32,
        ..desc.settings
    };
    let one = RenderSettings {
        max_depth: 1,
        ..base
    };
    assert_components_agree(&desc, base, one, Component::Direct, "cornell-surfaces");
    let (_, deep) = split(&desc, base);
    let (_, shallow) = split(&desc, one);
    let total = |c: &Components, k: Component| {
        c.get(k)
            .pixels()
            .iter()
            .map(|p| p.element_sum() as f64)
            .sum::<f64>()
    };
    assert_eq!(total(&shallow, Component::Indirect), 0.0);
    assert!(total(&deep, Component::Indirect) > 0.2 * total(&deep, Component::Direct));
}

/// Renders with light paths (caustics) refuse the components, saying why.
#[test]
fn light_path_renders_refuse_the_components() {
    let desc = common::load_native(&repo().join("scenes/glass-sphere-focus.toml")).expect("scene");
    let settings = RenderSettings {
        width: 8,
        height: 8,
        spp: 1,
        components: true,
        ..desc.settings
    };
    let region = RenderRegion::full(8, 8, 1);
    match render_region(
        &desc.scene,
        &settings,
        &region,
        None,
        &|_| {},
        &mut |_, _| ControlFlow::Continue(()),
    ) {
        Err(e) => assert!(e.to_string().contains("light paths"), "{e}"),
        Ok(_) => panic!("components were split for a render with light paths"),
    }
}

/// The AOVs' sums and images count against the render's memory limit:
/// per pixel, each kept kind adds its sum and four resolved images.
#[test]
fn the_aovs_count_in_the_memory_estimate() {
    let desc = common::demo().expect("demo");
    let plain = RenderSettings {
        width: 1000,
        height: 1000,
        ..desc.settings
    };
    let kept = RenderSettings {
        guides: true,
        components: true,
        ..plain
    };
    let (without, _) = plain.memory_estimate(&desc.scene);
    let (with, what) = kept.memory_estimate(&desc.scene);
    let image = 4 * std::mem::size_of::<tyndall::Rgb>();
    let per_pixel = std::mem::size_of::<tyndall::guides::GuideSum>()
        + std::mem::size_of::<tyndall::aov::ComponentSum>()
        + 2 * image;
    assert_eq!(with - without, 1_000_000 * per_pixel as u64, "{what}");
    assert!(
        what.contains("guides") && what.contains("components"),
        "{what}"
    );
}
