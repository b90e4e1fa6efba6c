//! The first-surface guides: what a camera ray sees first, as arbitrary
//! output variables (AOVs) and as the feature images a denoiser is guided
//! by (Intel Open Image Denoise's `albedo` and `normal` inputs).
//!
//! Per camera sample, [`first_surface`] follows the camera ray through the
//! specular events a denoiser cannot see past — thin glass panes (times
//! their transmittance), perfect mirrors (times their specular colour) and
//! solid dielectrics (the likelier of reflection and refraction, with no
//! random number, so the guides are free of that noise) — to the first
//! surface with a diffuse or rough lobe, an emitter, or the sky:
//! - **albedo**: that surface's diffuse plus specular reflectance
//!   (textures applied; at most 1 per channel), an emitter's radiance or
//!   the background or environment seen clamped to [0, 1] (what an image
//!   of it looks like),
//!   times the chain's transmittance;
//! - **normal**: that surface's shading normal in world space, turned to
//!   face the ray; 0 where the chain ends on the sky;
//! - **depth** and **position**: distance along the camera ray (scene
//!   units) to, and the world-space point of, the first surface it meets
//!   of any kind, glass included.
//!
//! Fog is transparent to the guides: a pixel whose light is mostly fog
//! in-scattered in front of a surface holds that surface's albedo and
//! normal, and one whose camera ray meets no surface holds the
//! albedo of the background (or environment) it sees, normal 0 and depth
//! `+∞`. The denoiser is then told
//! where the surfaces' edges are, and the fog's light is denoised by the
//! colour image alone (docs/physics.md §6.1).
//!
//! A pixel's guide is the mean over its samples ([`GuideSum`]): albedo
//! and normal over every sample, depth and position over the samples that
//! met a surface.

use crate::aov::Aov;
use crate::color::Rgb;
use crate::film::Image;
use crate::footprint::RayCone;
use crate::integrators::{MAX_GLASS_CROSSINGS, SurfaceHit};
use crate::materials::{Interface, SurfaceEvent, dielectric_reflectance, dielectric_scatter};
use crate::ray::{Ray, offset_origin};
use crate::scene::Scene;
use glam::{DVec3, Vec3};

/// Most mirror reflections and dielectric interfaces a guide ray follows
/// before it takes the surface it is on.
pub const MAX_GUIDE_BOUNCES: u32 = 8;

/// What one camera sample's ray sees first (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirstSurface {
    pub albedo: Rgb,
    /// Zero where the chain ends on the sky.
    pub normal: Vec3,
    /// The first surface the camera ray meets: distance and point, `None`
    /// where it meets none.
    pub hit: Option<(f32, Vec3)>,
}

/// Follows the camera ray `ray` (unit direction) to the surfaces its
/// guides describe (see the module docs), their textures filtered over
/// its `cone` if given (as the radiance's are: [`crate::footprint`]).
pub fn first_surface(scene: &Scene, mut ray: Ray, mut cone: Option<RayCone>) -> FirstSurface {
    let sky = |throughput: Rgb, direction: Vec3, hit| FirstSurface {
        albedo: throughput * scene.escaped_radiance(direction).clamp(Rgb::ZERO, Rgb::ONE),
        normal: Vec3::ZERO,
        hit,
    };
    let mut throughput = Rgb::ONE;
    let mut first_hit = None;
    let (mut bounces, mut crossings) = (0u32, 0u32);
    loop {
        let Some(hit) = scene.intersect(&ray, f32::INFINITY) else {
            return sky(throughput, ray.direction, first_hit);
        };
        let surface_hit = SurfaceHit::new(scene, &ray, &hit, cone);
        let (p, footprint) = (surface_hit.p, surface_hit.footprint);
        // Every event the guide ray follows is specular: its cone goes on.
        cone = cone.map(|c| c.advanced(hit.t));
        let first = *first_hit.get_or_insert((hit.t, p));
        let ends = |throughput: Rgb, albedo: Rgb| FirstSurface {
            albedo: throughput * albedo.clamp(Rgb::ZERO, Rgb::ONE),
            normal: surface_hit.normals.shading,
            hit: Some(first),
        };
        let n = surface_hit.geometric_normal;
        let event = scene
            .material(hit.primitive)
            .event(surface_hit.front, scene.glass.opaque_to_camera);
        // An emitter that also reflects is seen as its surface.
        match event.without_emission() {
            SurfaceEvent::Emitter { emitted, .. } => {
                let emitted = emitted.map(|le| scene.emitted_at(le, hit.primitive, p, footprint));
                return ends(throughput, emitted.unwrap_or(Rgb::ZERO));
            }
            SurfaceEvent::Pane { transmittance } => {
                crossings += 1;
                if crossings > MAX_GLASS_CROSSINGS {
                    return ends(throughput, Rgb::ZERO);
                }
                throughput *= transmittance;
                ray.origin = offset_origin(p, n, ray.direction);
            }
            // The guides see through a solid's absorption, as through fog.
            SurfaceEvent::Interface(Interface { ior, .. }) => {
                if bounces >= MAX_GUIDE_BOUNCES {
                    return ends(throughput, Rgb::ONE);
                }
                bounces += 1;
                // The likelier branch: u = 0 reflects (the reflectance
                // being above ½ > 0), u → 1 refracts (it being below ½).
                let u = if dielectric_reflectance(ray.direction, n, ior) > 0.5 {
                    0.0
                } else {
                    1.0 - f32::EPSILON
                };
                let direction = dielectric_scatter(ray.direction, n, ior, u).normalize();
                ray = Ray {
                    origin: offset_origin(p, n, direction),
                    direction,
                };
            }
            SurfaceEvent::Reflector(surface) => {
                let surface = scene.surface_at(surface, hit.primitive, p, footprint);
                let mirror = surface.roughness <= 0.0
                    && surface.diffuse == Rgb::ZERO
                    && surface.coat.reflectance == 0.0;
                if !mirror || !surface.has_specular() || bounces >= MAX_GUIDE_BOUNCES {
                    return ends(throughput, surface.albedo());
                }
                bounces += 1;
                throughput *= surface.specular;
                let normal = surface_hit.normals.shading;
                let direction = ray.direction - 2.0 * ray.direction.dot(normal) * normal;
                if !surface_hit.normals.reflects(direction) {
                    return ends(throughput, surface.specular);
                }
                ray = Ray {
                    origin: offset_origin(p, n, direction),
                    direction,
                };
            }
        }
    }
}

/// A pixel's guides summed over its samples (f64, so sample ranges add
/// up to the single render's sums up to rounding, as the radiance does).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GuideSum {
    pub albedo: DVec3,
    pub normal: DVec3,
    /// Sum of depths over the samples that met a surface.
    pub depth: f64,
    /// Sum of points over the samples that met a surface.
    pub position: DVec3,
    /// Samples that met a surface.
    pub hits: u32,
}

impl GuideSum {
    /// The names of the vector sums, in the order of [`GuideSum::vectors`].
    pub const VECTORS: [&'static str; 3] = ["albedo", "normal", "position"];

    /// The vector sums: albedo, normal, position.
    pub fn vectors(&self) -> [DVec3; 3] {
        [self.albedo, self.normal, self.position]
    }

    /// The vector sums, to write: albedo, normal, position.
    pub fn vectors_mut(&mut self) -> [&mut DVec3; 3] {
        [&mut self.albedo, &mut self.normal, &mut self.position]
    }

    pub fn add(&mut self, sample: &FirstSurface) {
        self.albedo += sample.albedo.as_dvec3();
        self.normal += sample.normal.as_dvec3();
        if let Some((t, p)) = sample.hit {
            self.depth += f64::from(t);
            self.position += p.as_dvec3();
            self.hits += 1;
        }
    }

    /// Adds the sums of other samples of the same pixel.
    pub fn append(&mut self, other: &GuideSum) {
        self.albedo += other.albedo;
        self.normal += other.normal;
        self.depth += other.depth;
        self.position += other.position;
        self.hits += other.hits;
    }
}

/// The guide images of a rectangle of pixels: each the mean of its
/// samples (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Guides {
    pub albedo: Image,
    pub normal: Image,
    /// Depth in every channel (`+∞` where no sample met a surface).
    pub depth: Image,
    /// Zero where no sample met a surface.
    pub position: Image,
}

impl Guides {
    /// The means of `sums` (row-major, `width`×`height`) over `samples`
    /// samples per pixel.
    pub fn resolve(width: u32, height: u32, sums: &[GuideSum], samples: u32) -> Guides {
        let n = f64::from(samples.max(1));
        let image = |f: &dyn Fn(&GuideSum) -> Rgb| {
            Image::from_pixels(width, height, sums.iter().map(f).collect())
        };
        let over_hits = |sum: DVec3, hits: u32| {
            if hits == 0 {
                Rgb::ZERO
            } else {
                (sum / f64::from(hits)).as_vec3()
            }
        };
        Guides {
            albedo: image(&|s| (s.albedo / n).as_vec3()),
            normal: image(&|s| (s.normal / n).as_vec3()),
            depth: image(&|s| {
                if s.hits == 0 {
                    Rgb::splat(f32::INFINITY)
                } else {
                    Rgb::splat((s.depth / f64::from(s.hits)) as f32)
                }
            }),
            position: image(&|s| over_hits(s.position, s.hits)),
        }
    }

    /// The image of `aov`, if it is a guide.
    pub fn get(&self, aov: Aov) -> Option<&Image> {
        match aov {
            Aov::Albedo => Some(&self.albedo),
            Aov::Normal => Some(&self.normal),
            Aov::Depth => Some(&self.depth),
            Aov::Position => Some(&self.position),
            Aov::Component(_) | Aov::LightGroups => None,
        }
    }
}
