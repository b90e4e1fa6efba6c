//! Integrators: how the radiance along a camera ray is estimated.
//!
//! [`volpath`] traces full paths with multiple scattering. The two
//! single-scattering integrators share the camera path
//! ([`Integrator::radiance`]): the ray is followed through thin glass,
//! dielectrics and specular reflections; on each
//! segment the in-scattered fog radiance is added (docs/physics.md §5.1),
//!
//! ```text
//! L = T(0, s_hit)·L_surface + ∫₀^{s_hit} T(0, s)·σs·Σ_lights L_in(x(s)) ds,
//! ```
//!
//! and surfaces are shaded with direct lighting. They differ in how they
//! estimate the integral: [`march`] by the paper's jittered fixed-step
//! Riemann sum, [`single`] by equiangular and distance sampling combined
//! with MIS. Both evaluate the integrand through `scattered_radiance`,
//! the paper's eq. 1 in one place.

pub mod light_tracer;
pub mod march;
pub mod single;
pub mod volpath;

pub use march::March;
pub use single::Single;
pub use volpath::{LightSubpaths, Volpath};

use crate::accel::Hit;
use crate::color::Rgb;
use crate::lights::{Incident, Light, LightPoint};
use crate::materials::{Surface, SurfaceEvent, dielectric_scatter};
use crate::media::Fog;
use crate::media::tracking::VolumeTracker;
use crate::phase::PhaseFunction;
use crate::ray::{Ray, offset_origin};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
pub use crate::settings::IntegratorKind;
use crate::settings::RenderSettings;
use crate::visibility::{RayCounts, Visibility};
use glam::{Vec2, Vec3};

/// Most glass panes a camera ray crosses before it is cut off (a guard
/// against degenerate scenes of stacked coincident panes).
const MAX_GLASS_CROSSINGS: u32 = 64;

/// A configured integrator, borrowing the render's visibility: the method
/// with its own parameters.
#[derive(Clone, Copy)]
pub enum Integrator<'a> {
    /// The paper's ray march (module `march`).
    March(March<'a>),
    /// Unbiased single scattering (module `single`).
    Single(Single<'a>),
    /// Volumetric path tracing (module `volpath`).
    Volpath(Volpath<'a>),
}

/// The pixel a camera sample belongs to, for methods that correlate
/// neighbouring pixels (interleaved sampling).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelPosition {
    pub x: u32,
    pub y: u32,
}

impl<'a> Integrator<'a> {
    /// The integrator `settings` choose, with its parameters from them,
    /// for one pass whose light subpaths (for `volpath`'s light-vertex
    /// connections) are `light_subpaths`.
    pub fn new(
        settings: &RenderSettings,
        visibility: &'a Visibility,
        light_subpaths: &'a LightSubpaths<'a>,
    ) -> Self {
        match settings.integrator {
            IntegratorKind::March => Integrator::March(March {
                step: settings.step,
                interleave: settings.interleave,
                max_bounces: settings.max_bounces,
                visibility,
            }),
            IntegratorKind::Single => Integrator::Single(Single {
                volume_samples: settings.volume_samples,
                max_bounces: settings.max_bounces,
                visibility,
            }),
            IntegratorKind::Volpath => Integrator::Volpath(Volpath {
                max_depth: settings.max_depth,
                strategies: settings.strategies,
                volume_samples: settings.volume_samples,
                visibility,
                light_subpaths,
            }),
        }
    }

    /// Which integrator this is.
    pub fn kind(&self) -> IntegratorKind {
        match self {
            Integrator::March(_) => IntegratorKind::March,
            Integrator::Single(_) => IntegratorKind::Single,
            Integrator::Volpath(_) => IntegratorKind::Volpath,
        }
    }

    /// Radiance arriving at the camera along `ray` (one sample) through
    /// pixel `pixel`.
    pub fn radiance(
        &self,
        scene: &Scene,
        ray: Ray,
        pixel: PixelPosition,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
    ) -> Rgb {
        match self {
            Integrator::March(march) => {
                let stratum = march::interleaved_stratum(pixel, march.interleave);
                let in_scattered =
                    |medium: &MediumQuery,
                     sampler: &mut PixelSampler,
                     counts: &mut RayCounts,
                     tracker: &mut VolumeTracker| {
                        march::in_scattered(medium, march.step, stratum, sampler, counts, tracker)
                    };
                let path = CameraPath {
                    visibility: march.visibility,
                    max_bounces: march.max_bounces,
                };
                path.radiance(scene, ray, sampler, counts, in_scattered)
            }
            Integrator::Single(single) => {
                let in_scattered =
                    |medium: &MediumQuery,
                     sampler: &mut PixelSampler,
                     counts: &mut RayCounts,
                     tracker: &mut VolumeTracker| {
                        single::in_scattered(
                            medium,
                            single.volume_samples,
                            sampler,
                            counts,
                            tracker,
                        )
                    };
                let path = CameraPath {
                    visibility: single.visibility,
                    max_bounces: single.max_bounces,
                };
                path.radiance(scene, ray, sampler, counts, in_scattered)
            }
            Integrator::Volpath(volpath) => volpath::radiance(volpath, scene, ray, sampler, counts),
        }
    }
}

/// The camera path the single-scattering integrators share: followed
/// through thin glass, dielectrics and specular reflections (at most
/// `max_bounces` of the latter two), adding on each fog segment the
/// in-scattered radiance that the integrator estimates, and at the
/// surface it ends on direct lighting.
struct CameraPath<'a> {
    visibility: &'a Visibility,
    max_bounces: u32,
}

impl CameraPath<'_> {
    /// Radiance arriving along `ray`; `in_scattered` estimates a fog
    /// segment's in-scattering relative to the radiance at its origin.
    fn radiance(
        &self,
        scene: &Scene,
        mut ray: Ray,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        mut in_scattered: impl FnMut(
            &MediumQuery,
            &mut PixelSampler,
            &mut RayCounts,
            &mut VolumeTracker,
        ) -> Rgb,
    ) -> Rgb {
        let mut radiance = Rgb::ZERO;
        let mut throughput = Rgb::ONE;
        let (mut bounces, mut crossings) = (0u32, 0u32);
        let mut solids = SolidDepth::default();
        let mut tracker = VolumeTracker::new(sampler.stream(TRACKING_STREAM));
        loop {
            counts.camera += 1;
            let hit = scene.geometry.intersect(&ray, f32::INFINITY);
            let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
            if let Some(fog) = &scene.fog
                && !solids.inside()
            {
                let medium = MediumQuery {
                    scene,
                    visibility: self.visibility,
                    fog,
                    ray,
                    t_hit,
                };
                radiance += throughput * in_scattered(&medium, sampler, counts, &mut tracker);
                throughput *= fog.transmittance(&ray, 0.0, t_hit);
            }
            let Some(hit) = hit else {
                return radiance + throughput * scene.background;
            };
            if throughput == Rgb::ZERO {
                return radiance;
            }
            let SurfaceHit {
                p,
                geometric_normal,
                normals,
                front,
            } = SurfaceHit::new(scene, &ray, &hit);
            let event = scene
                .material(hit.primitive)
                .event(front, scene.glass.opaque_to_camera);
            let surface = match event {
                // Camera paths here have only specular events: they see
                // lamps too.
                SurfaceEvent::Emitter { emitted, .. } => {
                    if let Some(le) = emitted {
                        radiance += throughput * le;
                    }
                    return radiance;
                }
                SurfaceEvent::Pane { transmittance } => {
                    crossings += 1;
                    if crossings > MAX_GLASS_CROSSINGS {
                        return radiance;
                    }
                    // Camera rays cross one pane at a time, so each
                    // crossing multiplies by its transmittance; for a
                    // single pane the blend model (eq. 6 from white) gives
                    // the same value.
                    throughput *= transmittance;
                    ray.origin = offset_origin(p, geometric_normal, ray.direction);
                    continue;
                }
                SurfaceEvent::Interface { ior } => {
                    if bounces >= self.max_bounces {
                        return radiance;
                    }
                    bounces += 1;
                    ray = refract_or_reflect(&ray, p, geometric_normal, ior, sampler, &mut solids);
                    continue;
                }
                // Glass drawn opaque is a diffuse surface of its colour.
                SurfaceEvent::Reflector(surface) => scene.surface_at(surface, hit.primitive, p),
            };
            radiance += throughput
                * self.direct_lighting(scene, &surface, p, normals, sampler, counts, &mut tracker);
            if !surface.has_specular() || bounces >= self.max_bounces {
                return radiance;
            }
            let Some(direction) =
                surface.reflect(ray.direction, normals.shading, sampler.next_2d())
            else {
                return radiance;
            };
            if !normals.reflects(direction) {
                return radiance;
            }
            bounces += 1;
            throughput *= surface.specular;
            ray = Ray {
                origin: offset_origin(p, geometric_normal, direction),
                direction,
            };
        }
    }

    /// Reflected radiance from direct lighting at surface point `p` with
    /// `normals` facing the viewer: `Σ ρ/π · E · cos θ · V · Tr_glass ·
    /// T_fog`, one sample per light.
    #[allow(clippy::too_many_arguments)]
    fn direct_lighting(
        &self,
        scene: &Scene,
        surface: &Surface,
        p: Vec3,
        normals: SurfaceNormals,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        tracker: &mut VolumeTracker,
    ) -> Rgb {
        lambert_direct_lighting(
            scene,
            self.visibility,
            surface,
            p,
            normals,
            sampler,
            counts,
            tracker,
            |_, _| 1.0,
        )
    }
}

/// Direct lighting of the Lambertian lobe of `surface` at point `p` with
/// `normals` facing the viewer, one sample per light:
/// `Σ ρ/π · E · cos θ · V · Tr_glass · T_media · w` (θ from the shading
/// normal; light from below the geometric surface does not count), where
/// `w = weight(p_light, ω)` is the caller's MIS weight given the light
/// sample's solid-angle density (`None` for delta lights) and unit
/// direction ω towards it.
#[allow(clippy::too_many_arguments)]
pub(crate) fn lambert_direct_lighting(
    scene: &Scene,
    visibility: &Visibility,
    surface: &Surface,
    p: Vec3,
    normals: SurfaceNormals,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
    weight: impl Fn(Option<f32>, Vec3) -> f32,
) -> Rgb {
    if surface.diffuse == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let mut sum = Rgb::ZERO;
    for (index, light) in scene.lights.iter().enumerate() {
        let Some((incident, p_light)) = sample_light(light, p, sampler) else {
            continue;
        };
        if !normals.reflects(incident.direction) {
            continue;
        }
        let cos = normals.shading.dot(incident.direction);
        let arriving = light_arriving(
            scene,
            visibility,
            index,
            p,
            Some(normals.geometric),
            &incident,
            counts,
            tracker,
        );
        sum += arriving * (cos * weight(p_light, incident.direction));
    }
    sum * surface.diffuse_brdf()
}

/// The [`PixelSampler::stream`] purpose of a path's tracking numbers.
const TRACKING_STREAM: u64 = 1;

/// How many solid dielectrics a path is inside. A solid displaces the
/// media: no fog or volume exists inside glass, so segments inside one
/// are not in-scattering (where regions and solids overlap, the solid
/// wins).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SolidDepth(u32);

impl SolidDepth {
    pub fn inside(self) -> bool {
        self.0 > 0
    }

    /// Records a scattering at a dielectric with geometric normal `n`
    /// from `incoming` to `outgoing`: a transmission into its front
    /// enters it, one out of its back leaves it.
    pub fn cross(&mut self, incoming: Vec3, outgoing: Vec3, n: Vec3) {
        let (din, dout) = (incoming.dot(n), outgoing.dot(n));
        if din < 0.0 && dout < 0.0 {
            self.0 += 1;
        } else if din > 0.0 && dout > 0.0 {
            self.0 = self.0.saturating_sub(1);
        }
    }
}

/// The ray leaving a solid dielectric of index `ior` at `p` (geometric
/// normal `geometric_normal`) for `ray` arriving there: reflected or
/// refracted with the Fresnel probabilities (one sample dimension), its
/// origin moved off the surface; records entering or leaving the solid.
pub(crate) fn refract_or_reflect(
    ray: &Ray,
    p: Vec3,
    geometric_normal: Vec3,
    ior: f32,
    sampler: &mut PixelSampler,
    solids: &mut SolidDepth,
) -> Ray {
    let direction = dielectric_scatter(ray.direction, geometric_normal, ior, sampler.next_1d());
    solids.cross(ray.direction, direction, geometric_normal);
    Ray {
        origin: offset_origin(p, geometric_normal, direction),
        direction,
    }
}

/// Where a ray meets a surface: the point, the geometric normal, the
/// normals turned to face the arriving ray, and whether the ray meets the
/// front (the side the geometric normal points to).
pub(crate) struct SurfaceHit {
    pub p: Vec3,
    pub geometric_normal: Vec3,
    pub normals: SurfaceNormals,
    pub front: bool,
}

impl SurfaceHit {
    pub fn new(scene: &Scene, ray: &Ray, hit: &Hit) -> Self {
        let p = ray.at(hit.t);
        let geometric_normal = scene.geometry.normal(hit.primitive, p);
        let front = geometric_normal.dot(ray.direction) < 0.0;
        let geometric = if front {
            geometric_normal
        } else {
            -geometric_normal
        };
        let shading = scene
            .shading_normal(hit.primitive, p)
            .map_or(geometric, |n| if n.dot(geometric) < 0.0 { -n } else { n });
        Self {
            p,
            geometric_normal,
            normals: SurfaceNormals { shading, geometric },
            front,
        }
    }
}

/// The normals of an opaque surface point, both turned to face the side a
/// path arrived from: `shading`, the mesh's vertex normals interpolated
/// (Phong 1975; `geometric` itself on flat shapes), orients the BSDF;
/// `geometric` decides which side a direction leaves on and offsets rays.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SurfaceNormals {
    pub shading: Vec3,
    pub geometric: Vec3,
}

impl SurfaceNormals {
    /// Both normals the geometric one (light paths, flat shapes).
    pub fn flat(geometric: Vec3) -> Self {
        Self {
            shading: geometric,
            geometric,
        }
    }

    /// Whether the unit direction `omega` leaves on the arrival side of
    /// both normals, the only directions an opaque surface scatters to.
    /// Above the shading normal but below the geometric surface a ray
    /// would pass through it and leak light (pbrt-v4 §10.1.1 discards
    /// such directions in the same way).
    #[inline]
    pub fn reflects(&self, omega: Vec3) -> bool {
        self.shading.dot(omega) > 0.0 && self.geometric.dot(omega) > 0.0
    }
}

/// A ray segment in fog and what estimating its in-scattering needs: the
/// scene, the render's visibility, the fog, and the segment `(0, t_hit)`
/// of `ray`.
#[derive(Clone, Copy)]
pub(crate) struct MediumQuery<'a> {
    pub scene: &'a Scene,
    pub visibility: &'a Visibility,
    pub fog: &'a Fog,
    pub ray: Ray,
    pub t_hit: f32,
}

impl MediumQuery<'_> {
    /// The phase function for light arriving as `incident` and leaving
    /// towards the ray's origin. Light travels along −direction before
    /// scattering and along −view after: cos θ = (−direction)·(−view).
    #[inline]
    pub fn phase(&self, incident: &Incident) -> f32 {
        self.fog
            .phase
            .eval(incident.direction.dot(self.ray.direction))
    }
}

/// The sample dimensions for choosing a point on `light`: two for an
/// area light, none for a delta light (whose point is fixed).
#[inline]
fn light_sample_u(light: &Light, sampler: &mut PixelSampler) -> Vec2 {
    if light.is_delta() {
        Vec2::ZERO
    } else {
        sampler.next_2d()
    }
}

/// The point on `light` a receiver connects to (the light's
/// `sample_point`).
#[inline]
fn light_point(light: &Light, sampler: &mut PixelSampler) -> Option<LightPoint> {
    light.sample_point(light_sample_u(light, sampler))
}

/// Light reaching receiver `x` from `light` for next event estimation,
/// with the solid-angle density of the light's point for MIS (the
/// light's `sample_li`).
#[inline]
pub(crate) fn sample_light(
    light: &Light,
    x: Vec3,
    sampler: &mut PixelSampler,
) -> Option<(Incident, Option<f32>)> {
    light.sample_li(x, light_sample_u(light, sampler))
}

/// Radiance scattered at fog point `x` of the query's ray towards the
/// camera from light number `index` via its emitting point `y`, per unit
/// length: the paper's eq. 1,
/// `σs · p(θ) · I(dir)/d² · V · Tr_glass · exp(−σt·d)`.
/// Zero without a visibility query outside a spotlight's cone.
#[inline]
pub(crate) fn scattered_radiance(
    medium: &MediumQuery,
    index: usize,
    y: Option<LightPoint>,
    x: Vec3,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
) -> Rgb {
    let Some(incident) = medium.scene.lights[index].incident(x, y) else {
        return Rgb::ZERO;
    };
    medium.fog.sigma_s() * scattered_light(medium, index, x, &incident, counts, tracker)
}

/// Eq. 1 without σs: light from light number `index` arriving at fog
/// point `x` as `incident` and scattered towards the query's origin,
/// `p(θ) · E · V · Tr_glass · T_media`; zero when occluded. Every
/// integrator evaluates in-scattering through this function.
#[inline]
pub(crate) fn scattered_light(
    medium: &MediumQuery,
    index: usize,
    x: Vec3,
    incident: &Incident,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
) -> Rgb {
    let arriving = light_arriving(
        medium.scene,
        medium.visibility,
        index,
        x,
        None,
        incident,
        counts,
        tracker,
    );
    arriving * medium.phase(incident)
}

/// Light from light number `index` arriving at `x` as `incident`, after
/// everything on its way: `E · V · Tr_glass · T_fog · T_volumes` (the
/// fog's in closed form, the volumes' by ratio tracking). `normal` is the
/// receiving surface's, facing the light's side (`None` in a medium): the
/// shadow ray starts just off it.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn light_arriving(
    scene: &Scene,
    visibility: &Visibility,
    index: usize,
    x: Vec3,
    normal: Option<Vec3>,
    incident: &Incident,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
) -> Rgb {
    let origin = normal.map_or(x, |n| offset_origin(x, n, incident.direction));
    // The shadow ray leaves from `origin`, not `x`: the light is this far
    // from there.
    let from_origin = Incident {
        distance: incident.distance - (origin - x).dot(incident.direction),
        ..*incident
    };
    let glass = visibility.transmittance(scene, index, origin, normal, &from_origin, counts);
    if glass == Rgb::ZERO {
        return Rgb::ZERO;
    }
    let media = media_transmittance(
        scene,
        tracker,
        x,
        origin,
        incident.direction,
        incident.distance,
    );
    incident.irradiance * glass * media
}

/// Transmittance of the scene's media from `x` over `distance` along the
/// unit `direction`: the fog's in closed form (from `x`), times the
/// volumes' by ratio tracking (one estimate, along the ray from `origin`:
/// `x` moved off a surface, where a shadow ray starts). Zero without
/// tracking where the fog alone already blocks the light. Every
/// connection to a light or the camera takes its transmittance here.
pub(crate) fn media_transmittance(
    scene: &Scene,
    tracker: &mut VolumeTracker,
    x: Vec3,
    origin: Vec3,
    direction: Vec3,
    distance: f32,
) -> Rgb {
    let fog_t = scene
        .fog
        .as_ref()
        .map_or(1.0, |fog| fog.transmittance_along(x, direction, distance));
    if fog_t == 0.0 {
        return Rgb::ZERO;
    }
    let ray = Ray { origin, direction };
    tracker.transmittance(&scene.volumes, &ray, 0.0, distance) * fog_t
}

/// A scattering vertex that a connection joins to another vertex (a
/// light vertex in `volpath`, the camera in the light tracer): how it
/// turns light towards the connection, and where a ray leaving it starts.
pub(crate) enum Scatterer<'a> {
    /// A real scattering event in a medium, reached by a path travelling
    /// along unit `arriving`.
    Medium {
        phase: &'a PhaseFunction,
        arriving: Vec3,
    },
    /// An opaque surface with its normals facing the side the path
    /// arrived from; connections join its Lambertian lobe.
    Surface {
        surface: Surface,
        normals: SurfaceNormals,
    },
}

impl Scatterer<'_> {
    /// For a connection leaving along unit `omega`: the scattering
    /// `p(θ)` (cos θ = arriving·omega) or the surface's Lambertian
    /// `ρ/π·cos θ` ([`Surface::eval`]), and the density with which
    /// continuing the path picks `omega` (phase sampling, or
    /// [`Surface::pdf`]). `None` if a surface does not scatter that way.
    pub fn scatter(&self, omega: Vec3) -> Option<(Rgb, f32)> {
        match *self {
            Scatterer::Medium { phase, arriving } => {
                let p = phase.eval(omega.dot(arriving));
                Some((Rgb::splat(p), p))
            }
            Scatterer::Surface { surface, normals } => normals.reflects(omega).then(|| {
                (
                    surface.eval(normals.shading, omega),
                    surface.pdf(normals.shading, omega),
                )
            }),
        }
    }

    /// Where a ray from `x` along `omega` starts: just off a surface.
    pub fn origin(&self, x: Vec3, omega: Vec3) -> Vec3 {
        match *self {
            Scatterer::Medium { .. } => x,
            Scatterer::Surface { normals, .. } => offset_origin(x, normals.geometric, omega),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::Strategies;

    /// Each integrator is built with its own parameters from the settings.
    #[test]
    fn integrator_takes_its_parameters_from_the_settings() {
        let visibility = Visibility::ShadowRays;
        let settings = RenderSettings {
            step: 0.25,
            interleave: 4,
            max_bounces: 3,
            volume_samples: 5,
            max_depth: 7,
            strategies: Strategies::NONE,
            ..RenderSettings::default()
        };
        let light_subpaths = LightSubpaths::none();
        for kind in IntegratorKind::ALL {
            let integrator = Integrator::new(
                &RenderSettings {
                    integrator: kind,
                    ..settings
                },
                &visibility,
                &light_subpaths,
            );
            assert_eq!(integrator.kind(), kind);
            match integrator {
                Integrator::March(m) => {
                    assert_eq!((m.step, m.interleave, m.max_bounces), (0.25, 4, 3))
                }
                Integrator::Single(s) => assert_eq!((s.volume_samples, s.max_bounces), (5, 3)),
                Integrator::Volpath(v) => assert_eq!(
                    (v.max_depth, v.strategies, v.volume_samples),
                    (7, Strategies::NONE, 5)
                ),
            }
        }
    }
}
