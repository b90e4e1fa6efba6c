//! The pinhole perspective camera.

use crate::footprint::RayCone;
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

impl FieldOfView {
    /// Smallest and largest field of view accepted, in degrees (either
    /// way it is given): below 10⁻³° the image plane's spacing underflows
    /// against the view distance; at 180° the image plane is infinite.
    pub const RANGE_DEG: (f32, f32) = (1e-3, 179.0);

    /// The accepted range in words, for error messages.
    pub const RANGE_WORDS: &str = "an angle from 0.001° to 179°";

    /// The angle in degrees, whichever side it spans.
    pub fn degrees(self) -> f32 {
        let (Self::Vertical(a) | Self::ShorterSide(a)) = self;
        a
    }

    /// Whether `degrees` lies in [`Self::RANGE_DEG`] (NaN does not).
    pub fn in_range(degrees: f32) -> bool {
        (Self::RANGE_DEG.0..=Self::RANGE_DEG.1).contains(&degrees)
    }
}

/// Where the camera is and how it looks, independent of image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSpec {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    pub fov: FieldOfView,
}

impl CameraSpec {
    /// A camera at `position` looking at `look_at`, +Y up, with a full
    /// vertical field of view of `fov_y_deg` degrees.
    pub fn looking_at(position: Vec3, look_at: Vec3, fov_y_deg: f32) -> Self {
        Self {
            position,
            look_at,
            up: Vec3::Y,
            fov: FieldOfView::Vertical(fov_y_deg),
        }
    }

    /// Checks that a camera can be built: distinct position and target, an
    /// up vector not parallel to the view direction.
    pub fn check(&self) -> Result<(), String> {
        let spec = self;
        let forward = spec.look_at - spec.position;
        let has_direction = forward.length_squared() > 0.0; // false for NaN too
        if !has_direction {
            return Err("the camera's look-at point must differ from its position".into());
        }
        let up_length = spec.up.length_squared(); // 0 when it underflows
        if !(up_length > 0.0 && up_length.is_finite()) {
            return Err(
            "the camera's up vector must be a non-zero direction (of length between 1e-19 and 1e19)"
                .into(),
        );
        }
        let up_across_view = forward
            .normalize()
            .cross(spec.up.normalize())
            .length_squared()
            > 1e-10;
        if !up_across_view {
            return Err("the camera's up vector must not be parallel to its view direction".into());
        }
        Ok(())
    }
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

    /// The camera's frame: forward, right and image-up (unit vectors) and
    /// the image plane's half-extent at distance 1, for renderers that
    /// build the rays themselves (the GPU path).
    pub fn frame(&self) -> (Vec3, Vec3, Vec3, Vec2) {
        (self.forward, self.right, self.up, self.half_extent)
    }

    /// The cone about the camera ray along unit `direction` that spreads
    /// over `scale` of a pixel ([`crate::footprint::camera_spread_scale`]):
    /// from the pinhole (width 0), its spread the angle a pixel subtends
    /// across that ray, `(2·tan(fov_y/2)/height)·cos θ` at θ off the
    /// optical axis, times `scale`.
    #[inline]
    pub fn cone(&self, direction: Vec3, scale: f32) -> RayCone {
        let pixel = 2.0 * self.half_extent.y / self.resolution.y;
        RayCone {
            width: 0.0,
            spread: pixel * direction.dot(self.forward).max(0.0) * scale,
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

/// Where a scene point appears on the film, for light paths connected to
/// the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Film position in pixels (as [`Camera::ray`] takes it).
    pub film: Vec2,
    /// Unit direction from the point to the camera.
    pub to_camera: Vec3,
    pub distance: f32,
    /// The camera's importance `W = 1/(A_pixel·cos³θ)` per unit solid
    /// angle at the camera, θ off the optical axis, `A_pixel` a pixel's
    /// area on the image plane at distance 1. Our pixels average radiance
    /// uniformly over their area on that plane, and a solid angle dω
    /// there covers `dω/cos³θ` of it, so `∫_pixel W·L dω` is the pixel's
    /// value: the light tracer's measurement matches the camera's.
    pub importance: f32,
}

impl Camera {
    /// The projection of `x`, or `None` if it is behind the camera or
    /// outside the image.
    pub fn project(&self, x: Vec3) -> Option<Projection> {
        let d = x - self.position;
        let distance = d.length();
        let z = d.dot(self.forward);
        if !(z > 0.0 && distance > 0.0) {
            return None;
        }
        let plane = Vec2::new(d.dot(self.right), d.dot(self.up)) / z;
        let ndc = Vec2::new(plane.x / self.half_extent.x, -plane.y / self.half_extent.y);
        let film = (ndc + Vec2::ONE) * 0.5 * self.resolution;
        if !(film.cmpge(Vec2::ZERO).all() && film.cmplt(self.resolution).all()) {
            return None;
        }
        let pixel_area =
            4.0 * self.half_extent.x * self.half_extent.y / (self.resolution.x * self.resolution.y);
        let cos = z / distance;
        Some(Projection {
            film,
            to_camera: -d / distance,
            distance,
            importance: 1.0 / (pixel_area * cos * cos * cos),
        })
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

    #[test]
    fn projection_inverts_rays_and_importance_integrates_to_one() {
        let spec = CameraSpec {
            position: Vec3::new(0.3, 1.0, 5.0),
            look_at: Vec3::new(0.0, 0.8, 0.0),
            up: Vec3::Y,
            fov: FieldOfView::Vertical(50.0),
        };
        let cam = Camera::new(&spec, 64, 48);
        for film in [
            Vec2::new(10.5, 7.25),
            Vec2::new(63.0, 0.5),
            Vec2::new(32.0, 24.0),
        ] {
            let ray = cam.ray(film);
            let p = cam.project(ray.at(3.0)).unwrap();
            assert!((p.film - film).length() < 1e-3, "{film} → {}", p.film);
            assert!((p.to_camera + ray.direction).length() < 1e-5);
            assert!((p.distance - 3.0).abs() < 1e-5);
        }
        // ∫ W dω over one pixel is 1: midpoint rule over 16² sub-cells,
        // each of solid angle ≈ A_cell·cos³θ (plane at distance 1).
        let pixel = Vec2::new(5.0, 40.0);
        let mut integral = 0.0;
        for i in 0..16 {
            for j in 0..16 {
                let f = pixel + (Vec2::new(i as f32, j as f32) + 0.5) / 16.0;
                let r = cam.ray(f);
                let w = cam.project(r.at(1.0)).unwrap().importance;
                let cos = r.direction.dot(cam.forward);
                let cell = 4.0 * cam.half_extent.x * cam.half_extent.y / (64.0 * 48.0) / 256.0;
                integral += w * cell * cos * cos * cos;
            }
        }
        assert!((integral - 1.0).abs() < 1e-3, "{integral}");
        assert!(cam.project(Vec3::new(0.3, 1.0, 6.0)).is_none(), "behind");
    }
}
