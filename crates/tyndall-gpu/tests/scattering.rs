//! One formula, two languages for the in-scattering of `shaders/lights.wgsl`
//! (issue 26): `scattered_radiance` (the paper's eq. 1, σs·p(θ)·E·V·
//! Tr_glass·T_fog) and `light_arriving` (E·V·Tr_glass·T_fog) run by compute
//! kernels appended to the march module, bound as the march binds a whole
//! scene (`formula_probe::evaluate_in_scene`), against their Rust twins
//! `tyndall::integrators::lighting::{scattered_radiance, light_arriving}`
//! (through `tyndall::testing::twins`), in a fog box lit by every kind of
//! light, with a glass pane and an opaque card in the way of some of them.
//!
//! Tolerances: the result is a product of factors, so its relative error
//! is the sum of theirs, each bounded from f32 rounding (ε = 2⁻²³) on each
//! side and from its sensitivity to the inputs' rounding, computed in f64
//! from the case; `incident` itself is checked alone by tests/lights.rs.
//! Cases where the two sides may legitimately disagree outright — a
//! receiver within rounding of a spot's cone, of an emitter's plane, or a
//! shadow ray within rounding of an occluder's edge — are left out, by a
//! criterion computed here, and the test asserts that most cases remain.

mod support;

use glam::{DVec3, Vec2, Vec3};
use tyndall::RenderSettings;
use tyndall::Scene;
use tyndall::lights::{Incident, Light, LightPoint};
use tyndall::settings::VisibilityMode;
use tyndall::testing::{Visibility, twins};
use tyndall_gpu::formula_probe::{SceneFormula, evaluate_in_scene};
use tyndall_gpu::{GpuMarch, MarchSettings};

const EPS: f64 = f32::EPSILON as f64;

/// The scene: fog σt 0.35 in a box, g 0.4; a point light, spots of the
/// three profiles, a quad light and a sun; a glass pane (filter model)
/// and an opaque card below the lights.
const SCENE: &str = r#"
[camera]
position = [0, 0, 9]
look_at = [0, 0, 0]
fov_y_deg = 40

[render]
width = 4
height = 4
integrator = "single"

[fog]
sigma_t = 0.35
albedo = [0.9, 0.7, 0.5]
g = 0.4
box = { min = [-4, -4, -4], max = [4, 4, 4] }

[materials.pane]
type = "glass"
color = [0.9, 0.3, 0.2]
alpha = 0.8

[materials.card]
type = "diffuse"
reflectance = 0.5

[[shapes]]
type = "quad"
corners = [[-1.5, 1.0, -1.5], [-1.5, 1.0, 0.5], [0.5, 1.0, 0.5], [0.5, 1.0, -1.5]]
material = "pane"

[[shapes]]
type = "quad"
corners = [[0.8, 0.6, 0.2], [0.8, 0.6, 1.8], [2.2, 0.6, 1.8], [2.2, 0.6, 0.2]]
material = "card"

[[lights]]
type = "point"
position = [0.3, 2.5, -0.2]
intensity = [3.0, 2.0, 1.5]

[[lights]]
type = "spot"
position = [-1.0, 3.0, 0.5]
direction = [0.2, -1.0, 0.1]
cutoff_deg = 35.0
profile = "linear"
intensity = [4.0, 4.0, 3.0]

[[lights]]
type = "spot"
position = [1.5, 2.8, -1.0]
direction = [-0.3, -1.0, 0.2]
cutoff_deg = 40.0
inner_deg = 20.0
profile = "smooth"
intensity = [2.0, 3.0, 4.0]

[[lights]]
type = "spot"
position = [0.0, 3.2, 1.5]
direction = [0.0, -1.0, -0.3]
cutoff_deg = 25.0
profile = "hard"
intensity = 5.0

%QUAD_LIGHT%
[[lights]]
type = "directional"
direction = [0.3, -1.0, 0.2]
irradiance = [0.8, 0.8, 0.7]
"#;

/// The quad light of [`SCENE`], left out where the GPU's twin draws
/// random numbers the Rust one cannot (the march's light points).
const QUAD_LIGHT: &str = r#"[[lights]]
type = "quad"
corners = [[-0.5, 3.5, -0.5], [0.5, 3.5, -0.5], [0.5, 3.5, 0.5], [-0.5, 3.5, 0.5]]
radiance = [1.5, 1.2, 1.0]
"#;

/// [`SCENE`] with its quad light, or without it (delta lights only).
fn scene_text(with_quad_light: bool) -> String {
    SCENE.replace(
        "%QUAD_LIGHT%",
        if with_quad_light { QUAD_LIGHT } else { "" },
    )
}

/// A deterministic spread of numbers in [0, 1): the golden-ratio sequence.
fn spread(i: usize) -> f32 {
    (i as f64 * 0.618_033_988_749_895).fract() as f32
}

fn d(v: Vec3) -> DVec3 {
    v.as_dvec3()
}

struct Fixture {
    gpu: tyndall_gpu::Gpu,
    scene: Scene,
    march: GpuMarch,
    visibility: Visibility,
    /// The march's lattice step.
    step: f32,
    settings: RenderSettings,
}

fn fixture(test: &str) -> Option<Fixture> {
    fixture_of(test, &scene_text(true))
}

fn fixture_of(test: &str, text: &str) -> Option<Fixture> {
    fixture_seeing(test, text, VisibilityMode::ShadowRays)
}

/// The scene `text` uploaded with lights seen through `visibility` on
/// both sides.
fn fixture_seeing(test: &str, text: &str, visibility: VisibilityMode) -> Option<Fixture> {
    let gpu = support::gpu_or_skip(test)?;
    let (desc, scene) = support::scene_in_folder(test, text, &[]);
    let settings = RenderSettings {
        visibility,
        ..desc.settings
    };
    let march = GpuMarch::new(&gpu, &scene, &MarchSettings::from(&settings)).expect("upload");
    let visibility = Visibility::new(&scene, visibility);
    Some(Fixture {
        gpu,
        scene,
        march,
        visibility,
        step: settings.step,
        settings,
    })
}

/// The ray from the camera (at (0, 0, 9)) towards `target` and the
/// distance to its first hit (∞ past everything).
fn camera_ray_towards(f: &Fixture, target: Vec3) -> (tyndall::ray::Ray, f32) {
    let origin = Vec3::new(0.0, 0.0, 9.0);
    let ray = tyndall::ray::Ray::new(origin, target - origin);
    let t_hit = f
        .scene
        .geometry()
        .intersect(&ray, f32::INFINITY)
        .map_or(f32::INFINITY, |h| h.t);
    (ray, t_hit)
}

/// A probe item for a ray over (0, t_hit) (∞ as WGSL's stand-in 3·10³⁸)
/// and an integer `key` below 2²⁴ (a jitter's or a seed's).
fn ray_item(ray: &tyndall::ray::Ray, t_hit: f32, key: u32) -> [[f32; 4]; 3] {
    let (o, w) = (ray.origin, ray.direction);
    [
        [o.x, o.y, o.z, t_hit.min(3.0e38)],
        [w.x, w.y, w.z, 0.0],
        [key as f32, 0.0, 0.0, 0.0],
    ]
}

/// Receivers spread over the fog box, with the light's sample numbers.
fn cases(lights: usize, per_light: usize) -> Vec<(usize, Vec3, Vec2, usize)> {
    let mut out = Vec::new();
    for l in 0..lights {
        for i in 0..per_light {
            let x = Vec3::new(
                7.0 * spread(3 * i) - 3.5,
                6.0 * spread(3 * i + 1) - 3.5,
                7.0 * spread(3 * i + 2) - 3.5,
            );
            let u = Vec2::new(spread(5 * i + 7 * l + 1), spread(11 * i + 3 * l + 2));
            out.push((l, x, u, i));
        }
    }
    out
}

/// (corner, edge a, edge b) of [`SCENE`]'s horizontal quads: the pane, the
/// card and the quad light (a shape too, opaque to the shadow rays of the
/// others).
const QUADS: [(Vec3, Vec3, Vec3); 3] = [
    (
        Vec3::new(-1.5, 1.0, -1.5),
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::new(2.0, 0.0, 0.0),
    ),
    (
        Vec3::new(0.8, 0.6, 0.2),
        Vec3::new(0.0, 0.0, 1.6),
        Vec3::new(1.4, 0.0, 0.0),
    ),
    (
        Vec3::new(-0.5, 3.5, -0.5),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
    ),
];

/// Whether the segment from `x` over `distance` along `direction` passes
/// within `margin` (relative to a quad's size) of the edge of one of the
/// scene's quads, or `x` lies within `margin` of their planes: cases
/// where rounding may decide visibility.
fn near_an_occluder_edge(x: Vec3, direction: Vec3, distance: f32, margin: f64) -> bool {
    let (o, w) = (d(x), d(direction));
    for (corner, a, b) in QUADS.map(|(c, a, b)| (d(c), d(a), d(b))) {
        let plane_y = corner.y;
        if (o.y - plane_y).abs() < margin {
            return true;
        }
        if w.y.abs() < 1e-12 {
            continue;
        }
        let t = (plane_y - o.y) / w.y;
        if t <= 0.0 || t >= f64::from(distance) {
            continue;
        }
        let p = o + w * t - corner;
        let (s, r) = (p.dot(a) / a.length_squared(), p.dot(b) / b.length_squared());
        let inside = |v: f64| (-margin..=1.0 + margin).contains(&v);
        let clear = |v: f64| (margin..=1.0 - margin).contains(&v);
        if inside(s) && inside(r) && !(clear(s) && clear(r)) {
            return true;
        }
    }
    false
}

/// The relative error bound of the light's irradiance `E` at `x` from
/// its point `y`, or `None` where the two sides may disagree about any
/// light at all (a spot's edge, an emitter's plane): E = I·f(cos)/d² or
/// L·A·cos_y/d². The direction's rounding is δ = 16ε(|x| + |y|)/d; a
/// spot's profile moves by |f'|·δ (f' by a difference quotient over δ);
/// the squares, divisions and products add 16ε. `moved` bounds how far
/// the two sides' receivers may lie apart besides (a lattice point
/// computed with or without a fused multiply-add).
fn irradiance_tolerance(light: &Light, x: Vec3, y: Vec3, moved: f64) -> Option<f64> {
    let dist = d(y - x).length();
    let delta = (16.0 * EPS * (d(x).length() + d(y).length()) + moved) / dist + 8.0 * EPS;
    let profile = match light {
        Light::Spot(s) => {
            let c = -d((y - x).normalize()).dot(d(s.direction));
            if (c - f64::from(s.cos_cutoff)).abs() < 1e-3 {
                return None;
            }
            let f = f64::from(s.falloff(c as f32));
            let (lo, hi) = (
                f64::from(s.falloff((c - delta) as f32)),
                f64::from(s.falloff((c + delta) as f32)),
            );
            if f == 0.0 {
                return None;
            }
            ((hi - f).abs().max((lo - f).abs()) + 8.0 * EPS * f) / f
        }
        Light::Quad(q) => {
            let cos_y = -d(q.quad.normal).dot(d(y - x)) / dist;
            if cos_y.abs() < 1e-2 {
                return None;
            }
            delta / cos_y.abs()
        }
        _ => 0.0,
    };
    Some(profile + 2.0 * delta + 16.0 * EPS)
}

/// A receiver both sides may be compared at: the light's point `y` for
/// sample numbers `u` and its light at `x` (Rust's), the point as a
/// position (one unit along the direction for a sun), and the
/// irradiance's relative tolerance.
struct Comparable {
    y: Option<LightPoint>,
    inc: Incident,
    point: Vec3,
    irradiance: f64,
}

/// The comparable case of light `light` at receiver `x` with sample
/// numbers `u`, or `None` where the light does not reach `x` or the sides
/// may legitimately disagree ([`irradiance_tolerance`],
/// [`near_an_occluder_edge`] at 10⁻⁴).
fn comparable(light: &Light, x: Vec3, u: Vec2) -> Option<Comparable> {
    comparable_within(light, x, u, 1e-4)
}

/// [`comparable`], with shadow rays within `edge_margin` of an occluder's
/// edge left out.
fn comparable_within(light: &Light, x: Vec3, u: Vec2, edge_margin: f64) -> Option<Comparable> {
    let y = light.sample_point(u);
    let inc = light.incident(x, y)?;
    let point = y.map_or(x + inc.direction, |p| p.position);
    let irradiance = irradiance_tolerance(light, x, point, 0.0)?;
    if near_an_occluder_edge(x, inc.direction, inc.distance, edge_margin) {
        return None;
    }
    Some(Comparable {
        y,
        inc,
        point,
        irradiance,
    })
}

/// Compares one GPU output with its Rust twin, channel by channel, to the
/// relative tolerance `tolerance` (plus 10⁻³⁰ absolute for zeros).
fn assert_close(what: &str, gpu: Vec3, rust: Vec3, tolerance: f64) {
    for c in 0..3 {
        let (g, r) = (f64::from(gpu[c]), f64::from(rust[c]));
        assert!(
            (g - r).abs() <= tolerance * r.abs() + 1e-30,
            "{what}, channel {c}: GPU {gpu} vs Rust {rust} (relative tolerance {tolerance:.2e})"
        );
    }
}

/// The rest of the product, relative, for a receiver `x` and a light
/// `dist` away: fog transmittance exp(−σt·s) over the fogged length s ≤
/// min(d, the box's diagonal) (WGSL's exp within 3 + 2σt·s ULP; s clipped
/// by the box's slabs, rounded by 16ε of |x| + the box's size 8 + s,
/// times σt), the glass tints (4ε a pane, two panes at most), and the
/// products (8ε).
fn transport_tolerance(sigma_t: f64, x: Vec3, dist: f64) -> f64 {
    let fogged = dist.min(8.0 * 3f64.sqrt());
    let optical = sigma_t * fogged;
    let clipping = sigma_t * 16.0 * EPS * (d(x).length() + 8.0 + fogged);
    (4.0 + 4.0 * optical) * EPS + clipping + 8.0 * EPS + 8.0 * EPS
}

/// The phase function p(cos θ) at cos θ = ω·view (g = 0.4, the scene's),
/// relative: its own rounding (tests/formulas.rs, 2(4.5ε·S/D + 10ε)) and
/// its change over the direction's rounding δ (with `moved` as in
/// [`irradiance_tolerance`]), |p'|·δ/p with p'/p = 3g/D.
fn phase_tolerance(direction: Vec3, view: Vec3, x: Vec3, point: Vec3, moved: f64) -> f64 {
    let g = 0.4f64;
    let cos = d(direction).dot(d(view));
    let denom = 1.0 + g * g - 2.0 * g * cos;
    let size = 1.0 + g * g + 2.0 * (g * cos).abs();
    let delta = (16.0 * EPS * (d(x).length() + d(point).length()) + moved)
        / d(point - x).length().max(1.0)
        + 8.0 * EPS;
    2.0 * (4.5 * EPS * size / denom + 10.0 * EPS) + 3.0 * g * delta / denom
}

#[test]
fn light_arriving_matches_rust() {
    let Some(f) = fixture("light_arriving_matches_rust") else {
        return;
    };
    check_light_arriving(&f, 1e-4, 0.0);
}

/// Resolution of the shadow maps both sides build for
/// [`light_arriving_through_shadow_maps_matches_rust`].
const MAP_RESOLUTION: u32 = 512;

/// `light_arriving` through the deep coloured shadow maps the GPU traces
/// (`trace_texel`) and looks up (`map_transmittance`) against the CPU's
/// (`ShadowMaps::build` and `::transmittance`), both at 512² texels a
/// face. The two trace their texels along the same rays through the same
/// geometry, so their maps differ only at texels whose ray passes within
/// rounding of an occluder's edge, and a lookup reads the four texels
/// around its point: receivers whose shadow ray passes within two texels
/// of an edge are left out. A texel spans at most 2/R rad of a point or
/// spot light's view (a cube face's centre; a spot's narrower face less)
/// and 2·4/R scene units of a sun's orthographic map over the fog box,
/// and no occluder lies over 4 units from a light: two texels are under
/// 16/R units at an occluder, or 16/R of its shortest edge (1 unit) in
/// the quads' coordinates. The bilinear weights round by 8ε more.
#[test]
fn light_arriving_through_shadow_maps_matches_rust() {
    let Some(f) = fixture_seeing(
        "light_arriving_through_shadow_maps_matches_rust",
        &scene_text(true),
        VisibilityMode::Maps {
            resolution: MAP_RESOLUTION,
        },
    ) else {
        return;
    };
    // Besides the spread receivers, receivers just behind the card and
    // the pane as each point or spot light sees them (0.02 to 0.8 past
    // them along its rays), where a map's depth test and bias decide.
    let mut behind = Vec::new();
    // The pane and the card (QUADS' first two).
    let occluders = &QUADS[..2];
    for (l, light) in f.scene.lights().iter().enumerate() {
        let Some(position) = light.position() else {
            continue;
        };
        for &(corner, a, b) in occluders {
            for k in 0..64 {
                let p =
                    corner + a * (0.1 + 0.8 * spread(2 * k)) + b * (0.1 + 0.8 * spread(2 * k + 1));
                let w = (p - position).normalize();
                let depth = [0.02, 0.1, 0.3, 0.8][k % 4];
                behind.push((l, p + w * depth, Vec2::ZERO, 3 * k + 2));
            }
        }
    }
    check_light_arriving_at(&f, &behind, 16.0 / f64::from(MAP_RESOLUTION), 8.0 * EPS, 10);
    check_light_arriving(&f, 16.0 / f64::from(MAP_RESOLUTION), 8.0 * EPS);
}

/// `light_arriving` against its twin at receivers spread over the fog box
/// (a third on surfaces facing up, a third down), shadow rays within
/// `edge_margin` of an occluder's edge left out, `extra` added to the
/// relative tolerance.
fn check_light_arriving(f: &Fixture, edge_margin: f64, extra: f64) {
    let all = cases(f.scene.lights().len(), 800);
    check_light_arriving_at(f, &all, edge_margin, extra, 150);
}

/// [`check_light_arriving`] at the receivers `all` (light, x, sample
/// numbers, case number: case i % 3 picks up, down or no surface), each
/// light compared at more than `least` of them.
fn check_light_arriving_at(
    f: &Fixture,
    all: &[(usize, Vec3, Vec2, usize)],
    edge_margin: f64,
    extra: f64,
    least: usize,
) {
    let lights = f.scene.lights();
    let mut items = Vec::new();
    for &(l, x, u, i) in all {
        // Every third receiver is on a surface whose normal faces up or
        // down, the shadow ray then leaving just off it.
        let (on_surface, normal) = match i % 3 {
            0 => (1.0, Vec3::Y),
            1 => (1.0, -Vec3::Y),
            _ => (0.0, Vec3::ZERO),
        };
        items.push([
            [x.x, x.y, x.z, on_surface],
            [normal.x, normal.y, normal.z, 0.0],
            [l as f32, u.x, u.y, 0.0],
        ]);
    }
    let out = evaluate_in_scene(&f.gpu, &f.march, SceneFormula::LightArriving, &items)
        .expect("GPU evaluation");
    let sigma_t = f64::from(f.scene.fog().expect("fog").sigma_t);
    let mut compared = vec![0usize; lights.len()];
    let mut lit = vec![0usize; lights.len()];
    for ((&(l, x, u, _), item), o) in all.iter().zip(&items).zip(&out) {
        let light = &lights[l];
        let Some(Comparable {
            inc, irradiance, ..
        }) = comparable_within(light, x, u, edge_margin)
        else {
            continue;
        };
        let normal = (item[0][3] == 1.0).then(|| Vec3::new(item[1][0], item[1][1], item[1][2]));
        let rust = twins::light_arriving(&f.scene, &f.visibility, l, x, normal, &inc);
        let gpu = Vec3::new(o[0][0], o[0][1], o[0][2]);
        assert_eq!(
            o[0][3], 1.0,
            "light #{l} at {x}: the GPU's incident is invalid"
        );
        let dist = f64::from(inc.distance).min(1e6);
        let tolerance = 2.0 * (irradiance + transport_tolerance(sigma_t, x, dist)) + extra;
        assert_close(
            &format!("light #{l} {light:?}, x = {x}, normal {normal:?}, u = {u}"),
            gpu,
            rust,
            tolerance,
        );
        compared[l] += 1;
        lit[l] += usize::from(rust != Vec3::ZERO);
    }
    for l in 0..lights.len() {
        let mentioned = all.iter().any(|c| c.0 == l);
        assert!(
            !mentioned || (compared[l] > least && lit[l] > least / 3),
            "light #{l}: {} compared, {} lit",
            compared[l],
            lit[l]
        );
    }
}

#[test]
fn scattered_radiance_matches_rust() {
    let Some(f) = fixture("scattered_radiance_matches_rust") else {
        return;
    };
    let lights = f.scene.lights();
    let fog = f.scene.fog().expect("fog");
    let all = cases(lights.len(), 800);
    let mut items = Vec::new();
    let mut views = Vec::new();
    for &(l, x, u, i) in &all {
        let view = Vec3::new(
            spread(7 * i + 1) - 0.5,
            spread(7 * i + 2) - 0.5,
            spread(7 * i + 3) - 0.5,
        )
        .normalize_or(Vec3::Z);
        views.push(view);
        items.push([
            [x.x, x.y, x.z, 0.0],
            [view.x, view.y, view.z, 0.0],
            [l as f32, u.x, u.y, 0.0],
        ]);
    }
    let out = evaluate_in_scene(&f.gpu, &f.march, SceneFormula::ScatteredRadiance, &items)
        .expect("GPU evaluation");
    let sigma_t = f64::from(fog.sigma_t);
    let mut compared = vec![0usize; lights.len()];
    for ((&(l, x, u, _), view), o) in all.iter().zip(&views).zip(&out) {
        let light = &lights[l];
        let Some(Comparable {
            y,
            inc,
            point,
            irradiance,
        }) = comparable(light, x, u)
        else {
            continue;
        };
        let rust = twins::scattered_radiance(&f.scene, &f.visibility, l, y, x, *view);
        let gpu = Vec3::new(o[0][0], o[0][1], o[0][2]);
        let dist = f64::from(inc.distance).min(1e6);
        let tolerance = 2.0 * (irradiance + transport_tolerance(sigma_t, x, dist))
            + phase_tolerance(inc.direction, *view, x, point, 0.0)
            + 8.0 * EPS;
        assert_close(
            &format!("light #{l} {light:?}, x = {x}, view {view}, u = {u}"),
            gpu,
            rust,
            tolerance,
        );
        compared[l] += 1;
    }
    for (l, n) in compared.iter().enumerate() {
        assert!(*n > 150, "light #{l}: {n} compared");
    }
}

// The file's further tests, in their own files (one test crate).
#[path = "scattering/lattice.rs"]
mod lattice;
#[path = "scattering/means.rs"]
mod means;
