//! Light arriving at points of a path, shared by every integrator: light
//! sampling, the in-scattered radiance of the paper's eq. 1
//! ([`scattered_radiance`]), the visibility and media transmittance of a
//! connection, and direct lighting of a Lambertian surface.

use super::path_radiance::{Gathered, Keep};
use super::surfaces::SurfaceNormals;
use crate::color::Rgb;
use crate::lights::{Chosen, Incident, Light, LightPoint};
use crate::materials::Surface;
use crate::media::Fog;
use crate::media::tracking::VolumeTracker;
use crate::ray::{Ray, offset_origin};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::visibility::{RayCounts, Visibility};
use glam::{Vec2, Vec3};

/// The [`PixelSampler::stream`] purpose of a path's tracking numbers.
pub(crate) const TRACKING_STREAM: u64 = 1;

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
pub(super) fn light_point(light: &Light, sampler: &mut PixelSampler) -> Option<LightPoint> {
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

/// The random number of a light choice: one sample dimension when the
/// light tree chooses, none when every light is visited.
#[inline]
fn choice_u(scene: &Scene, sampler: &mut PixelSampler) -> f32 {
    if scene.light_sampler.chooses() {
        sampler.next_1d()
    } else {
        0.0
    }
}

/// The lights an estimate at `x` connects to, with their weights
/// ([`crate::lights::LightSampler::at`]).
#[inline]
pub(crate) fn lights_at<'s>(scene: &'s Scene, x: Vec3, sampler: &mut PixelSampler) -> Chosen<'s> {
    let u = choice_u(scene, sampler);
    scene.light_sampler.at(x, u)
}

/// The lights an estimate along the fog segment `[a, b]` of `ray`
/// connects to, with their weights
/// ([`crate::lights::LightSampler::along`]).
#[inline]
pub(crate) fn lights_along<'s>(
    scene: &'s Scene,
    ray: &Ray,
    a: f32,
    b: f32,
    sampler: &mut PixelSampler,
) -> Chosen<'s> {
    let u = choice_u(scene, sampler);
    scene.light_sampler.along(&scene.lights, ray, a, b, u)
}

/// Radiance scattered at fog point `x` of the query's ray towards the
/// camera from light number `index` via its emitting point `y`, per unit
/// length: the paper's eq. 1,
/// `σs · p(θ) · I(dir)/d² · V · Tr_glass · exp(−σt·d)`.
/// Zero without a visibility query outside a spotlight's cone. A light
/// with neither a point nor a fixed direction (the environment, for which
/// [`light_point`] gives `None`) is sampled here, at `x`, from `sampler`.
#[inline]
pub(crate) fn scattered_radiance(
    medium: &MediumQuery,
    index: usize,
    y: Option<LightPoint>,
    x: Vec3,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
) -> Rgb {
    let light = &medium.scene.lights[index];
    let incident = match y {
        None if !light.is_delta() => sample_light(light, x, sampler).map(|(i, _)| i),
        _ => light.incident(x, y),
    };
    let Some(incident) = incident else {
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

/// Direct lighting of `surface` at point `p` with `normals` facing the
/// viewer, seen by a ray travelling along `incoming`, one sample per
/// chosen light ([`lights_at`], weight `c`):
/// `Σ c · (ρ/π · cos θ · w + f_layers) · E · V · Tr_glass · T_media` (θ
/// from the shading normal; light from below the geometric surface does
/// not count), where `w = weight(p_light, ω)` is the caller's MIS weight
/// for the Lambertian lobe given the light sample's solid-angle density
/// (`None` for delta lights) and unit direction ω towards it, and
/// `f_layers` is the glossy layers' `f·cos θ` ([`Surface::glossy_toward`])
/// for delta lights alone: their reflected rays find every other light,
/// and no ray finds a delta light.
#[allow(clippy::too_many_arguments)]
// Inlined into each integrator's two instantiations (with and without the
// components), as into their one before: measured, the call instead cost
// 1.5 % of a `single` sample.
#[inline(always)]
pub(crate) fn surface_direct_lighting<K: Keep>(
    scene: &Scene,
    visibility: &Visibility,
    surface: &Surface,
    (p, incoming): (Vec3, Vec3),
    normals: SurfaceNormals,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
    weight: impl Fn(Option<f32>, Vec3) -> f32,
) -> Gathered<K> {
    let mut sum = Gathered::new();
    // The glossy layers as this viewer sees them, made once for every
    // delta light (none on a surface without them).
    let glossy = surface
        .has_glossy_layer()
        .then(|| surface.glossy_toward(incoming, normals.shading));
    if surface.diffuse == Rgb::ZERO && glossy.is_none() {
        return sum;
    }
    for (index, chosen) in lights_at(scene, p, sampler) {
        let light = &scene.lights[index];
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
        let lambert = surface.diffuse_brdf() * (cos * weight(p_light, incident.direction));
        let f = match (p_light, &glossy) {
            (None, Some(layers)) => {
                let omega = incident.direction;
                lambert + layers.iter().flatten().map(|l| l.eval(omega)).sum::<Rgb>()
            }
            _ => lambert,
        };
        sum.add(scene.light_group(index), arriving * f * chosen);
    }
    sum
}

/// [`scattered_radiance`], [`light_arriving`] and
/// [`surface_direct_lighting`] with their scratch made here, for the
/// tests that check their WGSL twins (`lights.wgsl` and `camera.wgsl` of
/// crate `tyndall-gpu`) against them.
pub mod twins {
    use super::*;
    use crate::integrators::path_radiance::Whole;
    use crate::sampler::RandomStream;

    /// A tracker of its own for one twin's call.
    pub(crate) fn tracker() -> VolumeTracker {
        VolumeTracker::new(RandomStream::new(0))
    }

    /// The query of `ray` over `(0, t_hit)` in `scene`'s fog; `None`
    /// without fog.
    pub(crate) fn fog_query<'a>(
        scene: &'a Scene,
        visibility: &'a Visibility,
        ray: Ray,
        t_hit: f32,
    ) -> Option<MediumQuery<'a>> {
        Some(MediumQuery {
            scene,
            visibility,
            fog: scene.fog()?,
            ray,
            t_hit,
        })
    }

    /// [`scattered_radiance`] at fog point `x` of a ray along unit `view`
    /// from light `index` via its point `y`, in `scene`'s fog (none: 0).
    pub fn scattered_radiance(
        scene: &Scene,
        visibility: &Visibility,
        index: usize,
        y: Option<LightPoint>,
        x: Vec3,
        view: Vec3,
    ) -> Rgb {
        let ray = Ray {
            origin: x - view,
            direction: view,
        };
        let Some(medium) = fog_query(scene, visibility, ray, 1.0) else {
            return Rgb::ZERO;
        };
        let mut counts = RayCounts::default();
        super::scattered_radiance(
            &medium,
            index,
            y,
            x,
            &mut PixelSampler::new(0, 0, 0),
            &mut counts,
            &mut tracker(),
        )
    }

    /// [`surface_direct_lighting`] unweighted (one strategy) at `x` on a
    /// flat surface of unit `normal`, of Lambertian reflectance `diffuse`
    /// and a specular layer `(reflectance, roughness)`, seen along
    /// `incoming`. Area lights' points come from a fixed sample stream,
    /// which the GPU's twin does not share: compare on delta lights.
    pub fn direct_lighting(
        scene: &Scene,
        visibility: &Visibility,
        (diffuse, (specular, roughness)): (Rgb, (Rgb, f32)),
        (x, incoming): (Vec3, Vec3),
        normal: Vec3,
    ) -> Rgb {
        let mut counts = RayCounts::default();
        super::surface_direct_lighting::<Whole>(
            scene,
            visibility,
            &Surface::layered(diffuse, specular, roughness),
            (x, incoming),
            SurfaceNormals::flat(normal),
            &mut PixelSampler::new(0, 0, 0),
            &mut counts,
            &mut tracker(),
            |_, _| 1.0,
        )
        .total()
    }

    /// [`light_arriving`] at `x` (on a surface of unit `normal`, or in
    /// fog) from light `index` as `incident`.
    pub fn light_arriving(
        scene: &Scene,
        visibility: &Visibility,
        index: usize,
        x: Vec3,
        normal: Option<Vec3>,
        incident: &Incident,
    ) -> Rgb {
        let mut counts = RayCounts::default();
        super::light_arriving(
            scene,
            visibility,
            index,
            x,
            normal,
            incident,
            &mut counts,
            &mut tracker(),
        )
    }
}
