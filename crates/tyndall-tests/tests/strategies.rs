//! Each of `volpath`'s strategies alone, and all of them under MIS, give
//! the same image (issue 8): a strategy that is off leaves every other
//! strategy's weight, so the images agree only if every strategy is
//! unbiased on its own and the balance-heuristic weights of every path
//! sum to one. Three scenes at two scattering events (`max_depth` 2), so
//! that second vertices, where the Cornell box's bias hid, are covered:
//! surfaces only under an area light, fog under an area light, and fog
//! under a spotlight.
//!
//! The statistic: the image is cut into 4×3 regions; for two strategy
//! sets A and B, each rendered with two seeds, the difference of a
//! region's mean must lie within 5 standard errors, the standard error
//! being estimated from the two seeds' pixel differences (an unbiased
//! estimate with as many degrees of freedom as the region has pixels).
//! Seeds are fixed, so the outcome is deterministic.
mod common;

use common::Loaded;
use common::{pool_inflation, region_means, render, repo, scene};
use tyndall::IntegratorKind;
use tyndall::settings::Strategies;

const REGIONS_X: u32 = 4;
const REGIONS_Y: u32 = 3;

/// Both surface strategies (light sampling and BSDF sampling), for the
/// sets that test the media's strategies.
const SURFACES: Strategies = Strategies {
    surface_nee: true,
    surface_hits: true,
    ..Strategies::NONE
};

/// [`SURFACES`] with the media's strategies that `f` switches on.
fn surfaces_with(f: fn(&mut Strategies)) -> Strategies {
    let mut s = SURFACES;
    f(&mut s);
    s
}

fn check_scene(file: &str, size: (u32, u32), spp: u32, sets: &[(&str, Strategies)]) {
    let desc = common::load_native(&repo().join(file)).expect("scene");
    check(&desc, file, size, spp, sets);
}

fn check(desc: &Loaded, file: &str, size: (u32, u32), spp: u32, sets: &[(&str, Strategies)]) {
    let settings = |strategies: Strategies, seed: u64| {
        let mut s = desc.settings;
        s.width = size.0;
        s.height = size.1;
        s.spp = spp;
        s.seed = seed;
        s.integrator = IntegratorKind::Volpath;
        s.max_depth = 2;
        s.strategies = strategies;
        s
    };
    // A region's pixels share the pass's light subpaths when connections
    // are on: its standard error grows by at most this factor.
    let region_pixels = ((size.0 / REGIONS_X) * (size.1 / REGIONS_Y)) as usize;
    let inflation =
        |strategies: Strategies| pool_inflation(desc, &settings(strategies, 1), region_pixels);
    let shoot = |strategies: Strategies| {
        let one = |seed: u64| render(desc, |s| *s = settings(strategies, seed));
        region_means(&one(1), &one(2), (REGIONS_X, REGIONS_Y))
    };
    let all = shoot(Strategies::ALL);
    assert!(
        all.iter().any(|&(m, _)| m > 0.0),
        "{file}: the test needs light"
    );
    for &(name, strategies) in sets {
        let alone = shoot(strategies);
        let (fa, fb) = (inflation(Strategies::ALL), inflation(strategies));
        for (region, (&(ma, va), &(mb, vb))) in all.iter().zip(&alone).enumerate() {
            let sigma = (fa * fa * va + fb * fb * vb).sqrt();
            assert!(
                (ma - mb).abs() <= 5.0 * sigma,
                "{file}, region {region}: all strategies {ma:.5} vs {name} {mb:.5} (σ {sigma:.2e})"
            );
        }
    }
}

/// Surface interreflection under an area light, one indirect bounce:
/// light sampling alone, BSDF sampling alone.
#[test]
fn surface_strategies_agree() {
    let nee = Strategies {
        surface_nee: true,
        ..Strategies::NONE
    };
    let hits = Strategies {
        surface_hits: true,
        ..Strategies::NONE
    };
    check_scene(
        "scenes/reference/cornell-surfaces-depth3.toml",
        (40, 30),
        128,
        &[("surface NEE", nee), ("BSDF hits", hits)],
    );
}

/// Fog under an area light, two scattering events: each fog strategy
/// alone (surfaces keep both of theirs; equiangular samples on every
/// segment, not only camera rays), and light-vertex connections with NEE
/// (connections alone miss single scattering). The default set leaves
/// area lights out of equiangular sampling after the first event.
#[test]
fn fog_strategies_agree_under_an_area_light() {
    check_scene(
        "scenes/reference/fog-room-depth2.toml",
        (40, 30),
        64,
        &[
            ("fog NEE", surfaces_with(|s| s.medium_nee = true)),
            ("phase hits", surfaces_with(|s| s.medium_hits = true)),
            (
                "equiangular",
                surfaces_with(|s| {
                    s.equiangular = true;
                    s.later_area_equiangular = true
                }),
            ),
            (
                "connections + NEE",
                surfaces_with(|s| {
                    s.connections = true;
                    s.medium_nee = true
                }),
            ),
        ],
    );
}

/// Fog under a spotlight (a delta light: NEE and equiangular sampling
/// only), two scattering events.
#[test]
fn fog_strategies_agree_under_a_spotlight() {
    check_scene(
        "scenes/fig07-spot-sphere.toml",
        (40, 30),
        64,
        &[
            ("fog NEE", surfaces_with(|s| s.medium_nee = true)),
            ("equiangular", surfaces_with(|s| s.equiangular = true)),
        ],
    );
}

/// Uniform volumes under a point light and a spotlight (delta lights:
/// NEE at the volumes' collisions and equiangular samples along their
/// flights, the two weighed by the balance heuristic in t), two
/// scattering events: a chromatic haze filling all space, and a denser
/// box of another phase function overlapping it, so that flights cross
/// several uniform pieces (each with its own channel weights and reach)
/// and the in-scattering at a sample sums two volumes. Each strategy
/// alone against both.
#[test]
fn volume_strategies_agree_under_point_and_spot_lights() {
    let desc = scene(
        r#"
        [camera]
        position = [0, 1.2, 4]
        look_at = [0, 0.8, 0]
        fov_y_deg = 45
        [[media]]
        sigma_t = [0.2, 0.3, 0.45]
        albedo = [0.9, 0.8, 0.7]
        g = 0.3
        [[media]]
        sigma_t = [0.9, 0.6, 0.4]
        albedo = 0.85
        g = -0.2
        box = { min = [-1.2, 0.2, -1], max = [0.4, 1.6, 0.6] }
        [materials.floor]
        type = "diffuse"
        reflectance = 0.7
        [[shapes]]
        type = "quad"
        corners = [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]]
        material = "floor"
        [[lights]]
        type = "point"
        position = [0.6, 1.5, 0.2]
        intensity = [3, 2.5, 2]
        [[lights]]
        type = "spot"
        position = [-1.0, 2.2, 0.0]
        direction = [0.3, -1, 0]
        intensity = [4, 4, 5]
        cutoff_deg = 25
        "#,
    );
    check(
        &desc,
        "uniform volumes under delta lights",
        (40, 30),
        64,
        &[
            ("NEE at collisions", surfaces_with(|s| s.medium_nee = true)),
            ("equiangular", surfaces_with(|s| s.equiangular = true)),
        ],
    );
}

/// A chromatic uniform volume filling all space under an area light
/// (fog-room-depth2's room and lamp), two scattering events: NEE at
/// collisions alone, phase hits alone, and the light-vertex connections
/// with NEE and with phase hits (connections alone miss single
/// scattering), each against all of them. The connections' weights read
/// flight densities with even channel weights, which no path is drawn
/// with: the images agree only if those weights still sum to one for
/// every path.
#[test]
fn volume_strategies_agree_under_an_area_light() {
    let file = "scenes/reference/fog-room-depth2.toml";
    let text = std::fs::read_to_string(repo().join(file)).expect("scene");
    let fog = "[fog]\nsigma_t = 0.3\nalbedo = [0.9, 0.9, 0.9]\ng = 0.5\n";
    assert!(text.contains(fog), "{file}: the test replaces its fog");
    let chromatic = "[[media]]\nsigma_t = [0.45, 0.3, 0.15]\nalbedo = [0.8, 0.9, 0.97]\ng = 0.5\n";
    let desc = scene(&text.replace(fog, chromatic));
    check(
        &desc,
        "chromatic volume under an area light",
        (40, 30),
        512,
        &[
            ("NEE at collisions", surfaces_with(|s| s.medium_nee = true)),
            ("phase hits", surfaces_with(|s| s.medium_hits = true)),
            (
                "connections + NEE",
                surfaces_with(|s| {
                    s.connections = true;
                    s.medium_nee = true
                }),
            ),
            (
                "connections + phase hits",
                surfaces_with(|s| {
                    s.connections = true;
                    s.medium_hits = true
                }),
            ),
        ],
    );
}

/// An emissive sphere in fog over a floor (an area light found by
/// cone-sampled NEE and by phase and BSDF sampling): light sampling alone,
/// hits alone, and both, at two scattering events.
#[test]
fn strategies_agree_under_an_emissive_sphere() {
    let desc = scene(
        r#"
        [camera]
        position = [0, 1.2, 4]
        look_at = [0, 0.8, 0]
        fov_y_deg = 45
        [fog]
        sigma_t = 0.3
        albedo = 0.9
        g = 0.3
        [materials.floor]
        type = "diffuse"
        reflectance = 0.7
        [materials.glow]
        type = "emissive"
        radiance = [6, 5, 4]
        [[shapes]]
        type = "quad"
        corners = [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]]
        material = "floor"
        [[shapes]]
        type = "sphere"
        center = [0.3, 1.3, -0.5]
        radius = 0.35
        material = "glow"
        "#,
    );
    let nee = Strategies {
        surface_nee: true,
        medium_nee: true,
        ..Strategies::NONE
    };
    let hits = Strategies {
        surface_hits: true,
        medium_hits: true,
        ..Strategies::NONE
    };
    check(
        &desc,
        "emissive sphere in fog",
        (40, 30),
        64,
        &[("light sampling", nee), ("hits", hits)],
    );
}

/// An emissive triangle mesh in fog over a floor (an octahedron lamp,
/// one-sided outwards: an area light whose NEE picks a triangle by power
/// and a point on it by area, and which phase and BSDF sampling hit):
/// light sampling alone, hits alone, and both, at two scattering events.
/// Then the same lamp with an emission texture (white fading to black
/// along x: NEE weighs its points by the texture at the point it
/// sampled, a hit by the texture where it hit, two lookups that must
/// agree) over a grey diffuse surface that also reflects (glTF's emission
/// over a base colour: paths go on from the lamp).
#[test]
fn strategies_agree_under_an_emissive_mesh() {
    use glam::{Vec2, Vec3};
    use std::sync::Arc;
    use tyndall::description::{EmissionMap, MeshAttributes, Origin};
    use tyndall::materials::{Material, Surface};
    use tyndall::shapes::Triangle;
    use tyndall::texture::{Texture, Wrap};
    for textured in [false, true] {
        let mut desc = scene(
            r#"
            [camera]
            position = [0, 1.2, 4]
            look_at = [0, 0.8, 0]
            fov_y_deg = 45
            [fog]
            sigma_t = 0.3
            albedo = 0.9
            g = 0.3
            [materials.floor]
            type = "diffuse"
            reflectance = 0.7
            [[shapes]]
            type = "quad"
            corners = [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]]
            material = "floor"
            "#,
        )
        .desc;
        // An octahedron stretched along x, its faces wound outwards.
        let centre = Vec3::new(0.3, 1.0, -0.5);
        let axes = [Vec3::X * 1.2, Vec3::Y * 0.5, Vec3::Z * 0.8];
        let mut triangles = Vec::new();
        for sx in [-1.0f32, 1.0] {
            for sy in [-1.0f32, 1.0] {
                for sz in [-1.0f32, 1.0] {
                    let [a, b, c] = [axes[0] * sx, axes[1] * sy, axes[2] * sz].map(|v| centre + v);
                    let t = Triangle::new_one_sided(a, b, c).unwrap();
                    let t = if t.normal.dot(a - centre) > 0.0 {
                        t
                    } else {
                        Triangle::new_one_sided(a, c, b).unwrap()
                    };
                    triangles.push(t);
                }
            }
        }
        let radiance = tyndall::Rgb::new(6.0, 5.0, 4.0);
        let (glow, attributes) = if textured {
            let ramp = Texture::new(2, 1, vec![[255; 3], [0; 3]], [Wrap::Clamp; 2]).unwrap();
            let texture = desc.add_texture(Arc::new(ramp), Origin::Code);
            // u runs along x over the lamp's width.
            let uv = |p: Vec3| Vec2::new((p.x - centre.x) / 2.4 + 0.5, 0.5);
            let uvs = triangles
                .iter()
                .map(|t| [t.v0, t.v0 + t.e1, t.v0 + t.e2].map(uv))
                .collect();
            let material = Material::Emissive {
                radiance,
                two_sided: false,
                surface: Surface::diffuse(tyndall::Rgb::splat(0.5)),
            };
            let attributes = MeshAttributes {
                emission_map: Some(EmissionMap { texture, uvs }),
                ..MeshAttributes::default()
            };
            (material, attributes)
        } else {
            (
                Material::emitter(radiance, false),
                MeshAttributes::default(),
            )
        };
        let glow = desc.add_material(glow, Origin::Code);
        desc.add_mesh(triangles, attributes, glow, Origin::Code);
        let desc = Loaded::new(desc).expect("scene");
        let nee = Strategies {
            surface_nee: true,
            medium_nee: true,
            ..Strategies::NONE
        };
        let hits = Strategies {
            surface_hits: true,
            medium_hits: true,
            ..Strategies::NONE
        };
        let name = match textured {
            false => "emissive mesh in fog",
            true => "textured, reflecting emissive mesh in fog",
        };
        check(
            &desc,
            name,
            (40, 30),
            64,
            &[("light sampling", nee), ("hits", hits)],
        );
    }
}

/// Emitting media (the fire lighting a floor and wall, one bounce): next
/// event estimation towards the medium's emission off (only emission
/// found by tracking, in full), and emission found by tracking off at
/// vertices that ran NEE (NEE alone where it reaches), against both under
/// the balance heuristic: each strategy unbiased, and their weights
/// summing to one.
#[test]
fn emitting_media_strategies_agree() {
    check_scene(
        "scenes/fire.toml",
        (48, 54),
        128,
        &[
            (
                "emission NEE off",
                Strategies {
                    emission_nee: false,
                    ..Strategies::ALL
                },
            ),
            (
                "emission hits off",
                Strategies {
                    emission_hits: false,
                    ..Strategies::ALL
                },
            ),
        ],
    );
}
