//! Directional lights (a sun): parallel light from infinitely far.

use super::Incident;
use crate::color::Rgb;
use glam::Vec3;
use std::f32::consts::PI;

/// Directional light (a sun): parallel light travelling along `direction`
/// with irradiance `irradiance` (W/m²) on a surface facing it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalLight {
    /// Unit direction the light travels in.
    pub direction: Vec3,
    pub irradiance: Rgb,
}

impl DirectionalLight {
    /// Light reaching any point: the irradiance, from infinitely far
    /// against the light's direction.
    #[inline]
    pub(super) fn incident(&self) -> Incident {
        Incident {
            direction: -self.direction,
            distance: f32::INFINITY,
            irradiance: self.irradiance,
            light_normal: None,
        }
    }

    /// The flux through a disk of radius `scene_radius` (the scene's
    /// bounding sphere) facing the light, `E·π·r²`, as pbrt-v4's
    /// `DistantLight`.
    pub(super) fn power(&self, scene_radius: f32) -> Rgb {
        self.irradiance * (PI * scene_radius * scene_radius)
    }
}
