//! Gobos (issue 23): a spot's projected image on a floor, against the
//! projection the scene format documents and the image's own texels, and
//! in fog, against a quadrature written here.

mod common;

use glam::DVec3;
use std::f64::consts::PI;

const EPS: f64 = f32::EPSILON as f64;

/// A 4×4 pattern of distinct colours, as sRGB bytes, row by row from the
/// top, written as a PNG where the scene can name it.
const PATTERN: [[u8; 3]; 16] = [
    [255, 0, 0],
    [0, 255, 0],
    [0, 0, 255],
    [255, 255, 0],
    [0, 255, 255],
    [255, 0, 255],
    [128, 64, 32],
    [32, 64, 128],
    [200, 200, 200],
    [10, 120, 10],
    [240, 120, 0],
    [60, 0, 90],
    [255, 255, 255],
    [90, 90, 0],
    [0, 90, 90],
    [20, 20, 20],
];

fn srgb_to_linear(c: u8) -> f64 {
    let v = f64::from(c) / 255.0;
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// The pattern's linear colour at image coordinates `uv` as the scene
/// format documents it: bilinear between texel centres at half-integers,
/// clamped at the edges.
fn pattern_at(u: f64, v: f64) -> DVec3 {
    let texel = |x: i64, y: i64| {
        let [r, g, b] = PATTERN[(y.clamp(0, 3) * 4 + x.clamp(0, 3)) as usize];
        DVec3::new(srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b))
    };
    let (x, y) = (u * 4.0 - 0.5, v * 4.0 - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (x0, y0) = (x0 as i64, y0 as i64);
    texel(x0, y0) * (1.0 - fx) * (1.0 - fy)
        + texel(x0 + 1, y0) * fx * (1.0 - fy)
        + texel(x0, y0 + 1) * (1.0 - fx) * fy
        + texel(x0 + 1, y0 + 1) * fx * fy
}

/// A spot at (0, 3, 0) pointing down, cutoff 30°, hard, intensity 2, its
/// gobo turned 90°, in fog when `fog`.
fn projector(fog: bool) -> common::Loaded {
    let dir = std::env::temp_dir().join(format!("tyndall-gobo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let png = dir.join("pattern.png");
    image::RgbImage::from_fn(4, 4, |x, y| image::Rgb(PATTERN[(y * 4 + x) as usize]))
        .save(&png)
        .expect("write pattern");
    let fog = if fog {
        "[fog]\nsigma_t = 0.1\nalbedo = [1, 1, 1]\ng = 0.0\n\n"
    } else {
        ""
    };
    let text = format!(
        "[camera]\nposition = [0, 1, 6]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\n\n\
         [render]\nwidth = 4\nheight = 4\nintegrator = \"single\"\n\n{fog}\
         [[lights]]\ntype = \"spot\"\nposition = [0, 3, 0]\ndirection = [0, -1, 0]\n\
         cutoff_deg = 30\nprofile = \"hard\"\nintensity = 2.0\ngobo = \"pattern.png\"\n\
         gobo_rotate_deg = 90\n"
    );
    let path = dir.join(if fog.is_empty() {
        "clear.toml"
    } else {
        "fog.toml"
    });
    std::fs::write(&path, text).expect("write scene");
    common::load_native(&path).expect("scene loads")
}

/// The projection the scene format documents for this projector: axis
/// −Y, so up is −Z turned 90° counter-clockwise seen along the beam (to
/// −X), right = axis × up (−Z); the image fills ±tan 30° on the plane at
/// unit distance. Returns the image coordinates of direction `w`.
fn projected(w: DVec3) -> Option<(f64, f64)> {
    let axis = -DVec3::Y;
    let up = -DVec3::X;
    let right = axis.cross(up);
    let along = w.dot(axis);
    if along <= 0.0 {
        return None;
    }
    let half = 30f64.to_radians().tan();
    let (px, py) = (w.dot(right) / (along * half), w.dot(up) / (along * half));
    Some((0.5 + 0.5 * px, 0.5 - 0.5 * py))
}

/// On the floor under the projector, the light at each texel centre's
/// projection is the texel's linear colour times I/d² inside the cone and
/// nothing outside it (the four corner texels lie outside the cone's
/// inscribed disc). Tolerance: the image coordinates round within 16ε,
/// which moves the bilinear value by the neighbours' differences times
/// 4·16ε; the products add 16ε.
#[test]
fn gobo_on_a_floor_is_the_image_through_the_projection() {
    let loaded = projector(false);
    let light = &loaded.scene.lights()[0];
    let half = 30f64.to_radians().tan();
    let (axis, up) = (-DVec3::Y, -DVec3::X);
    let right = axis.cross(up);
    let (mut lit, mut dark) = (0, 0);
    for j in 0..4 {
        for i in 0..4 {
            let (u, v) = ((i as f64 + 0.5) / 4.0, (j as f64 + 0.5) / 4.0);
            let (px, py) = (2.0 * u - 1.0, 1.0 - 2.0 * v);
            let w = (axis + right * (px * half) + up * (py * half)).normalize();
            assert_eq!(
                projected(w).map(|(a, b)| ((a * 8.0).round(), (b * 8.0).round())),
                Some(((u * 8.0).round(), (v * 8.0).round()))
            );
            let x = DVec3::new(0.0, 3.0, 0.0) + w * (3.0 / -w.y);
            let d2 = (x - DVec3::new(0.0, 3.0, 0.0)).length_squared();
            let inside = px * px + py * py < 1.0;
            let got = light
                .incident(x.as_vec3(), None)
                .map_or(DVec3::ZERO, |inc| inc.irradiance.as_dvec3());
            if !inside {
                assert_eq!(got, DVec3::ZERO, "texel ({i}, {j}) lies outside the cone");
                dark += 1;
                continue;
            }
            let expected = pattern_at(u, v) * 2.0 / d2;
            let spread = (0..16)
                .map(|k| {
                    let [r, g, b] = PATTERN[k];
                    srgb_to_linear(r)
                        .max(srgb_to_linear(g))
                        .max(srgb_to_linear(b))
                })
                .fold(0.0f64, f64::max);
            let tolerance =
                spread * 4.0 * 16.0 * EPS * 2.0 / d2 + 16.0 * EPS * expected.max_element();
            let error = (got - expected).abs().max_element();
            assert!(
                error <= tolerance,
                "texel ({i}, {j}): {got} vs the image's {expected}"
            );
            lit += 1;
        }
    }
    assert_eq!((lit, dark), (12, 4));
}

/// In fog, the beam's single scattering along a camera ray through it is
/// the image projected into the fog: `single`'s estimate against the
/// test's quadrature of σs·p·I·G(ω(t))·e^{−σt(t + d(t))}/d(t)² along the
/// ray (isotropic phase, 1/4π), within 4 standard errors of the estimate
/// plus the quadrature's error at the cone's edges (the integrand jumps
/// there: two jumps of at most its maximum, each off by at most half a
/// step).
#[test]
fn gobo_in_fog_scatters_the_projected_image() {
    let loaded = projector(true);
    let origin = DVec3::new(-4.0, 1.2, 0.35);
    let direction = DVec3::new(1.0, 0.0, 0.1).normalize();
    let ray = tyndall::ray::Ray::new(origin.as_vec3(), direction.as_vec3());
    let sigma = 0.1;
    let apex = DVec3::new(0.0, 3.0, 0.0);
    let n = 40_000;
    let length = 8.0;
    let h = length / n as f64;
    let mut quadrature = DVec3::ZERO;
    let mut peak: f64 = 0.0;
    for k in 0..n {
        let t = (k as f64 + 0.5) * h;
        let x = origin + direction * t;
        let to_x = x - apex;
        let d = to_x.length();
        let w = to_x / d;
        if w.dot(-DVec3::Y) <= 30f64.to_radians().cos() {
            continue;
        }
        let (u, v) = projected(w).expect("in front");
        let f = pattern_at(u, v) * 2.0 * sigma / (4.0 * PI) * (-sigma * (t + d)).exp() / (d * d);
        peak = peak.max(f.max_element());
        quadrature += f * h;
    }
    let mut settings = loaded.settings;
    settings.volume_samples = 4;
    let (mean, stderr) = common::estimate_ray_with(&loaded, settings, ray, 4000);
    for c in 0..3 {
        let tolerance = 4.0 * f64::from(stderr[c]) + 2.0 * peak * h;
        assert!(
            (f64::from(mean[c]) - quadrature[c]).abs() <= tolerance,
            "channel {c}: single {mean} ± {stderr} vs the quadrature {quadrature} (tolerance {tolerance:.2e})"
        );
    }
    // The estimate is informative: its error far below the signal.
    assert!(
        stderr.max_element() < 0.05 * mean.max_element(),
        "{mean} ± {stderr}"
    );
}

/// Spots naming one gobo file share one image (a rig of 1024 heads reads
/// and holds its pattern once), and the scene hash that render parts
/// check, which sees an image only through its digest, still tells two
/// images apart by a single texel.
#[test]
fn spots_share_one_gobo_image_and_the_scene_hash_sees_its_texels() {
    let dir = std::env::temp_dir().join(format!("tyndall-gobo-shared-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let load = |texel: [u8; 3]| {
        let mut pixels = PATTERN;
        pixels[5] = texel;
        image::RgbImage::from_fn(4, 4, |x, y| image::Rgb(pixels[(y * 4 + x) as usize]))
            .save(dir.join("pattern.png"))
            .expect("write pattern");
        let spot = |x: f32| {
            format!(
                "[[lights]]\ntype = \"spot\"\nposition = [{x}, 3, 0]\ndirection = [0, -1, 0]\n\
                 cutoff_deg = 30\nintensity = 2.0\ngobo = \"pattern.png\"\n"
            )
        };
        let text = format!(
            "[camera]\nposition = [0, 1, 6]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\n\n{}{}",
            spot(-1.0),
            spot(1.0)
        );
        let path = dir.join("pair.toml");
        std::fs::write(&path, text).expect("write scene");
        common::load_native(&path).expect("scene loads")
    };
    let images = |loaded: &common::Loaded| -> Vec<std::sync::Arc<tyndall::texture::Texture>> {
        loaded
            .scene
            .lights()
            .iter()
            .filter_map(|l| match l {
                tyndall::lights::Light::Spot(s) => s.gobo.as_ref().map(|g| g.image.clone()),
                _ => None,
            })
            .collect()
    };
    let first = load(PATTERN[5]);
    let shared = images(&first);
    assert_eq!(shared.len(), 2);
    assert!(std::sync::Arc::ptr_eq(&shared[0], &shared[1]));
    let [r, g, b] = PATTERN[5];
    let changed = load([r ^ 1, g, b]);
    let hash = |l: &common::Loaded| tyndall::parts::scene_hash(&l.scene, &l.settings);
    assert_ne!(hash(&first), hash(&changed));
    assert_eq!(hash(&first), hash(&load(PATTERN[5])));
}
