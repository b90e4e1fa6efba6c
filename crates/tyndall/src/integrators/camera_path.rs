//! The camera path of the single-scattering integrators (`march` and
//! `single`): followed through thin glass, dielectrics and specular
//! reflections, with the fog's in-scattering on each segment and direct
//! lighting where it ends.

use super::lighting::{MediumQuery, TRACKING_STREAM, surface_direct_lighting};
use super::march;
use super::path_radiance::{Gathered, Keep, PathRadiance, ScatteringHistory};
use super::single;
use super::surfaces::{
    MAX_GLASS_CROSSINGS, SolidDepth, SurfaceHit, SurfaceNormals, refract_or_reflect,
};
use crate::aov::Scattering;
use crate::color::Rgb;
use crate::footprint::RayCone;
use crate::materials::{Surface, SurfaceEvent};
use crate::media::tracking::VolumeTracker;
use crate::ray::{Ray, offset_origin};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::visibility::{RayCounts, Visibility};
use glam::Vec3;

/// The camera path the single-scattering integrators share: followed
/// through thin glass, dielectrics and specular reflections (at most
/// `max_bounces` of the latter two), adding on each fog segment the
/// in-scattered radiance that the integrator estimates, and at the
/// surface it ends on direct lighting.
pub(super) struct CameraPath<'a> {
    pub visibility: &'a Visibility,
    pub max_bounces: u32,
    pub in_scattering: InScattering,
}

/// How a single-scattering integrator estimates a fog segment's
/// in-scattering (relative to the radiance at the segment's origin).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum InScattering {
    /// The paper's ray march ([`march::in_scattered`]): its step length
    /// and the pixel's interleaving stratum `(k, count)`.
    March { step: f32, stratum: (u32, u32) },
    /// Equiangular and distance sampling with MIS
    /// ([`single::in_scattered`]): equiangular samples per light.
    Single { volume_samples: u32 },
}

impl InScattering {
    /// The in-scattered radiance of the segment `medium`.
    // Inlined into each of the camera path's two instantiations (with
    // and without the components), as into its one before: measured, the
    // calls instead cost 4 % of a `single` sample.
    #[inline(always)]
    fn estimate<K: Keep>(
        self,
        medium: &MediumQuery,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        tracker: &mut VolumeTracker,
    ) -> Gathered<K> {
        match self {
            InScattering::March { step, stratum } => {
                march::in_scattered(medium, step, stratum, sampler, counts, tracker)
            }
            InScattering::Single { volume_samples } => {
                single::in_scattered(medium, volume_samples, sampler, counts, tracker)
            }
        }
    }
}

impl CameraPath<'_> {
    /// Radiance arriving along `ray`, with what `K` keeps of its
    /// components; textures are filtered over the ray's `cone`, if it has
    /// one, which goes on through every event the path follows (all
    /// specular or glossy: [`crate::footprint`]).
    pub fn radiance<K: Keep>(
        &self,
        scene: &Scene,
        mut ray: Ray,
        mut cone: Option<RayCone>,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
    ) -> PathRadiance<K> {
        let mut radiance = PathRadiance::new();
        // Glossy reflections scatter; mirrors and glass do not.
        let mut history = ScatteringHistory::default();
        let mut throughput = Rgb::ONE;
        let (mut bounces, mut crossings) = (0u32, 0u32);
        let mut solids = SolidDepth::default();
        let mut tracker = VolumeTracker::new(sampler.stream(TRACKING_STREAM));
        loop {
            counts.camera += 1;
            let hit = scene.intersect(&ray, f32::INFINITY);
            let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
            // Inside a solid the path crosses its absorbing inside.
            if solids.inside() {
                throughput *= solids.transmittance(t_hit);
            }
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
                radiance.add_gathered(
                    history.then(Scattering::Medium).component(),
                    throughput,
                    &self
                        .in_scattering
                        .estimate(&medium, sampler, counts, &mut tracker),
                );
                throughput *= fog.transmittance(&ray, 0.0, t_hit);
            }
            let Some(hit) = hit else {
                radiance.add(
                    history.component(),
                    scene.escaped_group(),
                    throughput * scene.escaped_radiance(ray.direction),
                );
                return radiance;
            };
            if throughput == Rgb::ZERO {
                return radiance;
            }
            let SurfaceHit {
                p,
                geometric_normal,
                normals,
                front,
                footprint,
            } = SurfaceHit::new(scene, &ray, &hit, cone);
            cone = cone.map(|c| c.advanced(hit.t));
            let event = scene
                .material(hit.primitive)
                .event(front, scene.glass.opaque_to_camera);
            let surface = match event {
                // Camera paths here have only specular events: they see
                // lamps too.
                SurfaceEvent::Emitter {
                    emitted, reflects, ..
                } => {
                    if let Some(le) = emitted {
                        let le = scene.emitted_at(le, hit.primitive, p, footprint);
                        radiance.add(
                            history.component(),
                            scene.light_group_at(hit.primitive),
                            throughput * le,
                        );
                    }
                    // An emitter that also reflects is lit as a surface.
                    match reflects {
                        Some(surface) => scene.surface_at(surface, hit.primitive, p, footprint),
                        None => return radiance,
                    }
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
                SurfaceEvent::Interface(interface) => {
                    if bounces >= self.max_bounces {
                        return radiance;
                    }
                    bounces += 1;
                    ray = refract_or_reflect(
                        &ray,
                        p,
                        geometric_normal,
                        interface,
                        sampler,
                        &mut solids,
                    );
                    continue;
                }
                // Glass drawn opaque is a diffuse surface of its colour.
                SurfaceEvent::Reflector(surface) => {
                    scene.surface_at(surface, hit.primitive, p, footprint)
                }
            };
            radiance.add_gathered(
                history.then(Scattering::Surface).component(),
                throughput,
                &self.direct_lighting(
                    scene,
                    &surface,
                    (p, ray.direction),
                    normals,
                    sampler,
                    counts,
                    &mut tracker,
                ),
            );
            if !surface.has_specular() || bounces >= self.max_bounces {
                return radiance;
            }
            // A coated surface's reflection is the coat's or the specular
            // layer's, chosen; without a coat no number is drawn for it.
            let choice = match surface.coat.reflectance > 0.0 {
                true => sampler.next_1d(),
                false => 0.0,
            };
            let Some(reflection) =
                surface.reflect_layers(ray.direction, normals.shading, choice, sampler.next_2d())
            else {
                return radiance;
            };
            let direction = reflection.direction;
            if !normals.reflects(direction) {
                return radiance;
            }
            bounces += 1;
            if surface.roughness_of(reflection.lobe) > 0.0 {
                history = history.then(Scattering::Surface);
            }
            throughput *= reflection.weight;
            ray = Ray {
                origin: offset_origin(p, geometric_normal, direction),
                direction,
            };
        }
    }

    /// Reflected radiance from direct lighting at surface point `p` with
    /// `normals` facing the viewer, seen along `incoming`: `Σ (ρ/π · cos θ
    /// + f_layers) · E · V · Tr_glass · T_fog`, one sample per light
    /// ([`surface_direct_lighting`]).
    #[allow(clippy::too_many_arguments)]
    // Inlined into each of the camera path's two instantiations (with
    // and without the components), as into its one before: measured, the
    // calls instead cost 4 % of a `single` sample.
    #[inline(always)]
    fn direct_lighting<K: Keep>(
        &self,
        scene: &Scene,
        surface: &Surface,
        (p, incoming): (Vec3, Vec3),
        normals: SurfaceNormals,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
        tracker: &mut VolumeTracker,
    ) -> Gathered<K> {
        surface_direct_lighting(
            scene,
            self.visibility,
            surface,
            (p, incoming),
            normals,
            sampler,
            counts,
            tracker,
            |_, _| 1.0,
        )
    }
}
