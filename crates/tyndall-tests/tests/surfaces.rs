//! Surface lighting against closed forms: a quad area light (Lambert's
//! polygon formula) and a mirror reflecting an emitter.
mod common;

use common::{estimate_ray, scene};
use glam::Vec3;
use std::f64::consts::PI;
use tyndall::IntegratorKind;
use tyndall::ray::Ray;

/// Irradiance at `p` (normal `n`) from a uniform Lambertian polygon of
/// radiance `l` facing it: Lambert's formula
/// `E = L/2 · Σ_i θ_i · (n · γ_i)`, with θ_i the angle the edge i subtends
/// at p and γ_i the unit normal of the plane through p and that edge.
fn lambert_polygon(p: [f64; 3], n: [f64; 3], corners: &[[f64; 3]], l: f64) -> f64 {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let norm = |a: [f64; 3]| {
        let len = dot(a, a).sqrt();
        [a[0] / len, a[1] / len, a[2] / len]
    };
    let mut sum = 0.0;
    for i in 0..corners.len() {
        let a = norm(sub(corners[i], p));
        let b = norm(sub(corners[(i + 1) % corners.len()], p));
        let theta = dot(a, b).clamp(-1.0, 1.0).acos();
        sum += theta * dot(n, norm(cross(a, b)));
    }
    (l / 2.0 * sum).abs()
}

/// A floor point lit by a 1 × 0.6 quad light above and to the side: the
/// floor radiance ρ/π·E, estimated with one area sample per camera sample,
/// matches Lambert's formula within 5 standard errors — by `single` and by
/// `volpath` (NEE and BSDF sampling under MIS), wherever the scene stands.
///
/// The placements move the whole scene away from the origin and bring the
/// light close to the floor: a shadow ray that starts off the surface (the
/// origin offset grows with the coordinates' magnitude) must still stop
/// short of the light's own quad. It once did not (the ray's end was
/// measured from the unmoved point with a fixed margin): NEE went black
/// wherever the offset beat the margin, 2.5 % of the Cornell box's
/// one-bounce light (issue 8).
#[test]
fn quad_light_irradiance_matches_lambert() {
    for (offset, height) in [
        ([0.0, 0.0, 0.0], 1.0),
        ([-0.3, 1.2, -0.3], 0.79),
        ([60.0, -40.0, 25.0], 1.0),
    ] {
        quad_light_at(offset, height);
    }
}

fn quad_light_at(offset: [f64; 3], height: f64) {
    let at = |x: f64, y: f64, z: f64| [x + offset[0], y + offset[1], z + offset[2]];
    let corners = [
        at(0.2, height, -0.3),
        at(1.2, height, -0.3),
        at(1.2, height, 0.3),
        at(0.2, height, 0.3),
    ];
    let fmt = |c: [f64; 3]| format!("[{}, {}, {}]", c[0], c[1], c[2]);
    let eye = at(0.0, 0.5 * height, 0.0);
    let target = at(0.0, 0.0, 0.0);
    let desc = scene(&format!(
        r#"
        [camera]
        position = {}
        look_at = {}
        up = [0, 0, 1]
        fov_y_deg = 1
        [materials.floor]
        type = "diffuse"
        reflectance = 0.5
        [[shapes]]
        type = "quad"
        corners = [{}, {}, {}, {}]
        material = "floor"
        [[lights]]
        type = "quad"
        corners = [{}, {}, {}, {}]
        radiance = 3.0
        "#,
        fmt(eye),
        fmt(target),
        fmt(at(-5.0, 0.0, -5.0)),
        fmt(at(-5.0, 0.0, 5.0)),
        fmt(at(5.0, 0.0, 5.0)),
        fmt(at(5.0, 0.0, -5.0)),
        fmt(corners[0]),
        fmt(corners[1]),
        fmt(corners[2]),
        fmt(corners[3])
    ));
    // The light's normal is (c1 − c0) × (c3 − c0) = x × z = −y: it faces
    // the floor.
    let e = lambert_polygon(target, [0.0, 1.0, 0.0], &corners, 3.0);
    let expected = 0.5 / PI * e;
    assert!(expected > 0.01, "the test needs light on the point");
    let v = |c: [f64; 3]| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
    let ray = Ray::new(v(eye), -Vec3::Y);
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        let (mean, stderr) = estimate_ray(&desc, kind, 0.1, ray, 8192);
        // f32 rounding of the scene's coordinates moves the point and
        // the corners by ~1e-7 of their magnitude: far below 1e-5 of E.
        let err = (mean.x as f64 - expected).abs();
        assert!(
            err <= 5.0 * stderr.x as f64 + 1e-5 * expected,
            "{kind:?} at {offset:?}, light {height} above: {} vs Lambert {expected} (stderr {})",
            mean.x,
            stderr.x
        );
    }
}

/// A camera looks down at a mirror floor that reflects an emissive
/// ceiling through fog that absorbs only: radiance = reflectance × L_e ×
/// exp(−σt × path length).
#[test]
fn mirror_reflects_emitter_through_fog() {
    let desc = scene(
        r#"
        [camera]
        position = [0, 1, 0]
        look_at = [0, 0, 0]
        up = [0, 0, 1]
        fov_y_deg = 1
        [fog]
        sigma_t = 0.2
        albedo = 0.0
        [materials.mirror]
        type = "mirror"
        reflectance = [0.9, 0.5, 0.2]
        [materials.glow]
        type = "emissive"
        radiance = 2.0
        [[shapes]]
        type = "quad"
        corners = [[-5, 0, -5], [-5, 0, 5], [5, 0, 5], [5, 0, -5]]
        material = "mirror"
        [[shapes]]
        type = "quad"
        corners = [[-5, 3, -5], [5, 3, -5], [5, 3, 5], [-5, 3, 5]]
        material = "glow"
        "#,
    );
    let ray = Ray::new(Vec3::new(0.0, 1.0, 0.0), -Vec3::Y);
    let expected = Vec3::new(0.9, 0.5, 0.2) * 2.0 * (-0.2f32 * 4.0).exp();
    // The reflected ray starts 1e-4 off the mirror (the origin offset),
    // which changes the fog path by up to that much: a relative change of
    // σt·2e-4 = 4e-5 at most, plus float rounding.
    let tolerance = expected * (0.2 * 2e-4 + 1e-6);
    // `march` and `single` apply transmittance analytically: exact.
    for kind in [IntegratorKind::March, IntegratorKind::Single] {
        let (mean, _) = estimate_ray(&desc, kind, 0.1, ray, 4);
        assert!(
            (mean - expected).abs().cmple(tolerance).all(),
            "{kind:?}: {mean} vs {expected}"
        );
    }
    // `volpath` estimates it by free flights: within 5 standard errors.
    let (mean, stderr) = estimate_ray(&desc, IntegratorKind::Volpath, 0.1, ray, 4096);
    assert!(
        (mean - expected)
            .abs()
            .cmple(5.0 * stderr + tolerance)
            .all(),
        "volpath: {mean} ± {stderr} vs {expected}"
    );
}

/// An emissive quad shape is an area light (issue 9): it lights the scene
/// in every integrator exactly as a `[[lights]]` quad of the same corners
/// and radiance does — the same image, bit for bit. Before, `march` and
/// `single` got no light from it and `volpath` found it only by chance.
#[test]
fn emissive_quad_is_a_quad_light() {
    let common = r#"
        [camera]
        position = [0, 1, 3]
        look_at = [0, 0.5, 0]
        fov_y_deg = 50
        [render]
        width = 24
        height = 16
        spp = 4
        [fog]
        sigma_t = 0.2
        albedo = 0.8
        [materials.floor]
        type = "diffuse"
        reflectance = 0.6
        [[shapes]]
        type = "quad"
        corners = [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]]
        material = "floor"
    "#;
    let light = r#"
        [[lights]]
        type = "quad"
        corners = [[-0.5, 1.5, -0.5], [0.5, 1.5, -0.5], [0.5, 1.5, 0.5], [-0.5, 1.5, 0.5]]
        radiance = [4, 3, 2]
    "#;
    let shape = r#"
        [materials.lamp]
        type = "emissive"
        radiance = [4, 3, 2]
        [[shapes]]
        type = "quad"
        corners = [[-0.5, 1.5, -0.5], [0.5, 1.5, -0.5], [0.5, 1.5, 0.5], [-0.5, 1.5, 0.5]]
        material = "lamp"
    "#;
    let as_light = scene(&format!("{common}{light}"));
    let as_shape = scene(&format!("{common}{shape}"));
    for kind in IntegratorKind::ALL {
        let with_light = common::render(&as_light, |s| s.integrator = kind);
        let with_shape = common::render(&as_shape, |s| s.integrator = kind);
        let lit = with_light.pixels().iter().filter(|p| p.y > 0.0).count();
        assert!(lit > 0, "{kind:?}: the test needs light");
        assert!(
            with_light.pixels() == with_shape.pixels(),
            "{kind:?}: an emissive quad renders differently from a quad light"
        );
    }
}

/// An emissive sphere is an area light (issue 9): a floor point below it
/// gets the irradiance of a uniform sphere fully above its horizon,
/// `E = π·L·(r/d)²·cos α` (d from the point to the centre, α off the
/// normal), in `single` (area samples) and `volpath` (cone samples under
/// MIS with BSDF sampling), within 5 standard errors.
#[test]
fn emissive_sphere_lights_like_a_sphere() {
    let (center, radius, radiance) = ([0.6f64, 1.2, -0.3], 0.4f64, 5.0f64);
    let desc = scene(&format!(
        r#"
        [camera]
        position = [0, 0.5, 0]
        look_at = [0, 0, 0]
        up = [0, 0, 1]
        fov_y_deg = 1
        [materials.floor]
        type = "diffuse"
        reflectance = 0.5
        [materials.glow]
        type = "emissive"
        radiance = {radiance}
        [[shapes]]
        type = "quad"
        corners = [[-5, 0, -5], [-5, 0, 5], [5, 0, 5], [5, 0, -5]]
        material = "floor"
        [[shapes]]
        type = "sphere"
        center = [{}, {}, {}]
        radius = {radius}
        material = "glow"
        "#,
        center[0], center[1], center[2]
    ));
    let d2 = center.iter().map(|c| c * c).sum::<f64>();
    let cos_alpha = center[1] / d2.sqrt();
    let e = PI * radiance * radius * radius / d2 * cos_alpha;
    let expected = 0.5 / PI * e;
    let ray = Ray::new(Vec3::new(0.0, 0.5, 0.0), -Vec3::Y);
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        let (mean, stderr) = estimate_ray(&desc, kind, 0.1, ray, 8192);
        let err = (mean.x as f64 - expected).abs();
        assert!(
            err <= 5.0 * stderr.x as f64 + 1e-5 * expected,
            "{kind:?}: {} ± {} vs {expected}",
            mean.x,
            stderr.x
        );
    }
}

/// An emissive triangle mesh is an area light (issue 9): a floor point
/// below a lamp made of six triangles of different sizes and slopes (a
/// tent over an irregular convex hexagon, each triangle facing the
/// floor) gets the summed Lambert irradiance of its triangles, in
/// every integrator — `march` and `single` by area samples of a triangle
/// chosen by power, `volpath` by those under MIS with BSDF sampling —
/// within 5 standard errors. Before, `march` and `single` got no light
/// from it and `volpath` found it only by chance.
#[test]
fn emissive_mesh_lights_like_its_triangles() {
    use tyndall::description::Origin;
    use tyndall::materials::Material;
    use tyndall::shapes::{Shape, Triangle};
    let radiance = 3.0f64;
    let mut desc = scene(
        r#"
        [camera]
        position = [0, 0.5, 0]
        look_at = [0, 0, 0]
        up = [0, 0, 1]
        fov_y_deg = 1
        [materials.floor]
        type = "diffuse"
        reflectance = 0.5
        [[shapes]]
        type = "quad"
        corners = [[-5, 0, -5], [-5, 0, 5], [5, 0, 5], [5, 0, -5]]
        material = "floor"
        "#,
    )
    .desc;
    let centre = [0.5, 1.3, 0.1];
    let rim: Vec<[f64; 3]> = [0.0f64, 50.0, 110.0, 180.0, 250.0, 300.0]
        .iter()
        .zip([0.6, 0.5, 0.55, 0.7, 0.45, 0.5])
        .map(|(deg, r): (&f64, f64)| {
            let a = deg.to_radians();
            [centre[0] + r * a.cos(), 1.0, centre[2] + r * a.sin()]
        })
        .collect();
    // A convex rim: the tent's inside is then seen from the floor point
    // (below it, inside the rim) with no triangle hiding another, as the
    // summed closed form assumes.
    for i in 0..rim.len() {
        let [a, b, c] = [0, 1, 2].map(|k| rim[(i + k) % rim.len()]);
        let turn = (b[0] - a[0]) * (c[2] - b[2]) - (b[2] - a[2]) * (c[0] - b[0]);
        assert!(turn > 0.0, "the rim turns one way at every vertex");
    }
    let v = |c: [f64; 3]| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
    let triangles: Vec<[[f64; 3]; 3]> = (0..rim.len())
        .map(|i| [centre, rim[i], rim[(i + 1) % rim.len()]])
        .collect();
    let shapes = triangles
        .iter()
        .map(|t| {
            let triangle = Triangle::new(v(t[0]), v(t[1]), v(t[2])).unwrap();
            assert!(triangle.normal.y < 0.0, "each triangle faces the floor");
            Shape::Triangle(triangle)
        })
        .collect();
    let lamp = desc.add_material(
        Material::emitter(tyndall::Rgb::splat(radiance as f32), false),
        Origin::Code,
    );
    desc.add_shapes(shapes, lamp, Origin::Code);
    let lit = common::Loaded::new(desc).unwrap();
    assert_eq!(lit.desc.lighting_warnings(), Vec::<String>::new());
    let e: f64 = triangles
        .iter()
        .map(|t| lambert_polygon([0.0; 3], [0.0, 1.0, 0.0], t, radiance))
        .sum();
    let expected = 0.5 / PI * e;
    assert!(expected > 0.01, "the test needs light on the point");
    let ray = Ray::new(Vec3::new(0.0, 0.5, 0.0), -Vec3::Y);
    for kind in IntegratorKind::ALL {
        let (mean, stderr) = estimate_ray(&lit, kind, 0.1, ray, 8192);
        let err = (mean.x as f64 - expected).abs();
        assert!(
            err <= 5.0 * stderr.x as f64 + 1e-5 * expected,
            "{kind:?}: {} ± {} vs Lambert {expected}",
            mean.x,
            stderr.x
        );
    }
}
