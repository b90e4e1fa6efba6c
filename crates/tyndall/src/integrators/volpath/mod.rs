//! `volpath`: a volumetric path tracer with multiple scattering — the
//! reference the fast single-scattering methods are judged against.
//!
//! From the camera, free-flight distances are sampled in the fog
//! proportionally to its transmittance (σt is grey, so one exponential
//! serves all channels and a real scattering event weighs the path by the
//! albedo σs/σt). At every scattering event in fog or on a surface, next
//! event estimation (NEE) connects to every light; the path then continues
//! by phase-function or BSDF sampling. Quad area lights are reachable both
//! ways, so the two estimates are combined by multiple importance sampling
//! with the balance heuristic (Veach 1997); point, spot and directional
//! lights only by NEE. Thin glass tints and passes the path; it is not a
//! scattering event. After three events Russian roulette ends paths with
//! probability 1 − max(throughput), unbiasedly.
//!
//! Every light but the sun is also estimated along fog segments by
//! equiangular sampling (Kulla & Fajardo 2012) towards the light's position
//! or an area-sampled point on it, combined by the balance heuristic with
//! NEE at the free-flight event (whose density is σt·e^{−σt(t−a)}) and,
//! for area lights, with phase-sampled hits: free flights alone put few
//! events near a light, whose 1/d² makes the rare ones fireflies. The
//! camera segment takes `volume_samples` stratified samples per point or
//! spot light and one per area light; later segments one per point or
//! spot light (NEE from a free-flight event has unbounded variance next
//! to a point light) and none per area light (solid-angle NEE is bounded
//! there, and the light-vertex connections cover the glow: more samples
//! cost more time than they saved error).
//! [`Strategies`] switches each estimator off for tests and measurements.
//!
//! Light-vertex connections: at every fog event and Lambertian surface
//! vertex (after the camera's), a light subpath started on a quad light
//! is picked from the pass's pool ([`LightSubpaths`]) and its first fog
//! event, and its second, joined to the vertex
//! (`connect_light_vertex`). This reaches the glow of fog right around
//! an area light, which camera paths find only by rare random walks; the
//! two join the balance heuristic as a fourth and fifth strategy. With volumes in the
//! scene it is off (the light subpath's flight density would need
//! tracking).
//!
//! Depth counts scattering events, as in pbrt-v4: with `max_depth = 1` the
//! path stops at its second event, so it holds exactly light scattered once
//! (by fog or a surface) on its way to the camera — what `single` computes.
//!
//! Surfaces: the Lambertian lobe is sampled by cosine and also reached by
//! NEE (with MIS); the reflective layer is sampled only, its light found
//! when its reflected ray hits an emitter. The lobe is chosen with
//! probability proportional to its reflectance's luminance.
//!
//! Volumes (`[[media]]`): on each segment the fog's free flight is drawn
//! first, then the volumes' first collision before it by spectral
//! tracking ([`crate::media::tracking`]); the nearer real event wins (the
//! first of independent Poisson processes). At a volume event NEE uses
//! ratio-tracked shadow rays and MIS against phase sampling. Every
//! transmittance the fog estimators use is multiplied by the volumes'
//! (ratio tracking), which keeps their MIS weights valid: the weights
//! still sum to one, and each strategy stays unbiased. Segments inside a
//! solid dielectric carry no medium. Emissive volumes add their emission
//! at every tentative collision of that walk (`β·j/μ̄`, as pbrt-v4's
//! `VolPathIntegrator`; docs/physics.md §2.5), on every segment of the
//! path, whatever its depth, like an emitting surface reached by BSDF
//! sampling. Emitting media are also lights: at volume events and
//! Lambertian surface vertices NEE draws a point of an emitting volume by
//! its power ([`crate::media::emitters`], `nee::media_emission_nee`), and
//! the emission tracking finds along the direction sampled there is
//! weighted against it by the balance heuristic (`HitWeighting`); from
//! fog events, the camera and specular bounces it counts in full.
//!
//! Light focused by dielectrics from point and spot lights cannot be
//! reached from here; [`super::light_tracer`] adds it.

mod connections;
mod light_subpaths;
mod mis;
mod nee;
mod segment;
mod segment_weights;

pub use crate::settings::Strategies;
pub use light_subpaths::LightSubpaths;

use super::path_radiance::{Keep, PathRadiance, ScatteringHistory};
use super::{
    MAX_GLASS_CROSSINGS, Scatterer, SolidDepth, SurfaceHit, TRACKING_STREAM, refract_or_reflect,
    surface_direct_lighting,
};
use crate::aov::Scattering;
use crate::color::Rgb;
use crate::footprint::RayCone;
use crate::light_groups::LightGroup;
use crate::materials::{Lobe, SurfaceEvent};
use crate::media::emitters::HitWeighting;
use crate::media::tracking::{Collision, VolumeTracker};
use crate::ray::{Ray, offset_origin};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::visibility::{RayCounts, Visibility};
use connections::{LightVertexOrigin, connect_light_vertex};
use glam::Vec3;
use mis::{EquiangularCounts, balance_of_two};
use nee::{PathVertex, media_emission_nee, medium_nee};
use segment::{Connections, EquiangularNee, FogSegment};
use segment_weights::{emission_weight, escape_weight};

/// Scattering events before Russian roulette may end a path.
const ROULETTE_DEPTH: u32 = 3;

/// Hard limit on scattering events when `max_depth` is unlimited. Russian
/// roulette never ends a path whose throughput stays 1 (albedo-1 fog with
/// nothing to absorb it, e.g. unbounded white fog), so without a limit such
/// a path would never end. Paths this long carry nothing measurable in any
/// scene that absorbs at all; in one that absorbs nothing the cut is a bias
/// and the only one in `volpath`.
pub(crate) const MAX_PATH_EVENTS: u32 = 65_536;

/// The volumetric path tracer's parameters.
#[derive(Clone, Copy)]
pub struct Volpath<'a> {
    /// Most scattering events of a path (pbrt-v4's depth: 1 is single
    /// scattering).
    pub max_depth: u32,
    /// The estimators combined by MIS.
    pub strategies: Strategies,
    /// Equiangular samples per point or spot light on a camera segment.
    pub volume_samples: u32,
    pub(crate) visibility: &'a Visibility,
    /// The pass's light subpaths, for light-vertex connections.
    pub(crate) light_subpaths: &'a LightSubpaths<'a>,
}

/// How the current path segment was sampled, for the MIS weight of the
/// emitter it may hit.
#[derive(Clone, Copy)]
enum Arrival<'a> {
    /// From the camera or a specular/glossy reflection: NEE cannot produce
    /// this direction, so emission counts in full.
    Unweighted,
    /// BSDF-sampled at surface point `from` (or phase-sampled at a volume
    /// event there, if `in_volume`) with solid-angle density `pdf`.
    Sampled {
        from: Vec3,
        pdf: f32,
        in_volume: bool,
    },
    /// Phase-sampled (density `pdf`) at the free-flight event at `t` on
    /// `segment`, whose equiangular estimator took `samples` per light:
    /// three strategies can produce the light it hits.
    Medium {
        pdf: f32,
        segment: FogSegment<'a>,
        t: f32,
        samples: EquiangularCounts,
    },
}

/// Radiance along a camera ray: one path sample. Textures are filtered
/// over the ray's `cone`, if it has one, through specular and glossy
/// events, and read at full resolution once the path has scattered
/// diffusely or in a medium ([`crate::footprint`]): from there on, light
/// sampling and hits must weigh the same texel.
pub(crate) fn radiance<K: Keep>(
    integrator: &Volpath,
    scene: &Scene,
    mut ray: Ray,
    mut cone: Option<RayCone>,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
) -> PathRadiance<K> {
    let mut radiance = PathRadiance::new();
    // Where the path scattered, for the components: surfaces with a
    // diffuse or glossy lobe and media scatter; interfaces and mirrors
    // do not.
    let mut history = ScatteringHistory::default();
    let mut throughput = Rgb::ONE;
    let mut depth = 0u32;
    let mut crossings = 0u32;
    let mut solids = SolidDepth::default();
    let mut arrival = Arrival::Unweighted;
    let mut equiangular = EquiangularNee::with_capacity(scene.light_sampler.most_chosen());
    let mut tracker = VolumeTracker::new(sampler.stream(TRACKING_STREAM));
    let max_events = integrator.max_depth.min(MAX_PATH_EVENTS);
    let strategies = integrator.strategies;
    let connections = integrator.light_subpaths.connect();
    let emissive = scene.volumes.iter().any(|v| v.is_emissive());
    // What the vertex the ray leaves from connected to.
    let mut connected_from = Connections::default();
    loop {
        counts.camera += 1;
        let hit = scene.intersect(&ray, f32::INFINITY);
        let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
        // Inside a solid the path crosses its absorbing inside.
        if solids.inside() {
            throughput *= solids.transmittance(t_hit);
        }
        // The fog's free-flight event, if one comes before the surface.
        let mut fog_event = None;
        if let Some(fog) = &scene.fog
            && !solids.inside()
            && let Some(segment) =
                FogSegment::new(integrator, scene, fog, ray, t_hit, connected_from)
        {
            let u_flight = sampler.next_1d();
            // Equiangular samples along the whole segment, for light
            // whose last scattering is on it.
            let samples = if depth == 0 {
                strategies.camera_equiangular(integrator.volume_samples)
            } else {
                strategies.later_equiangular()
            };
            equiangular.prepare(&segment, samples, sampler);
            if depth < max_events {
                radiance.add_gathered(
                    history.then(Scattering::Medium).component(),
                    throughput,
                    &equiangular.estimate(&segment, strategies, counts, &mut tracker),
                );
            }
            fog_event = segment.free_flight(u_flight).map(|t| (segment, t, samples));
        }
        // The volumes' first collision before the fog's event or the
        // surface: the first of independent events is the nearest.
        if !solids.inside() {
            let t_end = fog_event.map_or(t_hit, |(_, t, _)| t);
            // Emission of the volumes on the way, found by the walk
            // itself (docs/physics.md §2.5).
            let mut emitted = Rgb::ZERO;
            // Weighted against NEE towards the media at the vertex the
            // ray left (a volume event or a Lambertian bounce).
            let weighting = match arrival {
                Arrival::Sampled { from, pdf, .. } if emissive => Some(HitWeighting {
                    emitters: &scene.media_emitters,
                    from,
                    pdf_dir: pdf,
                    nee: strategies.emission_nee,
                    hits: strategies.emission_hits,
                }),
                _ => None,
            };
            let collision = tracker.sample_collision(
                &scene.volumes,
                &ray,
                0.0,
                t_end,
                &mut throughput,
                emissive.then_some((&mut emitted, weighting)),
            );
            // Emitting media are in no light group.
            radiance.add(history.component(), LightGroup::OTHER, emitted);
            match collision {
                Collision::Escaped => {}
                Collision::Absorbed => return radiance,
                Collision::Scatter { t, volume } => {
                    if depth >= max_events {
                        return radiance;
                    }
                    depth += 1;
                    history = history.then(Scattering::Medium);
                    let x = ray.at(t);
                    let phase = &scene.volumes[volume].phase;
                    let medium = PathVertex {
                        scene,
                        visibility: integrator.visibility,
                        x,
                        direction: ray.direction,
                        phase,
                    };
                    radiance.add_gathered(
                        history.component(),
                        throughput,
                        &medium.nee(strategies, sampler, counts, &mut tracker),
                    );
                    if emissive {
                        radiance.add(
                            history.component(),
                            LightGroup::OTHER,
                            throughput
                                * media_emission_nee(
                                    scene,
                                    x,
                                    None,
                                    strategies,
                                    sampler,
                                    counts,
                                    &mut tracker,
                                    |omega| {
                                        let p = phase.eval(omega.dot(ray.direction));
                                        Some((Rgb::splat(p), p))
                                    },
                                ),
                        );
                    }
                    let (direction, pdf) = phase.sample(ray.direction, sampler.next_2d());
                    arrival = Arrival::Sampled {
                        from: x,
                        pdf,
                        in_volume: true,
                    };
                    cone = None;
                    connected_from = Connections::default();
                    ray = Ray {
                        origin: x,
                        direction,
                    };
                    if !survives_roulette(&mut throughput, depth, sampler) {
                        return radiance;
                    }
                    continue;
                }
            }
        }
        if let Some((segment, t, samples)) = fog_event {
            // A real scattering event in the fog.
            if depth >= max_events {
                return radiance;
            }
            depth += 1;
            history = history.then(Scattering::Medium);
            let fog = segment.medium.fog;
            throughput *= fog.albedo;
            let x = ray.at(t);
            let nee = medium_nee(
                &segment,
                t,
                &equiangular,
                strategies,
                sampler,
                counts,
                &mut tracker,
            );
            radiance.add_gathered(history.component(), throughput, &nee);
            let connects = connections && depth < max_events;
            let twice = connects && depth + 1 < max_events;
            // The density with which the camera path reached x from a
            // vertex that connected to second light vertices.
            let reached = segment.reached_density(t);
            if connects {
                let vertex = Scatterer::Medium {
                    phase: &fog.phase,
                    arriving: ray.direction,
                };
                let at = LightVertexOrigin {
                    x,
                    vertex: &vertex,
                    reached,
                    twice,
                };
                // The light vertex is a scattering in the fog.
                let (group, light) =
                    connect_light_vertex(integrator, scene, fog, &at, sampler, counts);
                radiance.add(
                    history.then(Scattering::Medium).component(),
                    group,
                    throughput * light,
                );
            }
            let (direction, pdf) = fog.phase.sample(ray.direction, sampler.next_2d());
            // Phase sampling is exact: the weight p/pdf is 1.
            connected_from = Connections {
                first: connects.then_some(pdf),
                second: twice,
                reached: reached.map(|r| r * pdf),
            };
            arrival = Arrival::Medium {
                pdf,
                segment,
                t,
                samples,
            };
            cone = None;
            ray = Ray {
                origin: x,
                direction,
            };
            if !survives_roulette(&mut throughput, depth, sampler) {
                return radiance;
            }
            continue;
        }
        // No event before the surface: transmittance over its probability is 1.
        let Some(hit) = hit else {
            let weight = escape_weight(scene, strategies, arrival, ray.direction);
            radiance.add(
                history.component(),
                scene.escaped_group(),
                throughput * scene.escaped_radiance(ray.direction) * weight,
            );
            return radiance;
        };
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
            SurfaceEvent::Emitter {
                emitted,
                lamp,
                reflects,
            } => {
                match emitted {
                    // A spot's lamp is seen only by paths without a
                    // scattering event (camera and specular): scattered
                    // light already has the spot by NEE.
                    Some(le) if lamp => {
                        if matches!(arrival, Arrival::Unweighted) {
                            radiance.add(
                                history.component(),
                                scene.light_group_at(hit.primitive),
                                throughput * le,
                            );
                        }
                    }
                    Some(le) => {
                        let le = scene.emitted_at(le, hit.primitive, p, footprint);
                        let weight = emission_weight(
                            scene,
                            strategies,
                            arrival,
                            hit.primitive,
                            p,
                            ray.direction,
                        );
                        radiance.add(
                            history.component(),
                            scene.light_group_at(hit.primitive),
                            throughput * le * weight,
                        );
                    }
                    None => {}
                }
                // An emitter that also reflects goes on as a surface.
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
                throughput *= transmittance;
                ray.origin = offset_origin(p, geometric_normal, ray.direction);
                // The segment after the pane no longer starts at the event.
                connected_from = Connections::default();
                continue;
            }
            SurfaceEvent::Interface(interface) => {
                // A specular event: NEE cannot reach through it.
                if depth >= max_events {
                    return radiance;
                }
                depth += 1;
                ray =
                    refract_or_reflect(&ray, p, geometric_normal, interface, sampler, &mut solids);
                arrival = Arrival::Unweighted;
                connected_from = Connections::default();
                if !survives_roulette(&mut throughput, depth, sampler) {
                    return radiance;
                }
                continue;
            }
            SurfaceEvent::Reflector(surface) => {
                scene.surface_at(surface, hit.primitive, p, footprint)
            }
        };
        if depth >= max_events {
            return radiance;
        }
        depth += 1;
        if surface.diffuse_probability().is_none() {
            return radiance;
        }
        // Light reflected here, by whichever lobe, has scattered here.
        let here = history.then(Scattering::Surface);
        // NEE for the Lambertian lobe, MIS against its cosine sampling
        // (chosen with probability P_d).
        let mis = |p_light: Option<f32>, direction: Vec3| {
            p_light.map_or(1.0, |p_light| {
                balance_of_two(
                    p_light,
                    strategies.surface_hits,
                    surface.pdf(normals.shading, direction),
                )
            })
        };
        let visibility = integrator.visibility;
        if strategies.surface_nee {
            radiance.add_gathered(
                here.component(),
                throughput,
                &surface_direct_lighting(
                    scene,
                    visibility,
                    &surface,
                    (p, ray.direction),
                    normals,
                    sampler,
                    counts,
                    &mut tracker,
                    mis,
                ),
            );
        }
        // NEE towards emitting media, for the Lambertian lobe, MIS
        // against its cosine sampling as for area lights.
        if emissive && surface.diffuse != Rgb::ZERO {
            radiance.add(
                here.component(),
                LightGroup::OTHER,
                throughput
                    * media_emission_nee(
                        scene,
                        p,
                        Some(normals.geometric),
                        strategies,
                        sampler,
                        counts,
                        &mut tracker,
                        |omega| {
                            normals.reflects(omega).then(|| {
                                let cos = normals.shading.dot(omega);
                                (
                                    surface.diffuse_brdf() * cos,
                                    surface.pdf(normals.shading, omega),
                                )
                            })
                        },
                    ),
            );
        }
        // Light-vertex connections from Lambertian surfaces only: a
        // glossy lobe's density could not be weighed against them.
        let connects = connections && depth < max_events && !surface.has_specular();
        let twice = connects && depth + 1 < max_events;
        if connects && let Some(fog) = &scene.fog {
            let vertex = Scatterer::Surface { surface, normals };
            let at = LightVertexOrigin {
                x: p,
                vertex: &vertex,
                reached: None,
                twice,
            };
            let (group, light) = connect_light_vertex(integrator, scene, fog, &at, sampler, counts);
            radiance.add(
                here.then(Scattering::Medium).component(),
                group,
                throughput * light,
            );
        }
        let choice = sampler.next_1d();
        let u = sampler.next_2d();
        let Some(sample) = surface.sample(ray.direction, normals.shading, choice, u) else {
            return radiance;
        };
        if !normals.reflects(sample.direction) {
            return radiance;
        }
        throughput *= sample.weight;
        let direction = sample.direction;
        // A mirror's reflection does not scatter; a diffuse or glossy one does.
        if sample.lobe == Lobe::Diffuse || surface.roughness_of(sample.lobe) > 0.0 {
            history = here;
        }
        match sample.lobe {
            Lobe::Diffuse => {
                cone = None;
                arrival = Arrival::Sampled {
                    from: p,
                    pdf: sample.pdf,
                    in_volume: false,
                };
                let connects = connects && scene.fog.is_some();
                connected_from = Connections {
                    first: connects.then_some(sample.pdf),
                    second: twice && connects,
                    reached: None,
                };
            }
            Lobe::Specular | Lobe::Coat => {
                arrival = Arrival::Unweighted;
                connected_from = Connections::default();
            }
        }
        ray = Ray {
            origin: offset_origin(p, geometric_normal, direction),
            direction,
        };
        if !survives_roulette(&mut throughput, depth, sampler) {
            return radiance;
        }
    }
}

/// Russian roulette after [`ROULETTE_DEPTH`] events: continue with
/// probability `q = min(1, max(throughput))`, dividing by `q`.
pub(crate) fn survives_roulette(
    throughput: &mut Rgb,
    depth: u32,
    sampler: &mut PixelSampler,
) -> bool {
    if depth < ROULETTE_DEPTH {
        return true;
    }
    let q = throughput.max_element().min(1.0);
    if q <= 0.0 || sampler.next_1d() >= q {
        return false;
    }
    *throughput /= q;
    true
}
