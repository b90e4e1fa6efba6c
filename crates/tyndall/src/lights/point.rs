//! Point lights: radiant intensity in all directions from one point.

use super::{Incident, LeSample, LightPoint, towards};
use crate::color::Rgb;
use crate::ray::Ray;
use crate::sampling::uniform_cone;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Point light of radiant intensity `intensity` (W/sr) in all directions.
/// The paper writes `Φ/(4π)` for a light of power Φ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    pub intensity: Rgb,
}

impl PointLight {
    /// Light reaching `x`: `I/d²` from the light's position; `None` at
    /// the position itself.
    #[inline]
    pub(super) fn incident(&self, x: Vec3) -> Option<Incident> {
        let (direction, d2) = towards(x, self.position)?;
        Some(Incident {
            direction,
            distance: d2.sqrt(),
            irradiance: self.intensity / d2,
            light_normal: None,
        })
    }

    /// A ray leaving the light uniformly over the sphere (from
    /// `u_direction`), carrying `I·4π`.
    pub(super) fn sample_le(&self, u_direction: Vec2) -> LeSample {
        let direction = uniform_cone(Vec3::Z, -1.0, u_direction);
        LeSample {
            point: LightPoint::delta(self.position),
            ray: Ray {
                origin: self.position,
                direction,
            },
            beta: self.intensity * (4.0 * PI),
        }
    }

    /// Total emitted power, `4π·I`.
    pub(super) fn power(&self) -> Rgb {
        self.intensity * (4.0 * PI)
    }
}
