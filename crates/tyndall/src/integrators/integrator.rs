//! The integrator a render uses, configured from the settings, and the
//! one dispatch of a camera ray to it.

use super::PixelPosition;
use super::camera_path::{CameraPath, InScattering};
use super::march::{self, March};
use super::path_radiance::{Keep, PathRadiance, Whole};
use super::single::Single;
use super::volpath::{self, LightSubpaths, Volpath};
use crate::color::Rgb;
use crate::footprint::RayCone;
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use crate::settings::{IntegratorKind, RenderSettings};
use crate::visibility::{RayCounts, Visibility};

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
    /// pixel `pixel`, its textures read at full resolution (a ray without
    /// a cone).
    pub fn radiance(
        &self,
        scene: &Scene,
        ray: Ray,
        pixel: PixelPosition,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
    ) -> Rgb {
        self.sample::<Whole>(scene, ray, None, pixel, sampler, counts)
            .total()
    }

    /// As [`Integrator::radiance`], with what `K` keeps of its components
    /// ([`crate::aov::Component`]; the total is the same), and textures
    /// filtered over the camera ray's `cone` where it is given
    /// ([`crate::footprint`]).
    pub(crate) fn sample<K: Keep>(
        &self,
        scene: &Scene,
        ray: Ray,
        cone: Option<RayCone>,
        pixel: PixelPosition,
        sampler: &mut PixelSampler,
        counts: &mut RayCounts,
    ) -> PathRadiance<K> {
        let path = match self {
            Integrator::March(march) => CameraPath {
                visibility: march.visibility,
                max_bounces: march.max_bounces,
                in_scattering: InScattering::March {
                    step: march.step,
                    stratum: march::interleaved_stratum(pixel, march.interleave),
                },
            },
            Integrator::Single(single) => CameraPath {
                visibility: single.visibility,
                max_bounces: single.max_bounces,
                in_scattering: InScattering::Single {
                    volume_samples: single.volume_samples,
                },
            },
            Integrator::Volpath(volpath) => {
                return volpath::radiance(volpath, scene, ray, cone, sampler, counts);
            }
        };
        path.radiance(scene, ray, cone, sampler, counts)
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
