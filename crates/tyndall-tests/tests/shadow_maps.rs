//! Shadow and transmittance maps against exact shadow rays.
mod common;

use common::{render, repo, scene};
use glam::Vec3;
use tyndall::RayCounts;
use tyndall::Scene;
use tyndall::lights::Light;
use tyndall::settings::VisibilityMode;
use tyndall::testing::PixelPosition;
use tyndall::testing::Visibility;
use tyndall::testing::interleaved_stratum;
use tyndall::testing::{MapScene, ShadowMaps};
use tyndall::{IntegratorKind, Rgb};
use tyndall_image::metrics::relative_mse;

const RESOLUTION: u32 = 512;

fn maps(scene: &Scene, resolution: u32) -> ShadowMaps {
    let map_scene = MapScene {
        geometry: scene.geometry(),
        materials: scene.materials(),
        model: scene.glass().model,
    };
    ShadowMaps::build(&map_scene, scene.lights(), resolution)
}

/// Exact visibility of light `index` from `x` by a shadow ray.
fn exact(scene: &Scene, index: usize, x: Vec3) -> Option<Rgb> {
    let incident =
        scene.lights()[index].incident(x, scene.lights()[index].sample_point(glam::Vec2::ZERO))?;
    let mut counts = RayCounts::default();
    Some(Visibility::ShadowRays.transmittance(scene, index, x, None, &incident, &mut counts))
}

/// The i-th point of the Halton sequence in bases 2, 3, 5.
fn halton(i: u32) -> Vec3 {
    let radical = |mut n: u32, base: u32| {
        let (mut f, mut r) = (1.0f32, 0.0f32);
        while n > 0 {
            f /= base as f32;
            r += f * (n % base) as f32;
            n /= base;
        }
        r
    };
    Vec3::new(radical(i, 2), radical(i, 3), radical(i, 5))
}

/// Map visibility equals shadow-ray visibility at fog points, except
/// within a band around shadow edges that follows from the resolution:
/// PCF blends the four texels around a point, so only points within one
/// texel footprint `w = 2·depth·tan(half-angle)/R` (cube faces: tan 1) of
/// an edge can differ. A point counts as near an edge if exact
/// visibility changes anywhere within 2w of it across the light
/// direction; everywhere else the answers agree to float precision.
#[test]
fn map_visibility_agrees_with_shadow_rays() {
    for file in [
        "stained-glass.toml",
        "fig07-spot-sphere.toml",
        "fig08-glass-pair.toml",
    ] {
        let desc = common::load_native(&repo().join("scenes").join(file)).expect("scene");
        let scene = &desc.scene;
        let maps = maps(scene, RESOLUTION);
        let reach = scene.geometry().bounds().extent().length();
        let (mut checked, mut near_edge) = (0, 0);
        for (index, light) in scene.lights().iter().enumerate() {
            // Points spread over the light's cone (a spot) or all
            // directions (a point light), at distances up to the scene's
            // diagonal, so lit, shadowed and tinted fog are all covered.
            let (position, tan_half, axis, cos_max) = match light {
                Light::Spot(s) => (
                    s.position,
                    s.cos_cutoff.acos().tan().max(1.0),
                    s.direction,
                    s.cos_cutoff,
                ),
                Light::Point(p) => (p.position, 1.0, Vec3::Y, -1.0),
                _ => continue,
            };
            let (e1, e2) = axis.any_orthonormal_pair();
            for i in 1..3000 {
                let h = halton(i);
                let cos = 1.0 - h.x * (1.0 - cos_max);
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let phi = std::f32::consts::TAU * h.y;
                let dir = axis * cos + (e1 * phi.cos() + e2 * phi.sin()) * sin;
                let x = position + dir * (0.05 + h.z * reach);
                let Some(truth) = exact(scene, index, x) else {
                    continue;
                };
                let to_light = (position - x).normalize();
                let got = maps
                    .transmittance(index, x, None, to_light)
                    .expect("light has a map");
                let w = 2.0 * (position - x).length() * tan_half / RESOLUTION as f32;
                let (u, v) = to_light.any_orthonormal_pair();
                let edge = [u, -u, v, -v].iter().any(|d| {
                    exact(scene, index, x + *d * 2.0 * w)
                        .is_some_and(|t| (t - truth).abs().max_element() > 1e-4)
                });
                if edge {
                    near_edge += 1;
                    continue;
                }
                checked += 1;
                assert!(
                    (got - truth).abs().max_element() < 1e-4,
                    "{file}, light {index}, {x}: map {got} vs ray {truth}"
                );
            }
        }
        assert!(checked > 1000, "{file}: only {checked} points checked");
        assert!(
            near_edge * 10 < checked,
            "{file}: {near_edge} of {checked} near edges: the test lacks power"
        );
    }
}

/// Light crossing two overlapping panes: the map's tint below the overlap
/// is the product of the panes' transmittances (filter) or eq. 6 in order
/// (blend); above the panes it is white.
#[test]
fn tint_through_two_panes() {
    for model in ["filter", "blend"] {
        let desc = scene(&format!(
            r#"
            [camera]
            position = [0, 1, 5]
            look_at = [0, 1, 0]
            fov_y_deg = 40
            [render]
            glass_model = "{model}"
            [materials.red]
            type = "glass"
            color = [0.9, 0.15, 0.15]
            alpha = 0.8
            [materials.blue]
            type = "glass"
            color = [0.15, 0.15, 0.9]
            alpha = 0.6
            [[shapes]]
            type = "quad"
            corners = [[-1, 1.6, -1], [-1, 1.6, 1], [0.25, 1.6, 1], [0.25, 1.6, -1]]
            material = "red"
            [[shapes]]
            type = "quad"
            corners = [[-0.25, 1.5, -1], [-0.25, 1.5, 1], [1, 1.5, 1], [1, 1.5, -1]]
            material = "blue"
            [[lights]]
            type = "spot"
            position = [0, 3, 0]
            direction = [0, -1, 0]
            cutoff_deg = 25
            intensity = 1
            "#
        ));
        let maps = maps(&desc.scene, RESOLUTION);
        let red = tyndall::glass::Glass {
            color: Rgb::new(0.9, 0.15, 0.15),
            alpha: 0.8,
        };
        let blue = tyndall::glass::Glass {
            color: Rgb::new(0.15, 0.15, 0.9),
            alpha: 0.6,
        };
        let both = match model {
            "filter" => red.filter_transmittance() * blue.filter_transmittance(),
            _ => blue.blend(red.blend(Rgb::ONE)),
        };
        let at = |x: Vec3| {
            maps.transmittance(0, x, None, (Vec3::new(0.0, 3.0, 0.0) - x).normalize())
                .unwrap()
        };
        let overlap = Vec3::new(0.0, 1.0, 0.0);
        assert!(
            (at(overlap) - both).abs().max_element() < 1e-5,
            "{model}: {} vs {both}",
            at(overlap)
        );
        let red_only = Vec3::new(-0.5, 1.0, 0.0);
        let expected = match model {
            "filter" => red.filter_transmittance(),
            _ => red.blend(Rgb::ONE),
        };
        assert!(
            (at(red_only) - expected).abs().max_element() < 1e-5,
            "{model}: {}",
            at(red_only)
        );
        assert!(
            (at(Vec3::new(0.0, 2.0, 0.0)) - Rgb::ONE)
                .abs()
                .max_element()
                < 1e-6
        );
    }
}

/// A render with maps matches one with shadow rays: with the same seed
/// both draw the same samples, so they differ only where map visibility
/// does, within the edge band above. That difference must be well below
/// the Monte Carlo noise of the render itself (a tenth of the relMSE
/// between two seeds) and must shrink as the resolution grows.
#[test]
fn image_with_maps_matches_shadow_rays() {
    let desc = common::load_native(&repo().join("scenes/fig07-spot-sphere.toml")).expect("scene");
    let shot = |visibility: VisibilityMode, seed: u64| {
        render(&desc, |s| {
            s.width = 160;
            s.height = 120;
            s.spp = 4;
            s.integrator = IntegratorKind::March;
            s.step = 0.1;
            s.seed = seed;
            s.visibility = visibility;
        })
    };
    let rays = shot(VisibilityMode::ShadowRays, 1);
    let noise = relative_mse(&shot(VisibilityMode::ShadowRays, 2), &rays);
    let coarse = relative_mse(&shot(VisibilityMode::Maps { resolution: 128 }, 1), &rays);
    let fine = relative_mse(&shot(VisibilityMode::Maps { resolution: 1024 }, 1), &rays);
    assert!(
        fine < noise / 10.0,
        "maps vs rays {fine:.3e}, noise {noise:.3e}"
    );
    assert!(
        fine < coarse,
        "finer maps must agree better: {fine:.3e} at 1024², {coarse:.3e} at 128²"
    );
}

/// Every pixel of an interleaving tile takes a different stratum.
#[test]
fn interleaved_strata_cover_the_tile() {
    for n in 1..=6u32 {
        let mut seen = vec![false; (n * n) as usize];
        for y in 0..n {
            for x in 0..n {
                let (k, count) = interleaved_stratum(
                    PixelPosition {
                        x: x + 7 * n,
                        y: y + 3 * n,
                    },
                    n,
                );
                assert_eq!(count, n * n);
                assert!(!seen[k as usize], "n = {n}: stratum {k} twice");
                seen[k as usize] = true;
            }
        }
    }
}
