//! Light groups (AOV `light_groups`, issue 24; docs/physics.md §6.3):
//! every contribution goes to the group of the emitter it came from, so
//!
//! - per pixel the groups' images add up to the beauty, to the f32
//!   rounding of a sample's sums, in every integrator;
//! - each group's image is, region by region within its noise, a render
//!   of the scene with only that group's emitters switched on (the others'
//!   geometry black, casting its shadows) — the test of
//!   independent computation: the solo render has no other light to
//!   confuse with, and its estimators (light choice, MIS weights, light
//!   subpaths) are run with other densities than the full scene's.
//!
//! The scene: a floor, a sphere casting shadows, fog in a box, and five
//! emitters of each kind a group can hold — two spots (`left`, `right`),
//! a quad `[[lights]]` (`panel`: volpath starts light subpaths from it),
//! an emissive sphere (`glow`: a `[[shapes]]` emitter, seen and sampled)
//! and an ungrouped point light, whose light is the group `other`.

mod common;

use common::{Loaded, pool_inflation, region_means, scene};
use tyndall::light_groups::OTHER_NAME;
use tyndall::lights::LightSampling;
use tyndall::{Image, IntegratorKind, RenderSettings};

const REGIONS_X: u32 = 8;
const REGIONS_Y: u32 = 6;

/// The emitters: each group's name, its TOML, and the TOML of its
/// geometry switched off (black: it still casts its shadows, and, as an
/// emitter, it reflected nothing).
const EMITTERS: [(&str, &str, &str); 5] = [
    (
        "left",
        r#"
[[lights]]
type = "spot"
position = [-2.0, 4.5, 0.0]
look_at = [-1.5, 0.0, 0.5]
cutoff_deg = 22.0
intensity = [20.0, 12.0, 6.0]
light_group = "left"
"#,
        "",
    ),
    (
        "right",
        r#"
[[lights]]
type = "spot"
position = [2.0, 4.5, 0.0]
look_at = [1.5, 0.0, -0.5]
cutoff_deg = 16.0
profile = "linear"
intensity = [6.0, 10.0, 24.0]
light_group = "right"
"#,
        "",
    ),
    (
        "panel",
        r#"
[[lights]]
type = "quad"
corners = [[-1.0, 2.5, -3.9], [1.0, 2.5, -3.9], [1.0, 3.5, -3.9], [-1.0, 3.5, -3.9]]
radiance = 2.0
two_sided = true
light_group = "panel"
"#,
        r#"
[[shapes]]
type = "quad"
corners = [[-1.0, 2.5, -3.9], [1.0, 2.5, -3.9], [1.0, 3.5, -3.9], [-1.0, 3.5, -3.9]]
material = "black"
"#,
    ),
    (
        "glow",
        r#"
[[shapes]]
type = "sphere"
center = [3.0, 0.5, 1.5]
radius = 0.4
material = "glow"
light_group = "glow"
"#,
        r#"
[[shapes]]
type = "sphere"
center = [3.0, 0.5, 1.5]
radius = 0.4
material = "black"
"#,
    ),
    (
        OTHER_NAME,
        r#"
[[lights]]
type = "point"
position = [0.0, 4.0, 2.0]
intensity = 3.0
"#,
        "",
    ),
];

/// The scene with the emitters of the groups `groups` only switched on.
fn stage(groups: &[&str], sampling: LightSampling) -> Loaded {
    let mut text = format!(
        r#"
[camera]
position = [0.0, 2.5, 9.0]
look_at = [0.0, 1.5, 0.0]
fov_y_deg = 50.0

[render]
light_sampling = "{}"

[fog]
sigma_t = 0.1
albedo = 0.8
g = 0.2
box = {{ min = [-5.0, 0.0, -4.0], max = [5.0, 5.0, 4.0] }}

[materials.floor]
type = "diffuse"
reflectance = 0.5

[materials.glow]
type = "emissive"
radiance = [4.0, 2.0, 1.0]

[materials.black]
type = "diffuse"
reflectance = 0.0

[[shapes]]
type = "quad"
corners = [[-5, 0, -4], [-5, 0, 4], [5, 0, 4], [5, 0, -4]]
material = "floor"

[[shapes]]
type = "sphere"
center = [0.0, 0.8, 0.0]
radius = 0.8
material = "floor"
"#,
        sampling.name()
    );
    for (group, on, off) in EMITTERS {
        text.push_str(if groups.contains(&group) { on } else { off });
    }
    scene(&text)
}

fn everything(sampling: LightSampling) -> Loaded {
    stage(&EMITTERS.map(|(g, _, _)| g), sampling)
}

/// The beauty and each group's image (by the scene's group names) of a
/// render of `desc` with `settings`.
fn split(desc: &Loaded, settings: RenderSettings) -> (Image, Vec<(String, Image)>) {
    let settings = RenderSettings {
        light_groups: true,
        threads: Some(2),
        ..settings
    };
    let sums = common::accumulate(desc, &settings);
    let names = desc.scene.light_groups().names().to_vec();
    let images = sums.resolve_light_groups().expect("kept");
    assert_eq!(images.len(), names.len());
    (sums.resolve(), names.into_iter().zip(images).collect())
}

/// Per pixel and channel the groups add up to the beauty, to the f32
/// rounding of a sample's sums (`common::assert_parts_sum_to`), and every
/// group is lit somewhere.
#[test]
fn the_light_groups_sum_to_the_beauty() {
    let desc = everything(LightSampling::All);
    assert_eq!(
        desc.scene.light_groups().names(),
        ["other", "glow", "panel", "left", "right"],
        "OTHER first, then in the order of the scene's lights (emissive shapes, the quad light among them, first)"
    );
    for kind in [
        IntegratorKind::March,
        IntegratorKind::Single,
        IntegratorKind::Volpath,
    ] {
        let settings = RenderSettings {
            width: 40,
            height: 30,
            spp: 2,
            integrator: kind,
            step: 0.25,
            max_depth: 3,
            ..desc.settings
        };
        let (beauty, groups) = split(&desc, settings);
        let named: Vec<(String, &Image)> = groups.iter().map(|(n, im)| (n.clone(), im)).collect();
        common::assert_parts_sum_to(&beauty, &named, &format!("{kind:?}"));
        for (name, image) in &groups {
            let lit = image.pixels().iter().any(|p| p.max_element() > 0.0);
            assert!(lit, "{kind:?}: group {name} has no light");
        }
    }
}

/// Each group's image of the full scene against renders with only that
/// group's emitters: 8×6 region means, two seeds each, within 5 standard
/// errors (the solo renders' and the group images' own, from their seeds'
/// pixel differences).
fn check(kind: IntegratorKind, sampling: LightSampling, size: (u32, u32), spp: u32) {
    let full = everything(sampling);
    let settings = |desc: &Loaded, seed: u64| RenderSettings {
        width: size.0,
        height: size.1,
        spp,
        seed,
        integrator: kind,
        max_depth: 3,
        ..desc.settings
    };
    let per_region = ((size.0 / REGIONS_X) * (size.1 / REGIONS_Y)) as usize;
    let (_, one) = split(&full, settings(&full, 1));
    let (_, two) = split(&full, settings(&full, 2));
    let inflation_full = pool_inflation(&full, &settings(&full, 1), per_region);
    for (k, (name, _, _)) in EMITTERS.iter().enumerate() {
        let group = |images: &[(String, Image)]| {
            let (_, image) = images.iter().find(|(n, _)| n == name).expect("a group");
            image.clone()
        };
        let from_full = region_means(&group(&one), &group(&two), (REGIONS_X, REGIONS_Y));
        let solo = stage(&[name], sampling);
        let solo_render = |seed: u64| {
            tyndall::render(&solo.scene, &settings(&solo, 10 + seed), &|_| {})
                .expect("render")
                .image
        };
        let alone = region_means(&solo_render(1), &solo_render(2), (REGIONS_X, REGIONS_Y));
        let inflation_solo = pool_inflation(&solo, &settings(&solo, 11), per_region);
        let lit = alone.iter().filter(|&&(m, _)| m > 1e-4).count();
        assert!(
            lit >= 4,
            "{kind:?} {name}: the test needs light ({lit} lit regions)"
        );
        for (region, (&(ma, va), &(mb, vb))) in from_full.iter().zip(&alone).enumerate() {
            let sigma = (inflation_full.powi(2) * va + inflation_solo.powi(2) * vb).sqrt();
            assert!(
                (ma - mb).abs() <= 5.0 * sigma,
                "{kind:?}, {sampling:?}, group {k} ({name}), region {region}: in the full scene {ma:.5}, alone {mb:.5} (σ {sigma:.2e})"
            );
        }
    }
}

/// `single`: in-scattering along camera rays and direct light at the floor.
#[test]
fn a_group_in_single_scattering_is_its_lights_alone() {
    check(IntegratorKind::Single, LightSampling::All, (64, 36), 64);
}

/// `volpath` to three events, visiting every light: NEE at fog events and
/// surfaces, the segments' equiangular samples, hits on the panel and the
/// glowing sphere, and the panel's light subpaths.
#[test]
fn a_group_in_volpath_is_its_lights_alone() {
    check(IntegratorKind::Volpath, LightSampling::All, (64, 36), 32);
}

/// `volpath` with the light tree choosing the point and spot lights: a
/// group's image weighs its lights by the tree's choice among all of
/// them, the solo render by a choice among its own.
#[test]
fn a_group_under_the_light_tree_is_its_lights_alone() {
    check(IntegratorKind::Volpath, LightSampling::Tree, (64, 36), 32);
}
