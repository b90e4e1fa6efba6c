//! Rays and the offsets that keep secondary rays off the surface they leave.

use glam::Vec3;

/// A ray `x(s) = origin + s·direction` with a unit-length direction, so that
/// the parameter `s` is a distance in scene units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub direction: Vec3,
}

impl Ray {
    /// A ray from `origin` along `direction` (normalised here).
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        Self {
            origin,
            direction: direction.normalize(),
        }
    }

    /// The point at distance `s` along the ray.
    #[inline]
    pub fn at(&self, s: f32) -> Vec3 {
        self.origin + s * self.direction
    }
}

/// Relative size of the offset that moves a ray origin off a surface:
/// large enough to clear f32 rounding of the hit point (a few ulps of the
/// coordinates' magnitude), small against any feature of a scene.
const OFFSET_SCALE: f32 = 1e-4;

/// Moves `point` off a surface with geometric normal `normal` to the side
/// that `direction` leaves towards, so a ray spawned there does not hit the
/// surface it starts on.
#[inline]
pub fn offset_origin(point: Vec3, normal: Vec3, direction: Vec3) -> Vec3 {
    let eps = OFFSET_SCALE * (1.0 + point.abs().max_element());
    let side = if normal.dot(direction) >= 0.0 {
        1.0
    } else {
        -1.0
    };
    point + normal * (side * eps)
}

/// Shortening applied to a shadow ray that ends on a light, so that the
/// light's own geometry (an emissive quad) does not occlude it.
#[inline]
pub fn shadow_ray_end(distance: f32) -> f32 {
    distance * (1.0 - 1e-4) - OFFSET_SCALE
}
