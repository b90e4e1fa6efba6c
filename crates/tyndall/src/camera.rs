//! The pinhole perspective camera.

use crate::ray::Ray;
use glam::{Vec2, Vec3};

/// How a field of view is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FieldOfView {
    /// Full vertical angle in degrees (the native format, the references).
    Vertical(f32),
    /// Full angle in degrees across the image's shorter side (the course
    /// code base's `angle`).
    ShorterSide(f32),
}

/// Where the camera is and how it looks, independent of image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSpec {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    pub fov: FieldOfView,
}

/// A pinhole camera for one image size. Forward `f = normalize(look_at −
/// position)`, right `r = normalize(f × up)`, image-up `u = r × f`; pixel
/// row 0 is the top of the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    position: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    /// Half-extent of the image plane at distance 1: (tan(fov_x/2), tan(fov_y/2)).
    half_extent: Vec2,
    resolution: Vec2,
}

impl Camera {
    /// The camera for an image of `width × height` pixels. The spec is
    /// validated by the loaders (distinct position and look-at, up not
    /// parallel to the view direction).
    pub fn new(spec: &CameraSpec, width: u32, height: u32) -> Self {
        let forward = (spec.look_at - spec.position).normalize();
        let right = forward.cross(spec.up).normalize();
        let up = right.cross(forward);
        let aspect = width as f32 / height as f32;
        let tan_y = match spec.fov {
            FieldOfView::Vertical(deg) => (0.5 * deg.to_radians()).tan(),
            FieldOfView::ShorterSide(deg) => {
                let t = (0.5 * deg.to_radians()).tan();
                if aspect >= 1.0 { t } else { t / aspect }
            }
        };
        Self {
            position: spec.position,
            forward,
            right,
            up,
            half_extent: Vec2::new(tan_y * aspect, tan_y),
            resolution: Vec2::new(width as f32, height as f32),
        }
    }

    /// The ray through the film position `pixel` (in pixels: x to the
    /// right, y down, pixel (i, j) covers `[i, i+1) × [j, j+1)`).
    #[inline]
    pub fn ray(&self, pixel: Vec2) -> Ray {
        let ndc = 2.0 * pixel / self.resolution - Vec2::ONE;
        let dir = self.forward + self.right * (ndc.x * self.half_extent.x)
            - self.up * (ndc.y * self.half_extent.y);
        Ray::new(self.position, dir)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_pixel_looks_forward_and_top_row_looks_up() {
        let spec = CameraSpec {
            position: Vec3::new(0.0, 1.0, 5.0),
            look_at: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::Y,
            fov: FieldOfView::Vertical(40.0),
        };
        let cam = Camera::new(&spec, 320, 240);
        let c = cam.ray(Vec2::new(160.0, 120.0));
        assert!((c.direction - (-Vec3::Z)).length() < 1e-6);
        let top = cam.ray(Vec2::new(160.0, 0.0));
        let angle = top.direction.dot(-Vec3::Z).acos().to_degrees();
        assert!(top.direction.y > 0.0 && (angle - 20.0).abs() < 1e-3);
        let right = cam.ray(Vec2::new(320.0, 120.0));
        assert!(right.direction.x > 0.0);
    }
}
