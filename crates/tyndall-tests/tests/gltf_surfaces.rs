//! glTF surfaces point by point: base colour textures (with
//! `KHR_texture_transform`), vertex colours and alpha cut-outs, each
//! against the closed form of a sunlit floor.

mod common;
mod gltf_files;

use glam::Vec3;
use gltf_files::{MeshData, floor_uv, square, sunlit, test_dir, write_gltf};
use serde_json::{Value, json};
use std::f32::consts::PI;
use tyndall::IntegratorKind;
use tyndall::color::Rgb;
use tyndall::ray::Ray;

/// The 2×2 colour checker the texture tests write, texel by texel, row by
/// row: red, green, blue, white.
const CHECKER: [Rgb; 4] = [
    Rgb::new(1.0, 0.0, 0.0),
    Rgb::new(0.0, 1.0, 0.0),
    Rgb::new(0.0, 0.0, 1.0),
    Rgb::new(1.0, 1.0, 1.0),
];

/// Writes [`CHECKER`] as `dir/checker.png`.
fn write_checker(dir: &std::path::Path) {
    tyndall_image::output::write_image(
        &tyndall::Image::from_pixels(2, 2, CHECKER.to_vec()),
        &dir.join("checker.png"),
        0.0,
    )
    .expect("png");
}

/// The radiance straight up from the point under `(x, z)` met by a ray
/// down from height `y`, by `kind`.
fn looking_down(desc: &common::Loaded, kind: IntegratorKind, x: f32, y: f32, z: f32) -> Rgb {
    let ray = Ray::new(Vec3::new(x, y, z), Vec3::new(0.0, -1.0, 0.0));
    common::estimate_ray(desc, kind, 0.1, ray, 4).0
}

/// A base colour texture colours the surface point by point (issue 12):
/// a floor whose texture coordinates map it onto a 2×2 image of red,
/// green, blue and white texels (written as PNG here), under a sun
/// straight overhead, is lit as `factor·texel/π·E` at each texel's
/// centre and as the mean of two texels halfway between them (bilinear
/// filtering), by `single` and `volpath`. Without TEXCOORD_0 the
/// texture's mean colour applies, with a warning.
#[test]
fn base_colour_texture_colours_points() {
    let dir = test_dir("texture");
    write_checker(&dir);
    let texels = CHECKER;
    let factor = 0.8f32;
    let doc = sunlit(
        1,
        json!({
            "images": [{"uri": "checker.png"}],
            "samplers": [{"wrapS": 33071, "wrapT": 33071}],
            "textures": [{"source": 0, "sampler": 0}],
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [factor, factor, factor, 1.0],
                                                    "baseColorTexture": {"index": 0},
                                                    "metallicFactor": 0.0},
                           "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
        }),
    );
    let floor = |uv| square(0.0, 2.0, 0, uv);
    let textured = common::load_gltf(&write_gltf(
        &dir,
        "textured",
        &[floor(Some(floor_uv))],
        doc.clone(),
    ))
    .expect("loads");
    let untextured =
        common::load_gltf(&write_gltf(&dir, "no-uvs", &[floor(None)], doc)).expect("loads");
    assert!(
        untextured.warnings.iter().any(|w| w.contains("TEXCOORD_0")),
        "{:?}",
        untextured.warnings
    );
    // E = 683 lx / 683 lm/W = 1 W/m².
    let lit = |colour: Rgb| colour * (factor / PI);
    let mean = (texels[0] + texels[1] + texels[2] + texels[3]) / 4.0;
    let cases = [
        (&textured, [-1.0, -1.0], lit(texels[0])),
        (&textured, [1.0, -1.0], lit(texels[1])),
        (&textured, [-1.0, 1.0], lit(texels[2])),
        (&textured, [1.0, 1.0], lit(texels[3])),
        (&textured, [0.0, -1.0], lit((texels[0] + texels[1]) / 2.0)),
        (&untextured, [0.7, -1.3], lit(mean)),
    ];
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        for (desc, [x, z], expected) in cases {
            let ray = Ray::new(Vec3::new(x, 1.0, z), Vec3::new(0.0, -1.0, 0.0));
            let (got, _) = common::estimate_ray(desc, kind, 0.1, ray, 16);
            assert!(
                (got - expected).abs().max_element() < 1e-5,
                "{kind:?} at ({x}, {z}): {got} vs {expected}"
            );
        }
    }
    // The albedo guide (AOV, issue 24) is the textured reflectance itself:
    // `factor·texel`, point by point.
    for (desc, [x, z], expected) in cases {
        let ray = Ray::new(Vec3::new(x, 1.0, z), Vec3::new(0.0, -1.0, 0.0));
        let guide = tyndall::guides::first_surface(&desc.scene, ray, None);
        let albedo = expected * PI;
        assert!(
            (guide.albedo - albedo).abs().max_element() < 1e-5,
            "albedo at ({x}, {z}): {} vs {albedo}",
            guide.albedo
        );
    }
}

/// An emission texture makes a surface glow point by point, over the
/// light it reflects (glTF adds emission to the BRDF, as Cycles does; the
/// DamagedHelmet's visor and lamps): a grey floor (base colour 0.8,
/// Lambert) emitting `2 · texel` of the colour checker, under a sun
/// straight down (E = 1 W/m²), leaves `2·texel + 0.8/π` at each texel's
/// centre and the mean of two texels' glow halfway between them, by
/// `single` and `volpath`; its albedo guide is the grey it reflects.
/// Without TEXCOORD_0 the texture is not applied, with a warning, and the
/// floor glows `emissiveFactor` everywhere.
#[test]
fn emission_texture_glows_point_by_point() {
    let dir = test_dir("emission-texture");
    write_checker(&dir);
    let texels = CHECKER;
    let doc = sunlit(
        1,
        json!({
            "images": [{"uri": "checker.png"}],
            "samplers": [{"wrapS": 33071, "wrapT": 33071}],
            "textures": [{"source": 0, "sampler": 0}],
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0],
                                                    "metallicFactor": 0.0},
                           "emissiveFactor": [1.0, 1.0, 1.0],
                           "emissiveTexture": {"index": 0},
                           "extensions": {"KHR_materials_specular": {"specularFactor": 0.0},
                                          "KHR_materials_emissive_strength": {"emissiveStrength": 2.0}}}],
            "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular",
                               "KHR_materials_emissive_strength"]
        }),
    );
    let floor = |uv| square(0.0, 2.0, 0, uv);
    let glowing = common::load_gltf(&write_gltf(
        &dir,
        "glowing",
        &[floor(Some(floor_uv))],
        doc.clone(),
    ))
    .expect("loads");
    let plain = common::load_gltf(&write_gltf(&dir, "no-uvs", &[floor(None)], doc)).expect("loads");
    assert!(
        plain
            .warnings
            .iter()
            .any(|w| w.contains("emissiveTexture") && w.contains("TEXCOORD_0")),
        "{:?}",
        plain.warnings
    );
    let reflected = Rgb::splat(0.8 / PI);
    let glow = |texel: Rgb| texel * 2.0 + reflected;
    let cases = [
        (&glowing, [-1.0, -1.0], glow(texels[0])),
        (&glowing, [1.0, -1.0], glow(texels[1])),
        (&glowing, [-1.0, 1.0], glow(texels[2])),
        (&glowing, [1.0, 1.0], glow(texels[3])),
        (&glowing, [0.0, 1.0], glow((texels[2] + texels[3]) / 2.0)),
        (&plain, [0.7, -1.3], glow(Rgb::ONE)),
    ];
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        for (desc, [x, z], expected) in cases {
            let got = looking_down(desc, kind, x, 1.0, z);
            assert!(
                (got - expected).abs().max_element() < 1e-5,
                "{kind:?} at ({x}, {z}): {got} vs {expected}"
            );
        }
    }
    for (desc, [x, z], _) in cases {
        let ray = Ray::new(Vec3::new(x, 1.0, z), Vec3::new(0.0, -1.0, 0.0));
        let guide = tyndall::guides::first_surface(&desc.scene, ray, None);
        assert!(
            (guide.albedo - Rgb::splat(0.8)).abs().max_element() < 1e-5,
            "albedo at ({x}, {z}): {}",
            guide.albedo
        );
    }
}

/// A `metallicRoughnessTexture` varies the surface point by point (its
/// blue channel the metalness, its green the roughness, read as data and
/// multiplied by the factors): a floor of base colour 0.8, metallicFactor
/// 1, roughnessFactor 0.5 and F0 = 0 (specularFactor 0), the colour
/// checker as its texture, so that red and green texels are dielectric
/// (m = 0) and blue and white ones metal (m = 1), green and white rough
/// (α = 0.5²) and red and blue smooth. Under a sun straight down, seen
/// from straight above, the diffuse part gives `0.8·(1 − m)/π` and a
/// rough metal's glossy layer, of reflectance 0.8·m, its GGX lobe at its
/// peak (the sun in the mirror direction: `D·G₂/4 = 1/(4πα²)`, [`ggx_f_cos`])
/// times its compensated reflectance ([`compensated`]; within 3·10⁻³ of
/// it, the albedo table's error); a smooth one reflects the sun to no
/// one: so at each texel's centre, and halfway between a smooth
/// dielectric and a smooth metal texel `0.4/π`, by `single` and
/// `volpath`; the surface there is
/// `MetallicRoughness::surface` of those parameters, written out here.
/// Without the texture's TEXCOORD the factors hold, with a warning.
#[test]
fn metallic_roughness_texture_varies_the_surface() {
    use tyndall::materials::Surface;
    let dir = test_dir("metallic-roughness");
    write_checker(&dir);
    let doc = sunlit(
        1,
        json!({
            "images": [{"uri": "checker.png"}],
            "samplers": [{"wrapS": 33071, "wrapT": 33071}],
            "textures": [{"source": 0, "sampler": 0}],
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0],
                                                    "metallicFactor": 1.0,
                                                    "roughnessFactor": 0.5,
                                                    "metallicRoughnessTexture": {"index": 0}},
                           "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
        }),
    );
    let floor = |uv| square(0.0, 2.0, 0, uv);
    let mapped = common::load_gltf(&write_gltf(
        &dir,
        "mapped",
        &[floor(Some(floor_uv))],
        doc.clone(),
    ))
    .expect("loads");
    let plain = common::load_gltf(&write_gltf(&dir, "no-uvs", &[floor(None)], doc)).expect("loads");
    assert!(
        plain
            .warnings
            .iter()
            .any(|w| w.contains("metallicRoughnessTexture") && w.contains("TEXCOORD_0")),
        "{:?}",
        plain.warnings
    );
    assert!(
        !mapped
            .warnings
            .iter()
            .any(|w| w.contains("metallicRoughness")),
        "{:?}",
        mapped.warnings
    );
    // (metalness, roughness) at each point, from the texels' channels.
    let cases = [
        (&mapped, [-1.0, -1.0], (0.0, 0.0)),
        (&mapped, [1.0, -1.0], (0.0, 0.5)),
        (&mapped, [-1.0, 1.0], (1.0, 0.0)),
        (&mapped, [1.0, 1.0], (1.0, 0.5)),
        (&mapped, [-1.0, 0.0], (0.5, 0.0)),
        (&plain, [0.7, -1.3], (1.0, 0.5)),
    ];
    for (desc, [x, z], (m, r)) in cases {
        let glossy = match r > 0.0 {
            true => {
                let alpha = f64::from(r * r);
                let up = glam::DVec3::Y;
                (compensated(0.8 * f64::from(m), ggx_albedo(alpha, 1.0)) * ggx_f_cos(alpha, up, up))
                    as f32
            }
            false => 0.0,
        };
        let expected = Rgb::splat(0.8 * (1.0 - m) / PI + glossy);
        for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
            let got = looking_down(desc, kind, x, 1.0, z);
            assert!(
                (got - expected).abs().max_element() < 1e-5 + 3e-3 * glossy,
                "{kind:?} at ({x}, {z}): {got} vs {expected}"
            );
        }
        let ray = Ray::new(Vec3::new(x, 1.0, z), Vec3::new(0.0, -1.0, 0.0));
        let hit = desc
            .scene
            .intersect(&ray, f32::INFINITY)
            .expect("the floor");
        let tyndall::materials::Material::Opaque(surface) = *desc.scene.material(hit.primitive)
        else {
            panic!("{:?}", desc.scene.material(hit.primitive))
        };
        let at = desc.scene.surface_at(
            surface,
            hit.primitive,
            ray.at(hit.t),
            tyndall::footprint::Footprint::POINT,
        );
        let base = Rgb::splat(0.8);
        let diffuse = base * (1.0 - m);
        let specular = base * m;
        let close = |a: Rgb, b: Rgb| (a - b).abs().max_element() < 1e-5;
        if m == 0.0 {
            assert_eq!(at, Surface::diffuse(diffuse), "({x}, {z})");
        } else {
            assert!(
                close(at.diffuse, diffuse)
                    && close(at.specular, specular)
                    && (at.roughness - r * r).abs() < 1e-6,
                "({x}, {z}): {at:?}"
            );
        }
    }
}

/// `KHR_texture_transform` on a base colour texture: a 2×2 checker
/// (clamped) over a floor, its coordinates rotated a quarter turn and
/// offset by (0, 1), so that a point of coordinates (u, v) shows the
/// texel at `(v, 1 − u)` — the extension's `T·R·S` with its rotation
/// matrix `[cos sin; −sin cos]`, written out here. Each quadrant's
/// centre, lit by a sun straight down, shows that texel's colour.
#[test]
fn texture_transform_moves_the_texture() {
    let dir = test_dir("texture-transform");
    write_checker(&dir);
    let doc = sunlit(
        1,
        json!({
            "images": [{"uri": "checker.png"}],
            "samplers": [{"wrapS": 33071, "wrapT": 33071}],
            "textures": [{"source": 0, "sampler": 0}],
            "materials": [{"pbrMetallicRoughness": {
                               "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {
                                   "offset": [0.0, 1.0], "rotation": std::f32::consts::FRAC_PI_2}}},
                               "metallicFactor": 0.0},
                           "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
        }),
    );
    let floor = square(0.0, 2.0, 0, Some(floor_uv));
    let desc = common::load_gltf(&write_gltf(&dir, "turned", &[floor], doc)).expect("loads");
    assert!(
        desc.warnings
            .iter()
            .all(|w| !w.contains("KHR_texture_transform")),
        "{:?}",
        desc.warnings
    );
    for (x, z) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
        let [u, v] = floor_uv([x, 0.0, z]);
        // (u, v) ↦ (v, 1 − u), then the texel whose quadrant holds it.
        let (tu, tv) = (v, 1.0 - u);
        let texel = CHECKER[2 * usize::from(tv > 0.5) + usize::from(tu > 0.5)];
        let expected = texel / PI;
        let got = looking_down(&desc, IntegratorKind::Single, x, 1.0, z);
        assert!(
            (got - expected).abs().max_element() < 1e-5,
            "at ({x}, {z}): {got} vs {expected}"
        );
    }
}

/// Vertex colours (`COLOR_0`) multiply an opaque surface's diffuse
/// reflectance, interpolated across each triangle by barycentric weights:
/// a floor whose corners are red, green, blue and white, lit by a sun
/// straight down (E = 1 W/m²), shows at a point of weights `w` on a
/// triangle `0.8/π · Σ wᵢ cᵢ`, by `single` and `volpath`; its albedo guide
/// is `0.8 · Σ wᵢ cᵢ`.
#[test]
fn vertex_colours_colour_the_diffuse_reflectance() {
    let dir = test_dir("vertex-colours");
    let colours = [
        [1.0f32, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
    ];
    let doc = sunlit(
        1,
        json!({
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0], "metallicFactor": 0.0},
                           "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
        }),
    );
    let floor = MeshData {
        colors: Some(colours.to_vec()),
        tangents: None,
        ..square(0.0, 2.0, 0, None)
    };
    let positions = floor.positions.clone();
    let desc = common::load_gltf(&write_gltf(&dir, "coloured", &[floor], doc)).expect("loads");
    assert!(
        desc.warnings.iter().all(|w| !w.contains("COLOR_0")),
        "{:?}",
        desc.warnings
    );
    let at = |weights: [(usize, f32); 3]| {
        let mut p = Vec3::ZERO;
        let mut c = Rgb::ZERO;
        for (i, w) in weights {
            p += Vec3::from_array(positions[i]) * w;
            c += Rgb::from_array(colours[i]) * w;
        }
        (p, c * 0.8)
    };
    let points = [
        at([(0, 0.2), (1, 0.3), (2, 0.5)]),
        at([(0, 0.6), (2, 0.1), (3, 0.3)]),
        at([(0, 0.5), (2, 0.5), (3, 0.0)]),
        at([(0, 0.05), (2, 0.05), (3, 0.9)]),
    ];
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        for (p, albedo) in points {
            let got = looking_down(&desc, kind, p.x, 1.0, p.z);
            let ray = Ray::new(p + Vec3::Y, Vec3::new(0.0, -1.0, 0.0));
            let expected = albedo / PI;
            assert!(
                (got - expected).abs().max_element() < 1e-5,
                "{kind:?} at {p}: {got} vs {expected}"
            );
            let guide = tyndall::guides::first_surface(&desc.scene, ray, None);
            assert!((guide.albedo - albedo).abs().max_element() < 1e-5);
        }
    }
}

/// Minified textures are filtered over each camera ray's footprint (ray
/// cones and MIP levels), so one sample per pixel does not alias: a floor
/// under a sun straight down, seen from 3 above over 32 × 32 pixels, its
/// 256² texture a checker of single black and white texels spread over
/// 4 × 4 (64 texels a unit), has 5 texels or more under every pixel at one
/// sample (level of detail ≥ 2.3). Every level from 1 on is the checker's
/// mean, linear ½ (sRGB code 188: 0.5029), so every pixel of a 1-spp
/// render is `0.8·0.5029/π` to f32 rounding, for `single` and `volpath`.
/// Read at full resolution, pixels would be black or white at random.
#[test]
fn a_minified_checker_is_its_mean_at_one_sample() {
    let dir = test_dir("minified");
    image::RgbImage::from_fn(256, 256, |x, y| {
        image::Rgb([if (x + y) % 2 == 0 { 255 } else { 0 }; 3])
    })
    .save(dir.join("fine.png"))
    .expect("png");
    let mut doc = sunlit(
        1,
        json!({
            "images": [{"uri": "fine.png"}],
            "textures": [{"source": 0}],
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1.0],
                                                    "baseColorTexture": {"index": 0},
                                                    "metallicFactor": 0.0},
                           "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}]
        }),
    );
    gltf_files::camera_looking_down(&mut doc, 3.0, 0.8);
    let floor = square(0.0, 2.0, 0, Some(floor_uv));
    let desc = common::load_gltf(&write_gltf(&dir, "fine", &[floor], doc)).expect("loads");
    let mean = tyndall::texture::Encoding::Srgb.decode(188);
    let expected = 0.8 * mean / PI;
    for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
        let image = common::render(&desc, |s| {
            s.integrator = kind;
            s.width = 32;
            s.height = 32;
            s.spp = 1;
        });
        for (i, p) in image.pixels().iter().enumerate() {
            assert!(
                (*p - Rgb::splat(expected)).abs().max_element() < 1e-5,
                "{kind:?}, pixel {i}: {p} vs {expected}"
            );
        }
    }
}

/// GGX's `f·cos θ_i` for a layer of reflectance 1 (single scattering),
/// written out here: `D(h)·G₂/(4·cos θ_o)` with `D = α²/(π(cos²θ_h(α² −
/// 1) + 1)²)` and the height-correlated `G₂ = 1/(1 + Λ_o + Λ_i)`,
/// `Λ = (√(1 + α²tan²θ) − 1)/2` (Walter et al. 2007; Heitz 2014).
fn ggx_f_cos(alpha: f64, o: glam::DVec3, i: glam::DVec3) -> f64 {
    if o.y <= 0.0 || i.y <= 0.0 {
        return 0.0;
    }
    let h = (o + i).normalize();
    let a2 = alpha * alpha;
    let d = a2 / (std::f64::consts::PI * (h.y * h.y * (a2 - 1.0) + 1.0).powi(2));
    let lambda = |c: f64| 0.5 * ((1.0 + a2 * (1.0 - c * c) / (c * c)).sqrt() - 1.0);
    d / (1.0 + lambda(o.y) + lambda(i.y)) / (4.0 * o.y)
}

/// The directional albedo of [`ggx_f_cos`] towards a viewer at `cos_o`:
/// its midpoint quadrature over the hemisphere (600² cells).
fn ggx_albedo(alpha: f64, cos_o: f64) -> f64 {
    let view = glam::DVec3::new(-(1.0 - cos_o * cos_o).sqrt(), cos_o, 0.0);
    let k = 600;
    let mut albedo = 0.0;
    for i in 0..k {
        let c = (i as f64 + 0.5) / k as f64;
        let s = (1.0 - c * c).sqrt();
        for j in 0..k {
            let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / k as f64;
            let w = glam::DVec3::new(s * phi.cos(), c, s * phi.sin());
            albedo += ggx_f_cos(alpha, view, w) * 2.0 * std::f64::consts::PI / (k * k) as f64;
        }
    }
    albedo
}

/// A layer of reflectance `f` with GGX's multiple scattering restored by
/// albedo scaling (Turquin 2019), its single-scattering albedo `e`:
/// `f·(1 + f(1 − e)/e)`.
fn compensated(f: f64, e: f64) -> f64 {
    f * (1.0 + f * (1.0 - e) / e)
}

/// A glossy layer reflects delta lights too (next event estimation of the
/// layer's lobe: no reflected ray can find a sun): a rough metal floor of
/// base ρ (metallic 1, roughness factor √(8/31), so α = 8/31) under a sun
/// 30° off the vertical, of irradiance E = 1 W/m² across its beam, seen
/// from 41.4° (cos θ_o = ¾) at azimuths 0°, 20° and 60° from the sun's
/// plane, reflects `ρ·(1 + ρ(1 − E_o)/E_o)·f·cos(o, sun)`: GGX's
/// single-scattering `f·cos` ([`ggx_f_cos`]) scaled for the energy its
/// single scattering loses (Turquin 2019), `E_o` the lobe's directional
/// albedo towards the viewer — here by the test's own midpoint
/// quadrature of `ggx_f_cos` over the hemisphere. Tyndall's albedo comes
/// from its table (a grid of its own samples, 10⁻³ or so): the bound is
/// 3·10⁻³ of the value. By `single` and `volpath`; the paths are
/// deterministic (nothing else is lit).
#[test]
fn glossy_layers_reflect_the_sun() {
    use glam::DVec3;
    let dir = test_dir("glossy-sun");
    let rho = 0.7f32;
    let alpha = 8.0f32 / 31.0;
    let mut doc = sunlit(
        1,
        json!({
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1.0],
                                                    "metallicFactor": 1.0,
                                                    "roughnessFactor": alpha.sqrt()}}]
        }),
    );
    // The sun's light travels along −towards_sun (its node's −z).
    let sun = 30f64.to_radians();
    let towards_sun = DVec3::new(sun.sin(), sun.cos(), 0.0);
    let turn = glam::Quat::from_rotation_arc(Vec3::NEG_Z, -towards_sun.as_vec3());
    doc["nodes"][1]["rotation"] = json!(turn.to_array());
    let floor = square(0.0, 2.0, 0, None);
    let desc = common::load_gltf(&write_gltf(&dir, "metal", &[floor], doc)).expect("loads");
    let a = f64::from(alpha);
    let cos_o = 0.75f64;
    let sin_o = (1.0 - cos_o * cos_o).sqrt();
    let albedo = ggx_albedo(a, cos_o);
    let reflectance = compensated(f64::from(rho), albedo);
    for azimuth in [0f64, 20.0, 60.0] {
        // The viewer opposite the sun, turned by `azimuth` about +y.
        let (sa, ca) = azimuth.to_radians().sin_cos();
        let viewer = DVec3::new(-sin_o * ca, cos_o, sin_o * sa);
        let expected = reflectance * ggx_f_cos(a, viewer, towards_sun);
        let target = Vec3::new(0.2, 0.0, -0.3);
        let ray = Ray::new(target + viewer.as_vec3() * 2.0, -viewer.as_vec3());
        for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
            let (seen, _) = common::estimate_ray(&desc, kind, 0.1, ray, 4);
            let seen = f64::from(seen.x);
            assert!(
                (seen - expected).abs() <= 3e-3 * expected,
                "azimuth {azimuth}°, {kind:?}: {seen} vs {expected} (E_o {albedo})"
            );
        }
    }
}

/// A normal map bends the shading normal as its texels say (the closed
/// form of a tilted plane): a flat floor whose 1×1 map holds the tangent-
/// space vector `m = 2c/255 − 1` (x and y times `scale`) shades as a
/// floor of normal `normalize(m.x·T + m.y·B + m.z·N)`, where N = +y, T =
/// +x (u grows along x) and B = −z (v grows along z, and the map's +y
/// points up its image, against v). Under a sun from the side the map
/// tilts towards, the Lambertian floor of reflectance ρ is
/// `ρ/π·E·(n·ω)`: brighter than the flat floor's `ρ/π·E·cos γ`, exactly so
/// — also where the floor's node mirrors it (T turns, B does not).
/// Where the floor carries its own TANGENT (here T = +z, not the
/// coordinates' +x), the map tilts in that frame, `B = w·(N × T)`, and a
/// mirroring node flips the handedness w it gives. (Without TANGENT the
/// loader's MikkTSpace tangents of a plane are the coordinates' own.)
/// Each map is checked by `single` and `volpath`; the paths are
/// deterministic (one sun, a diffuse floor seen from above), so the
/// estimates agree with the closed form to f32.
#[test]
fn normal_maps_tilt_the_shading_normal() {
    let dir = test_dir("normal-map");
    let rho = 0.8f32;
    let gamma = 50f32.to_radians();
    // (texel codes, scale, the direction the sun's light comes from,
    // whether the floor's node mirrors x, which turns T to −x while B
    // stays, and the floor's TANGENT if it has one)
    let cases = [
        (
            [218u8, 128, 218],
            1.0f32,
            Vec3::new(gamma.sin(), gamma.cos(), 0.0),
            false,
            None,
        ),
        (
            [218, 128, 218],
            0.5,
            Vec3::new(gamma.sin(), gamma.cos(), 0.0),
            false,
            None,
        ),
        (
            [128, 218, 218],
            1.0,
            Vec3::new(0.0, gamma.cos(), -gamma.sin()),
            false,
            None,
        ),
        (
            [200, 200, 218],
            1.0,
            Vec3::new(-gamma.sin(), gamma.cos(), -gamma.sin()).normalize(),
            true,
            None,
        ),
        // T = +z: x of the map tilts towards +z.
        (
            [218, 128, 218],
            1.0,
            Vec3::new(0.0, gamma.cos(), gamma.sin()),
            false,
            Some([0.0f32, 0.0, 1.0, 1.0]),
        ),
        // T = +z, w = −1, mirrored: w becomes +1, B = y × z = +x.
        (
            [128, 218, 218],
            1.0,
            Vec3::new(gamma.sin(), gamma.cos(), 0.0),
            true,
            Some([0.0, 0.0, 1.0, -1.0]),
        ),
    ];
    for (k, (codes, scale, towards_sun, mirrored, tangent)) in cases.into_iter().enumerate() {
        image::RgbImage::from_raw(1, 1, codes.to_vec())
            .expect("image")
            .save(dir.join(format!("normal{k}.png")))
            .expect("png");
        let mut doc = sunlit(
            1,
            json!({
                "images": [{"uri": format!("normal{k}.png")}],
                "textures": [{"source": 0}],
                "materials": [{
                    "pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1.0],
                                             "metallicFactor": 0.0},
                    "normalTexture": {"index": 0, "scale": scale},
                    "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}}],
            }),
        );
        // The sun's light travels along −towards_sun: its node's −z.
        let turn = glam::Quat::from_rotation_arc(Vec3::NEG_Z, -towards_sun);
        doc["nodes"][1]["rotation"] = json!(turn.to_array());
        if mirrored {
            doc["nodes"][0]["scale"] = json!([-1.0, 1.0, 1.0]);
        }
        let floor = MeshData {
            tangents: tangent.map(|t| vec![t; 4]),
            ..square(0.0, 2.0, 0, Some(floor_uv))
        };
        let desc = common::load_gltf(&write_gltf(&dir, &format!("bumped{k}"), &[floor], doc))
            .expect("loads");
        let c = Vec3::new(codes[0] as f32, codes[1] as f32, codes[2] as f32) / 255.0;
        let m = (c * 2.0 - Vec3::ONE) * Vec3::new(scale, scale, 1.0);
        let (t, b) = match tangent {
            Some([x, y, z, w]) => {
                let flip = if mirrored { -1.0 } else { 1.0 };
                let t = Vec3::new(x * flip, y, z);
                (t, Vec3::Y.cross(t) * (w * flip))
            }
            None if mirrored => (Vec3::NEG_X, Vec3::NEG_Z),
            None => (Vec3::X, Vec3::NEG_Z),
        };
        let n = (t * m.x + b * m.y + Vec3::Y * m.z).normalize();
        let expected = rho / PI * n.dot(towards_sun);
        assert!(
            expected > rho / PI * gamma.cos() * 1.05,
            "the case tilts towards the sun"
        );
        for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
            let seen = looking_down(&desc, kind, 0.3, 1.0, -0.4);
            assert!(
                (seen - Rgb::splat(expected)).abs().max_element() < 1e-5,
                "map {k}, {kind:?}: {seen} vs {expected}"
            );
        }
    }
}

/// `KHR_materials_clearcoat` lays a clear coat over the surface: a floor
/// of base ρ (F0 0: Lambert) under a coat of factor c takes `1 − 0.04·c`
/// of the sun's light to its base and reflects `0.04·c` of it by its own
/// GGX lobe (α = 0.5² = 0.25): seen from above, the sun straight down in
/// the mirror direction, `[(1 − 0.04·c)·ρ/π + C(0.04·c)/(4πα²)]·E` (the
/// lobe at its peak, [`ggx_f_cos`], its reflectance compensated,
/// [`compensated`]), by `single` and `volpath`; the coat itself is the
/// surface's, its roughness squared. The coat's textures are named in warnings; a
/// factor outside [0, 1] is refused naming the material.
#[test]
fn clearcoat_dims_the_base_and_coats_it() {
    let dir = test_dir("clearcoat");
    write_checker(&dir);
    let rho = 0.8f32;
    let material = |coat: Value| {
        json!({
            "images": [{"uri": "checker.png"}],
            "textures": [{"source": 0}],
            "materials": [{
                "pbrMetallicRoughness": {"baseColorFactor": [rho, rho, rho, 1.0],
                                         "metallicFactor": 0.0},
                "extensions": {"KHR_materials_specular": {"specularFactor": 0.0},
                               "KHR_materials_clearcoat": coat}}],
        })
    };
    let floor = || square(0.0, 2.0, 0, Some(floor_uv));
    for c in [0.5f32, 1.0] {
        let coat = json!({"clearcoatFactor": c, "clearcoatRoughnessFactor": 0.5,
                          "clearcoatTexture": {"index": 0}});
        let path = write_gltf(&dir, "coated", &[floor()], sunlit(1, material(coat)));
        let desc = common::load_gltf(&path).expect("loads");
        let tyndall::materials::Material::Opaque(surface) = *desc.scene.material(0) else {
            panic!("{:?}", desc.scene.material(0))
        };
        assert!((surface.coat.reflectance - 0.04 * c).abs() < 1e-7);
        assert!((surface.coat.roughness - 0.25).abs() < 1e-7);
        assert!(
            desc.warnings
                .iter()
                .any(|w| w.contains("materials[0]") && w.contains("clearcoatTexture")),
            "{:?}",
            desc.warnings
        );
        let up = glam::DVec3::Y;
        let coat = (compensated(f64::from(0.04 * c), ggx_albedo(0.25, 1.0))
            * ggx_f_cos(0.25, up, up)) as f32;
        let expected = (1.0 - 0.04 * c) * rho / PI + coat;
        for kind in [IntegratorKind::Single, IntegratorKind::Volpath] {
            let seen = looking_down(&desc, kind, 0.3, 1.0, -0.4);
            assert!(
                (seen - Rgb::splat(expected)).abs().max_element() < 1e-5 + 3e-3 * coat,
                "c {c}, {kind:?}: {seen} vs {expected}"
            );
        }
    }
    let bad = write_gltf(
        &dir,
        "bad-coat",
        &[floor()],
        sunlit(1, material(json!({"clearcoatFactor": 1.5}))),
    );
    let Err(error) = common::load_gltf(&bad) else {
        panic!("a clearcoatFactor of 1.5 loaded")
    };
    let message = error.to_string();
    assert!(
        message.contains("materials[0]") && message.contains("clearcoatFactor"),
        "{message}"
    );
}

/// A texture a material may carry that Tyndall does not apply is named
/// in a warning with the material, which says what the image lacks: the
/// occlusion a path tracer computes itself (Cycles ignores it too), and a
/// normal map on a surface that is not opaque (thin glass).
#[test]
fn unapplied_textures_are_named() {
    let dir = test_dir("unapplied");
    write_checker(&dir);
    let doc = sunlit(
        2,
        json!({
            "images": [{"uri": "checker.png"}],
            "textures": [{"source": 0}],
            "materials": [{"occlusionTexture": {"index": 0}},
                          {"normalTexture": {"index": 0},
                           "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}}}],
        }),
    );
    let floor = square(0.0, 2.0, 0, Some(floor_uv));
    let pane = square(1.0, 0.5, 1, Some(floor_uv));
    let desc = common::load_gltf(&write_gltf(&dir, "maps", &[floor, pane], doc)).expect("loads");
    for (material, texture, lacks) in [
        ("materials[0]", "occlusionTexture", "Cycles"),
        ("materials[1]", "normalTexture", "opaque"),
    ] {
        assert!(
            desc.warnings
                .iter()
                .any(|w| w.contains(material) && w.contains(texture) && w.contains(lacks)),
            "{texture}: {:?}",
            desc.warnings
        );
    }
}
