//! The perspective camera: a pinhole, or a thin lens for depth of field.

use crate::footprint::RayCone;
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::sampling::concentric_disk;
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

/// What light passes through on its way to the film.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Aperture {
    /// A pinhole at the camera's position: everything is in focus.
    #[default]
    Pinhole,
    /// An ideal thin lens (pbrt-v4 §5.2.3; Kolb et al., "A Realistic
    /// Camera Model for Computer Graphics", 1995): a disk of `radius`
    /// (scene units) centred on the camera's position, facing along the
    /// view direction, focused on the plane `focus_distance` (scene
    /// units) in front of it. A point at depth z (along the view
    /// direction) is imaged as a disk of diameter `2·radius·|z −
    /// focus_distance|/z` measured on the plane of focus, the circle of
    /// confusion. The field of view is the pinhole's through the lens's
    /// centre. A real lens of focal length F at f-number N has `radius =
    /// F/(2N)`.
    ThinLens { radius: f32, focus_distance: f32 },
}

impl Aperture {
    /// Checks a thin lens's numbers: a radius > 0 and a focus distance >
    /// 0, both finite.
    pub fn check(&self) -> Result<(), String> {
        match *self {
            Self::Pinhole => Ok(()),
            Self::ThinLens {
                radius,
                focus_distance,
            } => {
                if !(radius > 0.0 && radius.is_finite()) {
                    return Err(format!(
                        "the lens's aperture radius must be finite and > 0 (it is {radius})"
                    ));
                }
                if !(focus_distance > 0.0 && focus_distance.is_finite()) {
                    return Err(format!(
                        "the lens's focus distance must be finite and > 0 (it is {focus_distance})"
                    ));
                }
                Ok(())
            }
        }
    }
}

/// Where the camera is and how it looks, independent of image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSpec {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    pub fov: FieldOfView,
    pub aperture: Aperture,
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
            aperture: Aperture::Pinhole,
        }
    }

    /// Checks that a camera can be built: distinct position and target, an
    /// up vector not parallel to the view direction, a valid aperture.
    pub fn check(&self) -> Result<(), String> {
        let spec = self;
        spec.aperture.check()?;
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

/// A camera for one image size. Forward `f = normalize(look_at −
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
    aperture: Aperture,
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
            aperture: spec.aperture,
        }
    }

    /// Whether rays start at a point of a lens, so [`Self::ray`] and
    /// [`Self::project`] use their `lens` sample (a pinhole ignores it).
    #[inline]
    pub fn has_lens(&self) -> bool {
        self.aperture != Aperture::Pinhole
    }

    /// The lens sample for [`Self::ray`] or [`Self::project`]: two numbers
    /// of `sampler` through a lens, none for a pinhole (so pinhole images
    /// keep their samples).
    #[inline]
    pub fn lens_sample(&self, sampler: &mut PixelSampler) -> Vec2 {
        if self.has_lens() {
            sampler.next_2d()
        } else {
            Vec2::ZERO
        }
    }

    /// The point of the lens that `u ∈ [0, 1)²` picks, uniformly over the
    /// lens's area (the camera's position for a pinhole).
    #[inline]
    fn lens_point(&self, u: Vec2) -> Vec3 {
        match self.aperture {
            Aperture::Pinhole => self.position,
            Aperture::ThinLens { radius, .. } => {
                let p = radius * concentric_disk(u);
                self.position + self.right * p.x + self.up * p.y
            }
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
    /// optical axis, times `scale`. Behind a thin lens this is the
    /// footprint in focus; out of focus the lens samples blur more than
    /// it, so textures are filtered as sharp as at focus, never blurrier.
    #[inline]
    pub fn cone(&self, direction: Vec3, scale: f32) -> RayCone {
        let pixel = 2.0 * self.half_extent.y / self.resolution.y;
        RayCone {
            width: 0.0,
            spread: pixel * direction.dot(self.forward).max(0.0) * scale,
        }
    }

    /// The ray through the film position `pixel` (in pixels: x to the
    /// right, y down, pixel (i, j) covers `[i, i+1) × [j, j+1)`) and the
    /// lens point `lens ∈ [0, 1)²` picks. Through a thin lens it runs from
    /// that point to where the pinhole ray of `pixel` meets the plane of
    /// focus (pbrt-v4's `PerspectiveCamera::GenerateRay`).
    #[inline]
    pub fn ray(&self, pixel: Vec2, lens: Vec2) -> Ray {
        let ndc = 2.0 * pixel / self.resolution - Vec2::ONE;
        // The pinhole direction, of unit length along `forward`.
        let dir = self.forward + self.right * (ndc.x * self.half_extent.x)
            - self.up * (ndc.y * self.half_extent.y);
        match self.aperture {
            Aperture::Pinhole => Ray::new(self.position, dir),
            Aperture::ThinLens { focus_distance, .. } => {
                let origin = self.lens_point(lens);
                let focus = self.position + dir * focus_distance;
                Ray::new(origin, focus - origin)
            }
        }
    }
}

/// Where a scene point appears on the film, for light paths connected to
/// the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// Film position in pixels (as [`Camera::ray`] takes it).
    pub film: Vec2,
    /// Unit direction from the point to the camera (to the lens point).
    pub to_camera: Vec3,
    pub distance: f32,
    /// The camera's importance `W = 1/(A_pixel·cos³θ)` per unit solid
    /// angle at the camera, θ off the optical axis, `A_pixel` a pixel's
    /// area on the image plane at distance 1. Our pixels average radiance
    /// uniformly over their area on that plane, and a solid angle dω
    /// there covers `dω/cos³θ` of it, so `∫_pixel W·L dω` is the pixel's
    /// value: the light tracer's measurement matches the camera's.
    ///
    /// Through a thin lens the same `W` holds per unit solid angle at the
    /// lens point, for a lens point drawn uniformly: a solid angle dω
    /// there covers `dω·F²/cos³θ` of the plane of focus at distance F,
    /// which is `dω/cos³θ` of the image plane at distance 1, and the
    /// lens's area cancels between the camera's uniform choice of lens
    /// point (its measurement's `1/A_lens`) and the connection's (pdf
    /// `1/A_lens`), as do the lens's cosine and the geometry term's.
    pub importance: f32,
}

impl Camera {
    /// The projection of `x` through the lens point `lens ∈ [0, 1)²`
    /// picks (ignored by a pinhole), or `None` if `x` is behind the lens
    /// or images outside the film. Through a thin lens the film position
    /// is the pinhole image of the point where the line from the lens
    /// point through `x` meets the plane of focus: the camera ray of
    /// that film position and lens point passes through `x`.
    pub fn project(&self, x: Vec3, lens: Vec2) -> Option<Projection> {
        let origin = self.lens_point(lens);
        let d = x - origin;
        let distance = d.length();
        let z = d.dot(self.forward);
        if !(z > 0.0 && distance > 0.0) {
            return None;
        }
        let on_plane = match self.aperture {
            Aperture::Pinhole => d,
            Aperture::ThinLens { focus_distance, .. } => {
                origin + d * (focus_distance / z) - self.position
            }
        };
        let plane =
            Vec2::new(on_plane.dot(self.right), on_plane.dot(self.up)) / on_plane.dot(self.forward);
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
            aperture: Aperture::Pinhole,
        };
        let cam = Camera::new(&spec, 320, 240);
        let c = cam.ray(Vec2::new(160.0, 120.0), Vec2::ZERO);
        assert!((c.direction - (-Vec3::Z)).length() < 1e-6);
        let top = cam.ray(Vec2::new(160.0, 0.0), Vec2::ZERO);
        let angle = top.direction.dot(-Vec3::Z).acos().to_degrees();
        assert!(top.direction.y > 0.0 && (angle - 20.0).abs() < 1e-3);
        let right = cam.ray(Vec2::new(320.0, 120.0), Vec2::ZERO);
        assert!(right.direction.x > 0.0);
    }

    #[test]
    fn projection_inverts_rays_and_importance_integrates_to_one() {
        let spec = CameraSpec {
            position: Vec3::new(0.3, 1.0, 5.0),
            look_at: Vec3::new(0.0, 0.8, 0.0),
            up: Vec3::Y,
            fov: FieldOfView::Vertical(50.0),
            aperture: Aperture::Pinhole,
        };
        let cam = Camera::new(&spec, 64, 48);
        for film in [
            Vec2::new(10.5, 7.25),
            Vec2::new(63.0, 0.5),
            Vec2::new(32.0, 24.0),
        ] {
            let ray = cam.ray(film, Vec2::ZERO);
            let p = cam.project(ray.at(3.0), Vec2::ZERO).unwrap();
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
                let r = cam.ray(f, Vec2::ZERO);
                let w = cam.project(r.at(1.0), Vec2::ZERO).unwrap().importance;
                let cos = r.direction.dot(cam.forward);
                let cell = 4.0 * cam.half_extent.x * cam.half_extent.y / (64.0 * 48.0) / 256.0;
                integral += w * cell * cos * cos * cos;
            }
        }
        assert!((integral - 1.0).abs() < 1e-3, "{integral}");
        assert!(
            cam.project(Vec3::new(0.3, 1.0, 6.0), Vec2::ZERO).is_none(),
            "behind"
        );
    }

    /// Through a thin lens, `project` inverts `ray` for every lens point;
    /// a point on the plane of focus images to one film position whatever
    /// the lens point; a point at depth z spreads over the circle of
    /// confusion, diameter `2·radius·|z − F|/z` on the plane of focus
    /// (similar triangles), here measured in pixels across the lens.
    #[test]
    fn thin_lens_rays_meet_at_focus_and_blur_by_the_circle_of_confusion() {
        let (radius, focus) = (0.1f32, 4.0f32);
        let spec = CameraSpec {
            position: Vec3::new(0.0, 1.0, 5.0),
            look_at: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::Y,
            fov: FieldOfView::Vertical(40.0),
            aperture: Aperture::ThinLens {
                radius,
                focus_distance: focus,
            },
        };
        let cam = Camera::new(&spec, 200, 100);
        let lens_points = [
            Vec2::new(0.5, 0.5),
            Vec2::new(0.1, 0.9),
            Vec2::new(0.95, 0.2),
            Vec2::new(0.0, 0.5),
        ];
        for film in [Vec2::new(100.0, 50.0), Vec2::new(13.5, 80.25)] {
            for lens in lens_points {
                let ray = cam.ray(film, lens);
                assert!(ray.origin.distance(Vec3::new(0.0, 1.0, 5.0)) <= radius * 1.0001);
                for t in [2.5, 7.0] {
                    let p = cam.project(ray.at(t), lens).unwrap();
                    assert!(
                        (p.film - film).length() < 2e-3,
                        "{film} {lens} → {}",
                        p.film
                    );
                    assert!((p.distance - t).abs() < 1e-4);
                    assert!((p.to_camera + ray.direction).length() < 1e-5);
                }
            }
        }
        let in_focus = Vec3::new(0.3, 1.2, 5.0 - focus);
        let sharp = cam.project(in_focus, lens_points[0]).unwrap().film;
        for lens in lens_points {
            assert!((cam.project(in_focus, lens).unwrap().film - sharp).length() < 1e-3);
        }
        // Lens points at the left and right rim, (0, ½) and (1, ½), image
        // a point at depth z = 2 a circle-of-confusion diameter apart.
        let z = 2.0;
        let x = Vec3::new(0.0, 1.0, 5.0 - z);
        let left = cam.project(x, Vec2::new(0.0, 0.5)).unwrap().film;
        let right = cam.project(x, Vec2::new(1.0, 0.5)).unwrap().film;
        let pixel_on_focus_plane = 2.0 * focus * 20f32.to_radians().tan() / 100.0;
        let expected = 2.0 * radius * (z - focus).abs() / z / pixel_on_focus_plane;
        let measured = (right - left).length();
        assert!(
            (measured - expected).abs() < 1e-3 * expected,
            "{measured} vs {expected}"
        );
        assert!(
            Aperture::ThinLens {
                radius: 0.0,
                focus_distance: 1.0
            }
            .check()
            .is_err()
        );
    }
}
