//! One camera path of `volpath`: its state between events ([`PathState`])
//! and what the whole path shares ([`PathContext`]), with one method per
//! kind of event. Every event that scatters ends the same way,
//! [`PathContext::scatter`]: the path leaves along a new ray and Russian
//! roulette may end it.

use super::connections::{LightVertexOrigin, connect_light_vertex};
use super::mis::{EquiangularCounts, balance_of_two};
use super::nee::{PathVertex, media_emission_nee, medium_nee};
use super::segment::{Connections, EquiangularNee, FogSegment};
use super::segment_weights::{emission_weight, escape_weight};
use super::volume_connections::{CollisionVertex, connect_in_volumes, reached_density};
use super::volume_equiangular::VolumeEquiangular;
use super::{Arrival, MAX_PATH_EVENTS, Volpath, survives_roulette};
use crate::accel::Hit;
use crate::aov::Scattering;
use crate::color::Rgb;
use crate::footprint::RayCone;
use crate::integrators::path_radiance::{Keep, PathRadiance, ScatteringHistory};
use crate::integrators::surfaces::SurfaceNormals;
use crate::integrators::{
    MAX_GLASS_CROSSINGS, Scatterer, SolidDepth, SurfaceHit, TRACKING_STREAM, refract_or_reflect,
    surface_direct_lighting,
};
use crate::light_groups::LightGroup;
use crate::materials::{Lobe, Surface, SurfaceEvent};
use crate::media::emitters::HitWeighting;
use crate::media::tracking::{Collision, FlightOptions, VolumeTracker};
use crate::ray::{Ray, offset_origin};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::settings::Strategies;
use crate::visibility::RayCounts;
use glam::Vec3;

/// Radiance along a camera ray: one path sample. Textures are filtered
/// over the ray's `cone`, if it has one, through specular and glossy
/// events, and read at full resolution once the path has scattered
/// diffusely or in a medium ([`crate::footprint`]): from there on, light
/// sampling and hits must weigh the same texel.
pub(crate) fn radiance<K: Keep>(
    integrator: &Volpath,
    scene: &Scene,
    ray: Ray,
    cone: Option<RayCone>,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
) -> PathRadiance<K> {
    let mut path = PathContext::new(integrator, scene, sampler, counts);
    let mut state = PathState::new(ray, cone);
    while path.step(&mut state) == Step::Continue {}
    path.radiance
}

/// Whether a path goes on after an event.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Step {
    Continue,
    End,
}

/// Where a camera path is between events and what it carries.
struct PathState<'a> {
    /// The ray the path follows from its last event.
    ray: Ray,
    /// The ray's footprint for texture filtering; `None` once the path
    /// has scattered diffusely or in a medium.
    cone: Option<RayCone>,
    /// The product of the events' weights so far.
    throughput: Rgb,
    /// Scattering events so far (pbrt-v4's depth).
    depth: u32,
    /// Thin-glass panes crossed.
    crossings: u32,
    /// The solid dielectrics the path is inside.
    solids: SolidDepth,
    /// Where the path scattered, for the components.
    history: ScatteringHistory,
    /// How the current segment was sampled, for the MIS weight of the
    /// emitter it may hit.
    arrival: Arrival<'a>,
    /// What the vertex the ray leaves from connected to.
    connected_from: Connections,
}

impl PathState<'_> {
    fn new(ray: Ray, cone: Option<RayCone>) -> Self {
        Self {
            ray,
            cone,
            throughput: Rgb::ONE,
            depth: 0,
            crossings: 0,
            solids: SolidDepth::default(),
            history: ScatteringHistory::default(),
            arrival: Arrival::Unweighted,
            connected_from: Connections::default(),
        }
    }
}

/// What every event of one camera path shares: the integrator and scene,
/// the path's sampler, counters and trackers, and the radiance it has
/// gathered.
struct PathContext<'a, K: Keep> {
    integrator: &'a Volpath<'a>,
    scene: &'a Scene,
    sampler: &'a mut PixelSampler,
    counts: &'a mut RayCounts,
    tracker: VolumeTracker,
    /// The equiangular samples of the current fog segment.
    equiangular: EquiangularNee,
    /// The equiangular samples of the current segment's flight through
    /// uniform volumes, towards point and spot lights.
    volume_equiangular: VolumeEquiangular,
    radiance: PathRadiance<K>,
    strategies: Strategies,
    /// Most scattering events ([`MAX_PATH_EVENTS`] when unlimited).
    max_events: u32,
    /// Whether light-vertex connections are made (a pool exists).
    connections: bool,
    /// Whether any volume emits.
    emissive: bool,
    /// Whether flights aim at lights: the scene has uniform volumes,
    /// whose flights can be drawn towards them, and lights that are not
    /// Dirac deltas.
    aims: bool,
    /// Whether flights through uniform volumes take equiangular samples
    /// towards point and spot lights.
    delta_equiangular: bool,
}

impl<'a, K: Keep> PathContext<'a, K> {
    fn new(
        integrator: &'a Volpath<'a>,
        scene: &'a Scene,
        sampler: &'a mut PixelSampler,
        counts: &'a mut RayCounts,
    ) -> Self {
        let tracker = VolumeTracker::new(sampler.stream(TRACKING_STREAM));
        let uniform = scene
            .volumes
            .iter()
            .any(|v| v.uniform_extinction().is_some());
        Self {
            integrator,
            scene,
            tracker,
            equiangular: EquiangularNee::with_capacity(scene.light_sampler.most_chosen()),
            volume_equiangular: VolumeEquiangular::with_capacity(scene.light_sampler.most_chosen()),
            radiance: PathRadiance::new(),
            strategies: integrator.strategies,
            max_events: integrator.max_depth.min(MAX_PATH_EVENTS),
            connections: integrator.light_subpaths.connect(),
            emissive: scene.volumes.iter().any(|v| v.is_emissive()),
            aims: uniform && !scene.extended_lights().is_empty(),
            // The lights that are not extended are Dirac deltas.
            delta_equiangular: uniform && scene.extended_lights().len() < scene.lights.len(),
            sampler,
            counts,
        }
    }

    /// Counts a scattering event; false (the path ends) when it would be
    /// one more than `max_depth` allows.
    fn count_event(&self, state: &mut PathState) -> bool {
        if state.depth >= self.max_events {
            return false;
        }
        state.depth += 1;
        true
    }

    /// The end of every scattering event: the path leaves along `ray`,
    /// sampled as `arrival` says, having connected as `connected_from`
    /// says; after [`super::ROULETTE_DEPTH`] events Russian roulette may
    /// end it.
    fn scatter<'x>(
        &mut self,
        state: &mut PathState<'x>,
        ray: Ray,
        arrival: Arrival<'x>,
        connected_from: Connections,
    ) -> Step {
        state.ray = ray;
        state.arrival = arrival;
        state.connected_from = connected_from;
        match survives_roulette(&mut state.throughput, state.depth, self.sampler) {
            true => Step::Continue,
            false => Step::End,
        }
    }

    /// One segment of the path: the fog's and the volumes' events on it,
    /// else the surface it ends on, else the sky.
    fn step(&mut self, state: &mut PathState<'a>) -> Step {
        let (scene, integrator, strategies) = (self.scene, self.integrator, self.strategies);
        self.counts.camera += 1;
        let hit = scene.intersect(&state.ray, f32::INFINITY);
        let t_hit = hit.map_or(f32::INFINITY, |h| h.t);
        // Inside a solid the path crosses its absorbing inside.
        if state.solids.inside() {
            state.throughput *= state.solids.transmittance(t_hit);
        }
        // The fog's free-flight event, if one comes before the surface.
        let mut fog_event = None;
        if let Some(fog) = &scene.fog
            && !state.solids.inside()
            && let Some(segment) = FogSegment::new(
                integrator,
                scene,
                fog,
                state.ray,
                t_hit,
                state.connected_from,
            )
        {
            let u_flight = self.sampler.next_1d();
            // Equiangular samples along the whole segment, for light
            // whose last scattering is on it.
            let samples = if state.depth == 0 {
                strategies.camera_equiangular(integrator.volume_samples)
            } else {
                strategies.later_equiangular()
            };
            self.equiangular.prepare(&segment, samples, self.sampler);
            if state.depth < self.max_events {
                let light =
                    self.equiangular
                        .estimate(&segment, strategies, self.counts, &mut self.tracker);
                self.radiance.add_gathered(
                    state.history.then(Scattering::Medium).component(),
                    state.throughput,
                    &light,
                );
            }
            fog_event = segment.free_flight(u_flight).map(|t| (segment, t, samples));
        }
        // The volumes' first collision before the fog's event or the
        // surface: the first of independent events is the nearest.
        if !state.solids.inside() {
            let t_end = fog_event.map_or(t_hit, |(_, t, _)| t);
            self.volume_equiangular(state, t_end);
            match self.volumes_collision(state, t_end) {
                Collision::Escaped => {}
                Collision::Absorbed => return Step::End,
                Collision::Scatter { t, volume } => return self.volume_event(state, t, volume),
            }
        }
        if let Some((segment, t, samples)) = fog_event {
            return self.fog_event(state, segment, t, samples);
        }
        // No event before the surface: transmittance over its probability is 1.
        let Some(hit) = hit else {
            let direction = state.ray.direction;
            let weight = escape_weight(scene, strategies, state.arrival, direction);
            self.radiance.add(
                state.history.component(),
                scene.escaped_group(),
                state.throughput * scene.escaped_radiance(direction) * weight,
            );
            return Step::End;
        };
        self.surface_event(state, &hit)
    }

    /// The volumes' first collision on the ray before `t_end`, by spectral
    /// tracking, adding the emission of the volumes on the way (found by
    /// the walk itself, docs/physics.md §2.5; weighted against NEE towards
    /// the media at the vertex the ray left, a volume event or a
    /// Lambertian bounce).
    fn volumes_collision(&mut self, state: &mut PathState, t_end: f32) -> Collision {
        let scene = self.scene;
        let strategies = self.strategies;
        let mut emitted = Rgb::ZERO;
        let weighting = match state.arrival {
            Arrival::Sampled { from, pdf, .. } if self.emissive => Some(HitWeighting {
                emitters: &scene.media_emitters,
                from,
                pdf_dir: pdf,
                nee: strategies.emission_nee,
                hits: strategies.emission_hits,
            }),
            _ => None,
        };
        let aim = self.aim();
        let collision = self.tracker.sample_collision(
            &scene.volumes,
            &state.ray,
            0.0,
            t_end,
            &mut state.throughput,
            FlightOptions {
                emitted: self.emissive.then_some((&mut emitted, weighting)),
                aim,
            },
        );
        // Emitting media are in no light group.
        self.radiance
            .add(state.history.component(), LightGroup::OTHER, emitted);
        collision
    }

    /// Equiangular samples towards point and spot lights along the
    /// segment's flight through uniform volumes up to `t_end`, for light
    /// whose last scattering is on it ([`VolumeEquiangular`]).
    fn volume_equiangular(&mut self, state: &PathState, t_end: f32) {
        self.volume_equiangular.clear();
        if !self.delta_equiangular || state.depth >= self.max_events {
            return;
        }
        let samples = if state.depth == 0 {
            self.strategies
                .camera_equiangular(self.integrator.volume_samples)
        } else {
            self.strategies.later_equiangular()
        };
        self.volume_equiangular.prepare(
            self.scene,
            &mut self.tracker,
            state.ray,
            t_end,
            state.throughput,
            samples.delta,
            self.sampler,
        );
        let light = self.volume_equiangular.estimate(
            self.scene,
            self.integrator.visibility,
            self.strategies,
            self.counts,
            &mut self.tracker,
        );
        self.radiance.add_gathered(
            state.history.then(Scattering::Medium).component(),
            state.throughput,
            &light,
        );
    }

    /// A point on an area light for the segment's flight through uniform
    /// volumes to aim at ([`FlightOptions::aim`]): one of the scene's
    /// lights that are not Dirac deltas chosen uniformly, a uniform point
    /// on it; `None` for the environment, and without uniform volumes or
    /// such lights (which take no random numbers for it). Point and spot
    /// lights are not aimed at: their equiangular samples feed NEE only
    /// ([`VolumeEquiangular`]).
    fn aim(&mut self) -> Option<Vec3> {
        if !self.aims {
            return None;
        }
        let extended = self.scene.extended_lights();
        let u = self.sampler.next_1d();
        let point = self.sampler.next_2d();
        let nth = ((u * extended.len() as f32) as usize).min(extended.len() - 1);
        self.scene.lights[extended[nth]]
            .sample_point(point)
            .map(|p| p.position)
    }

    /// A real scattering event at `t` in volume `volume`: NEE towards the
    /// lights and the emitting media, then phase sampling.
    fn volume_event(&mut self, state: &mut PathState<'a>, t: f32, volume: usize) -> Step {
        if !self.count_event(state) {
            return Step::End;
        }
        let (scene, strategies) = (self.scene, self.strategies);
        state.history = state.history.then(Scattering::Medium);
        let ray = state.ray;
        let x = ray.at(t);
        let phase = &scene.volumes[volume].phase;
        // The camera path's density of reaching x, if the vertex before
        // connected to light vertices (which can produce x as one).
        let reached = reached_density(
            scene,
            &mut self.tracker,
            &ray,
            t,
            state.connected_from.first,
        );
        let medium = PathVertex {
            scene,
            visibility: self.integrator.visibility,
            x,
            direction: ray.direction,
            phase,
            reached,
        };
        let equiangular = &self.volume_equiangular;
        let light = medium.nee(
            strategies,
            self.sampler,
            self.counts,
            &mut self.tracker,
            |index, light| equiangular.collision_weight(index, light, t),
        );
        self.radiance
            .add_gathered(state.history.component(), state.throughput, &light);
        if self.emissive {
            let emitted = media_emission_nee(
                scene,
                x,
                None,
                strategies,
                self.sampler,
                self.counts,
                &mut self.tracker,
                |omega| {
                    let p = phase.eval(omega.dot(ray.direction));
                    Some((Rgb::splat(p), p))
                },
            );
            self.radiance.add(
                state.history.component(),
                LightGroup::OTHER,
                state.throughput * emitted,
            );
        }
        let connects = self.connections && state.depth < self.max_events;
        if connects {
            let at = CollisionVertex {
                x,
                arriving: ray.direction,
                phase,
            };
            let (group, light) = connect_in_volumes(
                self.integrator,
                scene,
                &at,
                self.sampler,
                self.counts,
                &mut self.tracker,
            );
            self.radiance.add(
                state.history.then(Scattering::Medium).component(),
                group,
                state.throughput * light,
            );
        }
        let (direction, pdf) = phase.sample(ray.direction, self.sampler.next_2d());
        let arrival = Arrival::Sampled {
            from: x,
            pdf,
            in_volume: true,
            reached,
        };
        let connected_from = Connections {
            first: connects.then_some(pdf),
            ..Connections::default()
        };
        state.cone = None;
        let ray = Ray {
            origin: x,
            direction,
        };
        self.scatter(state, ray, arrival, connected_from)
    }

    /// A real scattering event in the fog at `t` on `segment`, whose
    /// equiangular estimator took `samples`: NEE (weighed against the
    /// segment's strategies), light-vertex connections, phase sampling.
    fn fog_event(
        &mut self,
        state: &mut PathState<'a>,
        segment: FogSegment<'a>,
        t: f32,
        samples: EquiangularCounts,
    ) -> Step {
        if !self.count_event(state) {
            return Step::End;
        }
        let (scene, strategies, max_events) = (self.scene, self.strategies, self.max_events);
        state.history = state.history.then(Scattering::Medium);
        let fog = segment.medium.fog;
        state.throughput *= fog.albedo;
        let ray = state.ray;
        let x = ray.at(t);
        let nee = medium_nee(
            &segment,
            t,
            &self.equiangular,
            strategies,
            self.sampler,
            self.counts,
            &mut self.tracker,
        );
        self.radiance
            .add_gathered(state.history.component(), state.throughput, &nee);
        let connects = self.connections && state.depth < max_events;
        let twice = connects && state.depth + 1 < max_events;
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
                connect_light_vertex(self.integrator, scene, fog, &at, self.sampler, self.counts);
            self.radiance.add(
                state.history.then(Scattering::Medium).component(),
                group,
                state.throughput * light,
            );
        }
        let (direction, pdf) = fog.phase.sample(ray.direction, self.sampler.next_2d());
        // Phase sampling is exact: the weight p/pdf is 1.
        let connected_from = Connections {
            first: connects.then_some(pdf),
            second: twice,
            reached: reached.map(|r| r * pdf),
        };
        let arrival = Arrival::Medium {
            pdf,
            segment,
            t,
            samples,
        };
        state.cone = None;
        let ray = Ray {
            origin: x,
            direction,
        };
        self.scatter(state, ray, arrival, connected_from)
    }

    /// The surface the segment ends on: its emission, then what it does
    /// to the path (a pane passes it, an interface refracts or reflects
    /// it, a reflector scatters it).
    fn surface_event(&mut self, state: &mut PathState<'a>, hit: &Hit) -> Step {
        let (scene, strategies) = (self.scene, self.strategies);
        let ray = state.ray;
        let SurfaceHit {
            p,
            geometric_normal,
            normals,
            front,
            footprint,
        } = SurfaceHit::new(scene, &ray, hit, state.cone);
        state.cone = state.cone.map(|c| c.advanced(hit.t));
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
                        if matches!(state.arrival, Arrival::Unweighted) {
                            self.radiance.add(
                                state.history.component(),
                                scene.light_group_at(hit.primitive),
                                state.throughput * le,
                            );
                        }
                    }
                    Some(le) => {
                        let le = scene.emitted_at(le, hit.primitive, p, footprint);
                        let weight = emission_weight(
                            scene,
                            strategies,
                            state.arrival,
                            hit.primitive,
                            p,
                            ray.direction,
                            &mut self.tracker,
                        );
                        self.radiance.add(
                            state.history.component(),
                            scene.light_group_at(hit.primitive),
                            state.throughput * le * weight,
                        );
                    }
                    None => {}
                }
                // An emitter that also reflects goes on as a surface.
                match reflects {
                    Some(surface) => scene.surface_at(surface, hit.primitive, p, footprint),
                    None => return Step::End,
                }
            }
            SurfaceEvent::Pane { transmittance } => {
                state.crossings += 1;
                if state.crossings > MAX_GLASS_CROSSINGS {
                    return Step::End;
                }
                state.throughput *= transmittance;
                state.ray.origin = offset_origin(p, geometric_normal, ray.direction);
                // The segment after the pane no longer starts at the event.
                state.connected_from = Connections::default();
                return Step::Continue;
            }
            SurfaceEvent::Interface(interface) => {
                // A specular event: NEE cannot reach through it.
                if !self.count_event(state) {
                    return Step::End;
                }
                let next = refract_or_reflect(
                    &ray,
                    p,
                    geometric_normal,
                    interface,
                    self.sampler,
                    &mut state.solids,
                );
                return self.scatter(state, next, Arrival::Unweighted, Connections::default());
            }
            SurfaceEvent::Reflector(surface) => {
                scene.surface_at(surface, hit.primitive, p, footprint)
            }
        };
        if !self.count_event(state) {
            return Step::End;
        }
        self.reflection(state, &surface, p, geometric_normal, normals)
    }

    /// Scattering by a surface's lobes at `p`: NEE for its Lambertian
    /// lobe (MIS against its cosine sampling) and towards emitting media,
    /// light-vertex connections, then one lobe sampled.
    fn reflection(
        &mut self,
        state: &mut PathState<'a>,
        surface: &Surface,
        p: Vec3,
        geometric_normal: Vec3,
        normals: SurfaceNormals,
    ) -> Step {
        let (scene, strategies, max_events) = (self.scene, self.strategies, self.max_events);
        if surface.diffuse_probability().is_none() {
            return Step::End;
        }
        let ray = state.ray;
        // Light reflected here, by whichever lobe, has scattered here.
        let here = state.history.then(Scattering::Surface);
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
        if strategies.surface_nee {
            let light = surface_direct_lighting(
                scene,
                self.integrator.visibility,
                surface,
                (p, ray.direction),
                normals,
                self.sampler,
                self.counts,
                &mut self.tracker,
                mis,
            );
            self.radiance
                .add_gathered(here.component(), state.throughput, &light);
        }
        // NEE towards emitting media, for the Lambertian lobe, MIS
        // against its cosine sampling as for area lights.
        if self.emissive && surface.diffuse != Rgb::ZERO {
            let emitted = media_emission_nee(
                scene,
                p,
                Some(normals.geometric),
                strategies,
                self.sampler,
                self.counts,
                &mut self.tracker,
                |omega| {
                    normals.reflects(omega).then(|| {
                        let cos = normals.shading.dot(omega);
                        (
                            surface.diffuse_brdf() * cos,
                            surface.pdf(normals.shading, omega),
                        )
                    })
                },
            );
            self.radiance.add(
                here.component(),
                LightGroup::OTHER,
                state.throughput * emitted,
            );
        }
        // Light-vertex connections from Lambertian surfaces only: a
        // glossy lobe's density could not be weighed against them.
        let connects = self.connections && state.depth < max_events && !surface.has_specular();
        let twice = connects && state.depth + 1 < max_events;
        if connects && let Some(fog) = &scene.fog {
            let vertex = Scatterer::Surface {
                surface: *surface,
                normals,
            };
            let at = LightVertexOrigin {
                x: p,
                vertex: &vertex,
                reached: None,
                twice,
            };
            let (group, light) =
                connect_light_vertex(self.integrator, scene, fog, &at, self.sampler, self.counts);
            self.radiance.add(
                here.then(Scattering::Medium).component(),
                group,
                state.throughput * light,
            );
        }
        let choice = self.sampler.next_1d();
        let u = self.sampler.next_2d();
        let Some(sample) = surface.sample(ray.direction, normals.shading, choice, u) else {
            return Step::End;
        };
        if !normals.reflects(sample.direction) {
            return Step::End;
        }
        state.throughput *= sample.weight;
        let direction = sample.direction;
        // A mirror's reflection does not scatter; a diffuse or glossy one does.
        if sample.lobe == Lobe::Diffuse || surface.roughness_of(sample.lobe) > 0.0 {
            state.history = here;
        }
        let (arrival, connected_from) = match sample.lobe {
            Lobe::Diffuse => {
                state.cone = None;
                let connects = connects && scene.fog.is_some();
                (
                    Arrival::Sampled {
                        from: p,
                        pdf: sample.pdf,
                        in_volume: false,
                        reached: None,
                    },
                    Connections {
                        first: connects.then_some(sample.pdf),
                        second: twice && connects,
                        reached: None,
                    },
                )
            }
            Lobe::Specular | Lobe::Coat => (Arrival::Unweighted, Connections::default()),
        };
        let ray = Ray {
            origin: offset_origin(p, geometric_normal, direction),
            direction,
        };
        self.scatter(state, ray, arrival, connected_from)
    }
}
