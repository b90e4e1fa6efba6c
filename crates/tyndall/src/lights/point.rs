//! Point lights: radiant intensity in all directions from one point.

use super::bounds::LightBounds;
use super::photometric::Luminaire;
use super::{Incident, LeSample, LightPoint, mean_channel, towards};
use crate::color::Rgb;
use crate::ray::Ray;
use crate::sampling::uniform_cone;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Point light of radiant intensity `intensity` (W/sr) in all directions,
/// or, with a measured `luminaire` profile, `intensity·P(ω)` towards ω
/// (`intensity` then the peak). The paper writes `Φ/(4π)` for a light of
/// power Φ.
#[derive(Clone, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    pub intensity: Rgb,
    pub luminaire: Option<Luminaire>,
}

impl PointLight {
    /// The relative intensity towards the unit direction `emitted`: 1, or
    /// the luminaire's profile there.
    #[inline]
    fn profile(&self, emitted: Vec3) -> f32 {
        self.luminaire.as_ref().map_or(1.0, |l| l.factor(emitted))
    }

    /// Light reaching `x`: `I·P/d²` from the light's position; `None` at
    /// the position itself and where the profile is 0.
    #[inline]
    pub(super) fn incident(&self, x: Vec3) -> Option<Incident> {
        let (direction, d2) = towards(x, self.position)?;
        let irradiance = match &self.luminaire {
            None => self.intensity / d2,
            Some(l) => {
                let profile = l.factor(-direction);
                if profile <= 0.0 {
                    return None;
                }
                self.intensity * (profile / d2)
            }
        };
        Some(Incident {
            direction,
            distance: d2.sqrt(),
            irradiance,
            light_normal: None,
        })
    }

    /// A ray leaving the light uniformly over the sphere (from
    /// `u_direction`), carrying `I·P·4π`.
    pub(super) fn sample_le(&self, u_direction: Vec2) -> LeSample {
        let direction = uniform_cone(Vec3::Z, -1.0, u_direction);
        LeSample {
            point: LightPoint::delta(self.position),
            ray: Ray {
                origin: self.position,
                direction,
            },
            beta: self.intensity * (self.profile(direction) * 4.0 * PI),
        }
    }

    /// Its emission's bounds: all directions, at most `I` (a measured
    /// profile is normalised to its peak).
    pub(super) fn bounds(&self) -> LightBounds {
        LightBounds::sphere(self.position, mean_channel(self.intensity))
    }

    /// Total emitted power, `4π·I` (times the profile's mean).
    pub(super) fn power(&self) -> Rgb {
        let mean = self.luminaire.as_ref().map_or(1.0, |l| l.profile.mean());
        self.intensity * (4.0 * PI * mean)
    }
}
