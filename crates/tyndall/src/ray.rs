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

/// The distance [`offset_origin`] moves `point` off a surface: a fixed
/// fraction of the point's largest coordinate (plus one scene unit), so
/// that it clears the rounding of hit points at any position.
#[inline]
pub fn offset_distance(point: Vec3) -> f32 {
    OFFSET_SCALE * (1.0 + point.abs().max_element())
}

/// Moves `point` off a surface with geometric normal `normal` to the side
/// that `direction` leaves towards, so a ray spawned there does not hit the
/// surface it starts on.
#[inline]
pub fn offset_origin(point: Vec3, normal: Vec3, direction: Vec3) -> Vec3 {
    let side = if normal.dot(direction) >= 0.0 {
        1.0
    } else {
        -1.0
    };
    point + normal * (side * offset_distance(point))
}

/// How far a shadow ray from `origin` along the unit `direction` may go
/// towards a point on a light `distance` away from `origin` without
/// reaching the light's own geometry (an emissive quad): that distance,
/// which must be measured from the ray's actual origin (which
/// [`offset_origin`] may have moved off the receiver), shortened by the
/// same scale-aware offset at the light's end and by a relative margin
/// for the rounding of the distance itself.
///
/// Measuring from the receiver instead of the moved origin, with a fixed
/// margin, let shadow rays from receivers whose offset exceeded the
/// margin (coordinates above about 1 unit, a light under a metre away)
/// end past the light and be blocked by it.
#[inline]
pub fn shadow_ray_end(origin: Vec3, direction: Vec3, distance: f32) -> f32 {
    distance * (1.0 - 1e-4) - offset_distance(origin + direction * distance)
}
