//! Shared helpers for the integration tests.
#![allow(dead_code)]

use glam::{Vec2, Vec3};
use std::path::{Path, PathBuf};
use tyndall::RayCounts;
use tyndall::ray::Ray;
use tyndall::testing::PixelSampler;
use tyndall::testing::Visibility;
use tyndall::testing::{Integrator, LightSubpaths, PixelPosition};
use tyndall::{Image, IntegratorKind, RenderSettings, Rgb, Scene, SceneDesc};
use tyndall_load::{LegacyOptions, SceneError, SourceText, legacy, native};

/// A loaded scene: its description and the runtime scene built from it,
/// with the description's settings, output and warnings at hand.
pub struct Loaded {
    pub desc: SceneDesc,
    pub scene: Scene,
    pub settings: RenderSettings,
    pub output: Option<PathBuf>,
    pub warnings: Vec<String>,
}

impl Loaded {
    /// Builds the runtime scene of `desc`.
    pub fn new(desc: SceneDesc) -> Result<Self, SceneError> {
        let scene = Scene::build(&desc)?;
        Ok(Self {
            scene,
            settings: desc.settings,
            output: desc.output.clone(),
            warnings: desc.warnings.clone(),
            desc,
        })
    }

    /// [`SceneDesc::override_fog`], then the scene rebuilt.
    pub fn override_fog(
        &mut self,
        density: Option<f32>,
        albedo: Option<f32>,
    ) -> Result<(), String> {
        self.desc.override_fog(density, albedo)?;
        self.scene = Scene::build(&self.desc).map_err(|e| e.to_string())?;
        Ok(())
    }

    /// [`SceneDesc::override_fog_asymmetry`], then the scene rebuilt.
    pub fn override_fog_asymmetry(&mut self, g: f32) -> Result<(), String> {
        self.desc.override_fog_asymmetry(g)?;
        self.scene = Scene::build(&self.desc).map_err(|e| e.to_string())?;
        Ok(())
    }
}

/// A native scene file, loaded and built.
pub fn load_native(path: &Path) -> Result<Loaded, SceneError> {
    Loaded::new(native::load(path)?)
}

/// Native scene text, parsed and built.
pub fn parse_native(source: &SourceText) -> Result<Loaded, SceneError> {
    Loaded::new(native::parse(source)?)
}

/// A legacy .obj scene file, loaded and built.
pub fn load_legacy(path: &Path, options: LegacyOptions) -> Result<Loaded, SceneError> {
    Loaded::new(legacy::load(path, options)?)
}

/// Legacy .obj scene text, parsed and built.
pub fn parse_legacy(source: &SourceText, options: LegacyOptions) -> Result<Loaded, SceneError> {
    Loaded::new(legacy::parse(source, options)?)
}

/// Any scene file (by its ending, as `tyndall render` reads it), loaded
/// and built.
pub fn load_any(path: &Path, options: tyndall_load::LoadOptions) -> Result<Loaded, SceneError> {
    Loaded::new(tyndall_load::load(path, options)?)
}

/// A glTF file as a whole scene, loaded and built.
pub fn load_gltf(path: &Path) -> Result<Loaded, SceneError> {
    Loaded::new(tyndall_load::gltf::load(path)?)
}

/// The built-in demo, loaded and built.
pub fn demo() -> Result<Loaded, SceneError> {
    Loaded::new(tyndall_load::demo::load()?)
}

/// Parses a native scene from text.
pub fn scene(text: &str) -> Loaded {
    parse_native(&SourceText::new("test.toml", text)).unwrap_or_else(|e| panic!("{e}"))
}

/// The repository's root directory.
pub fn repo() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Renders with the scene's settings changed by `f`.
pub fn render(desc: &Loaded, f: impl FnOnce(&mut RenderSettings)) -> Image {
    let mut settings = desc.settings;
    f(&mut settings);
    tyndall::render(&desc.scene, &settings, &|_| {})
        .expect("render")
        .image
}

/// The sums of a whole render of `desc` with `settings` (what it keeps
/// beside the radiance: its guides and components, if asked), as
/// `tyndall::render` computes them but kept unresolved.
pub fn accumulate(desc: &Loaded, settings: &RenderSettings) -> tyndall::render::Accumulation {
    let region = tyndall::region::RenderRegion::full(settings.width, settings.height, settings.spp);
    let (sums, _) = tyndall::render::render_region(
        &desc.scene,
        settings,
        &region,
        None,
        &|_| {},
        &mut |_, _| std::ops::ControlFlow::Continue(()),
    )
    .expect("render");
    sums
}

/// How much a standard error taken from the scatter of pixels (as if
/// they were independent) must grow for a mean over `pixels` pixels of a
/// render with `settings`: `volpath`'s light-vertex connections share a
/// pool of M light subpaths between the pixels of a pass
/// ([`LightSubpaths`]), which adds at most 1/M of the pixels' mean
/// variance to the variance of any mean over them (the law of total
/// variance, and Cauchy–Schwarz over the pixels), against the 1/n of
/// independent pixels: the factor √(1 + n/M). 1 for renders without a
/// pool.
pub fn pool_inflation(desc: &Loaded, settings: &RenderSettings, pixels: usize) -> f64 {
    if !LightSubpaths::apply(&desc.scene, settings) {
        return 1.0;
    }
    let per_pass = u64::from(settings.width) * u64::from(settings.height);
    (1.0 + pixels as f64 / LightSubpaths::pool_size(per_pass) as f64).sqrt()
}

/// The image cut into `regions.0 × regions.1` regions: per region, the
/// mean over its pixels of (r + g + b) of the average of `a` and `b`, two
/// renders with independent seeds, and the squared standard error of
/// that mean, estimated from the renders' pixel differences (an unbiased
/// estimate with as many degrees of freedom as the region has pixels).
pub fn region_means(a: &Image, b: &Image, regions: (u32, u32)) -> Vec<(f64, f64)> {
    let (w, h) = (a.width(), a.height());
    let (nx, ny) = regions;
    let mut out = Vec::new();
    for ry in 0..ny {
        for rx in 0..nx {
            let (mut sum, mut sq, mut n) = (0.0, 0.0, 0.0);
            for y in ry * h / ny..(ry + 1) * h / ny {
                for x in rx * w / nx..(rx + 1) * w / nx {
                    let (pa, pb) = (a.pixel(x, y), b.pixel(x, y));
                    let (va, vb) = ((pa.x + pa.y + pa.z) as f64, (pb.x + pb.y + pb.z) as f64);
                    sum += 0.5 * (va + vb);
                    // E[((va − vb)/2)²] = Var((va + vb)/2) for independent
                    // seeds.
                    sq += 0.25 * (va - vb) * (va - vb);
                    n += 1.0;
                }
            }
            out.push((sum / n, sq / (n * n)));
        }
    }
    out
}

/// Asserts that no part is negative and that per pixel and channel the
/// `parts` (name, image) add up to `beauty` to the f32 rounding of a
/// sample's sums: at most 64 contributions, each rounding by ε relative,
/// a bound of 64·ε of the pixel. `what` names the render in failures.
pub fn assert_parts_sum_to(beauty: &Image, parts: &[(String, &Image)], what: &str) {
    for (i, b) in beauty.pixels().iter().enumerate() {
        let mut sum = Rgb::ZERO;
        for (name, image) in parts {
            let p = image.pixels()[i];
            assert!(p.min_element() >= 0.0, "{what}: negative {name}");
            sum += p;
        }
        let bound = 64.0 * f32::EPSILON * b.max_element() + 1e-12;
        assert!(
            (sum - *b).abs().max_element() <= bound,
            "{what} pixel {i}: the parts sum to {sum}, beauty {b}"
        );
    }
}

/// Mean and standard error of the mean of `n` one-sample estimates of the
/// radiance along one fixed ray.
pub fn estimate_ray(
    desc: &Loaded,
    kind: IntegratorKind,
    step: f32,
    ray: Ray,
    n: u32,
) -> (Rgb, Rgb) {
    estimate_ray_with(
        desc,
        RenderSettings {
            integrator: kind,
            step,
            ..desc.settings
        },
        ray,
        n,
    )
}

/// [`estimate_ray`] with explicit settings.
pub fn estimate_ray_with(desc: &Loaded, settings: RenderSettings, ray: Ray, n: u32) -> (Rgb, Rgb) {
    let visibility = Visibility::new(&desc.scene, settings.visibility);
    let mut counts = RayCounts::default();
    let (mut sum, mut sum2) = (glam::DVec3::ZERO, glam::DVec3::ZERO);
    for i in 0..n {
        // One camera sample a pass: a pool of one light subpath, which
        // all its vertices share.
        let light_subpaths = LightSubpaths::for_pass(&desc.scene, &settings, 1, i, &mut counts);
        let integrator = Integrator::new(&settings, &visibility, &light_subpaths);
        let mut sampler = PixelSampler::new(17, 0, i);
        // Keep the first two dimensions for the pixel, as a render does.
        let _: Vec2 = sampler.next_2d();
        let l = integrator
            .radiance(
                &desc.scene,
                ray,
                PixelPosition::default(),
                &mut sampler,
                &mut counts,
            )
            .as_dvec3();
        sum += l;
        sum2 += l * l;
    }
    let mean = sum / n as f64;
    let var =
        (sum2 / n as f64 - mean * mean).max(glam::DVec3::ZERO) * (n as f64 / (n as f64 - 1.0));
    (mean.as_vec3(), (var / n as f64).map(f64::sqrt).as_vec3())
}

/// `mean((a − b)² / (r² + 0.01))` with a common denominator image `r`.
pub fn relative_distance(a: &Image, b: &Image, r: &Image) -> f64 {
    let mut sum = 0.0;
    for ((pa, pb), pr) in a.pixels().iter().zip(b.pixels()).zip(r.pixels()) {
        for i in 0..3 {
            let d = (pa[i] - pb[i]) as f64;
            sum += d * d / ((pr[i] as f64).powi(2) + 0.01);
        }
    }
    sum / (3 * a.pixels().len()) as f64
}

/// Per-pixel relative squared error of `a` against `b` over the common
/// denominator `r`, summed over channels.
pub fn pixel_distances(a: &Image, b: &Image, r: &Image) -> Vec<f64> {
    a.pixels()
        .iter()
        .zip(b.pixels())
        .zip(r.pixels())
        .map(|((pa, pb), pr)| {
            (0..3)
                .map(|i| {
                    let d = (pa[i] - pb[i]) as f64;
                    d * d / ((pr[i] as f64).powi(2) + 0.01)
                })
                .sum()
        })
        .collect()
}

/// Mean of per-pixel terms and the standard error of that mean.
pub fn mean_and_stderr(z: &[f64]) -> (f64, f64) {
    let n = z.len() as f64;
    let mean = z.iter().sum::<f64>() / n;
    let var = z.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// How far two estimators' images disagree beyond their noise: for
/// independent renders A₁, A₂ of one and B₁, B₂ of the other, the mean
/// over pixels of `z = d(A₁, B₁) − (d(A₁, A₂) + d(B₁, B₂))/2` (`d` the
/// relative squared difference over the four's mean), and its standard
/// error. Each `d` holds the two renders' variances, so `z` has
/// expectation 0 where the estimators agree and the squared bias where
/// they do not. `bias` scales B₁ first (1: as rendered), to show that a
/// test would see a bias of that size.
pub fn excess_disagreement(a: [&Image; 2], b: [&Image; 2], bias: f32) -> (f64, f64) {
    let r = average(&[a[0], a[1], b[0], b[1]]);
    let (aa, bb) = (
        pixel_distances(a[0], a[1], &r),
        pixel_distances(b[0], b[1], &r),
    );
    let b1 = Image::from_pixels(
        b[0].width(),
        b[0].height(),
        b[0].pixels().iter().map(|p| *p * bias).collect(),
    );
    let ab = pixel_distances(a[0], &b1, &r);
    let z: Vec<f64> = (0..ab.len())
        .map(|i| ab[i] - 0.5 * (aa[i] + bb[i]))
        .collect();
    mean_and_stderr(&z)
}

/// Per-pixel average of images.
pub fn average(images: &[&Image]) -> Image {
    let n = images.len() as f32;
    let pixels = (0..images[0].pixels().len())
        .map(|i| images.iter().map(|im| im.pixels()[i]).sum::<Rgb>() / n)
        .collect();
    Image::from_pixels(images[0].width(), images[0].height(), pixels)
}

/// Composite Simpson's rule of `f` over `[a, b]` with `n` (even) intervals.
pub fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
    let h = (b - a) / n as f64;
    let mut s = f(a) + f(b);
    for i in 1..n {
        s += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

pub fn v3(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}
