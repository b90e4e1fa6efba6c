//! Unbiased single scattering: per light, equiangular sampling (Kulla &
//! Fajardo 2012) and transmittance-proportional distance sampling along
//! the camera ray, combined by multiple importance sampling with the
//! balance heuristic (Veach 1997).
//!
//! For each light chosen for the segment (all of them, or the visited ones
//! and those the light tree chooses, [`crate::lights::LightSampler`],
//! each estimate times its weight `1/P`), one emitting point `y` is
//! chosen; then `n` equiangular
//! samples (restricted to the light's reach: a spotlight's cone) and the
//! ray's one distance sample (shared by all lights) estimate the
//! in-scattering integral for that `y`. With densities `p_e`, `p_d`, the
//! multi-sample balance heuristic gives the unbiased estimator
//! `Σ_k f(t_k)/(n·p_e(t_k) + p_d(t_k)) + f(t_d)/(n·p_e(t_d) + p_d(t_d))`,
//! which takes the better strategy where each is good: equiangular near
//! point lights, distance sampling in dense fog and for suns.
//!
//! The `n` equiangular samples of a ray are stratified: they share one
//! sample dimension `u` and use `(k + u)/n`, so along the ray they cover
//! the light's reach evenly, as a march's steps do, while each pixel
//! sample's `u` is stratified against the others. Visibility (shadows,
//! window frames) is what makes one sample per ray noisy; several cost a
//! shadow ray each but no new camera ray.

use super::lighting::{MediumQuery, light_point, lights_along, scattered_radiance};
use super::path_radiance::{Gathered, Keep};
use crate::color::Rgb;
use crate::media::tracking::VolumeTracker;
use crate::media::transmittance;
use crate::sampler::PixelSampler;
use crate::sampling::{EquiangularSampler, ExponentialSampler};
use crate::visibility::{RayCounts, Visibility};

/// Single scattering's parameters.
#[derive(Clone, Copy)]
pub struct Single<'a> {
    /// Equiangular samples per light on each camera segment.
    pub volume_samples: u32,
    /// Most specular events (dielectrics, reflective layers) a camera
    /// path follows.
    pub max_bounces: u32,
    pub(crate) visibility: &'a Visibility,
}

/// One sample's term of the multi-sample balance heuristic above:
/// `f·T/(n·p_e + p_d)`, with `f` eq. 1 at the sample, `T` the camera-side
/// transmittance to it, `n` equiangular samples of density `p_e` and the
/// distance sample's density `p_d` there. The WGSL twin is
/// `single_sample` of the GPU crate's `formulas.wgsl`.
#[inline]
pub fn single_sample(f: Rgb, camera_transmittance: f32, n: f32, pdf_e: f32, pdf_d: f32) -> Rgb {
    f * (camera_transmittance / (n * pdf_e + pdf_d))
}

/// In-scattered radiance along the query's ray over `(0, t_hit)`,
/// relative to the radiance at the ray origin (one sample).
// Inlined into both instantiations of the camera path (with and without
// the components; see `camera_path::InScattering::estimate`).
#[inline(always)]
pub(crate) fn in_scattered<K: Keep>(
    medium: &MediumQuery,
    samples_per_light: u32,
    sampler: &mut PixelSampler,
    counts: &mut RayCounts,
    tracker: &mut VolumeTracker,
) -> Gathered<K> {
    let (scene, fog, ray) = (medium.scene, medium.fog, &medium.ray);
    let mut sum = Gathered::new();
    let u_distance = sampler.next_1d();
    let Some((a, b)) = fog.interval(ray, 0.0, medium.t_hit) else {
        return sum;
    };
    if fog.sigma_s() == Rgb::ZERO {
        return sum;
    }
    let Some(distance) = ExponentialSampler::new(fog.sigma_t, a, b) else {
        return sum;
    };
    let (t_d, pdf_d) = distance.sample(u_distance);
    let x_d = ray.at(t_d);
    let camera_t = |t: f32| transmittance(fog.sigma_t, t - a);
    for (index, chosen) in lights_along(scene, ray, a, b, sampler) {
        let light = &scene.lights[index];
        let group = scene.light_group(index);
        let y = light_point(light, sampler);
        let u_equiangular = sampler.next_1d();
        let equiangular = y.and_then(|y| {
            let (ea, eb) = light.reach(ray, a, b)?;
            EquiangularSampler::new(ray, y.position, ea, eb)
        });
        let n = samples_per_light as f32;
        if let Some(eq) = &equiangular {
            for k in 0..samples_per_light {
                let (t, pdf_e) = eq.sample((k as f32 + u_equiangular) / n);
                let f = scattered_radiance(medium, index, y, ray.at(t), sampler, counts, tracker);
                if f != Rgb::ZERO {
                    sum.add(
                        group,
                        single_sample(f, camera_t(t), n, pdf_e, distance.pdf(t)) * chosen,
                    );
                }
            }
        }
        let pdf_e = equiangular.map_or(0.0, |eq| eq.pdf(t_d));
        let f = scattered_radiance(medium, index, y, x_d, sampler, counts, tracker);
        if f != Rgb::ZERO {
            sum.add(
                group,
                single_sample(f, camera_t(t_d), n, pdf_e, pdf_d) * chosen,
            );
        }
    }
    sum
}
