//! Moving the view: an orbit camera (drag rotates the eye around
//! `look_at`, the wheel moves it nearer or farther) and fly keys (the eye
//! and its target move together).

use glam::Quat;
use tyndall::camera::CameraSpec;

/// Radians of orbit per pixel of mouse drag.
const ORBIT_PER_PIXEL: f32 = 0.005;
/// How close (radians) the view may come to the up axis: the camera's
/// frame is undefined when looking straight along `up`.
const POLE_MARGIN: f32 = 0.02;
/// Distance factor per wheel notch (towards `look_at` for positive notches).
const ZOOM_PER_NOTCH: f32 = 0.9;
/// A fly key moves the eye by this fraction of its distance to `look_at`.
const FLY_FRACTION: f32 = 0.05;

/// Rotates the eye around `look_at`: `dx` pixels about `up` (yaw), `dy`
/// pixels about the camera's right axis (pitch), stopping short of the poles.
pub fn orbit(camera: &mut CameraSpec, dx: f32, dy: f32) {
    let up = camera.up.normalize();
    let offset = camera.position - camera.look_at;
    let yawed = Quat::from_axis_angle(up, -dx * ORBIT_PER_PIXEL) * offset;
    let polar = yawed.normalize().dot(up).clamp(-1.0, 1.0).acos();
    let pitch = (-dy * ORBIT_PER_PIXEL).clamp(
        POLE_MARGIN - polar,
        std::f32::consts::PI - POLE_MARGIN - polar,
    );
    let right = up.cross(yawed);
    let rotated = if right.length_squared() > 0.0 {
        Quat::from_axis_angle(right.normalize(), -pitch) * yawed
    } else {
        yawed
    };
    camera.position = camera.look_at + rotated;
}

/// Moves the eye towards `look_at` (positive `notches`) or away.
pub fn zoom(camera: &mut CameraSpec, notches: f32) {
    let offset = camera.position - camera.look_at;
    let distance = offset.length();
    let new_distance = (distance * ZOOM_PER_NOTCH.powf(notches)).max(1e-3);
    camera.position = camera.look_at + offset * (new_distance / distance);
}

/// A fly direction in the camera's frame: `forward`, `right`, `up` in
/// {−1, 0, 1}.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fly {
    pub forward: f32,
    pub right: f32,
    pub up: f32,
}

/// Moves eye and target together by `FLY_FRACTION` of their distance.
pub fn fly(camera: &mut CameraSpec, step: Fly) {
    let offset = camera.look_at - camera.position;
    let distance = offset.length();
    let forward = offset / distance;
    let right = forward.cross(camera.up).normalize();
    let up = right.cross(forward);
    let delta =
        (forward * step.forward + right * step.right + up * step.up) * distance * FLY_FRACTION;
    camera.position += delta;
    camera.look_at += delta;
}

/// Whether a camera can be built from `camera` (see [`CameraSpec::check`]).
pub fn is_valid(camera: &CameraSpec) -> bool {
    camera.check().is_ok() && camera.position.is_finite() && camera.look_at.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use tyndall::camera::{Aperture, FieldOfView};

    fn camera() -> CameraSpec {
        CameraSpec {
            position: Vec3::new(0.0, 1.0, 5.0),
            look_at: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::Y,
            fov: FieldOfView::Vertical(40.0),
            aperture: Aperture::Pinhole,
        }
    }

    #[test]
    fn orbit_keeps_the_distance_and_target() {
        let mut c = camera();
        orbit(&mut c, 120.0, -45.0);
        assert!(((c.position - c.look_at).length() - 5.0).abs() < 1e-4);
        assert_eq!(c.look_at, Vec3::new(0.0, 1.0, 0.0));
        assert!(c.position.distance(camera().position) > 0.1);
    }

    #[test]
    fn orbit_stops_short_of_the_pole() {
        let mut c = camera();
        for _ in 0..100 {
            orbit(&mut c, 0.0, 1000.0);
        }
        assert!(is_valid(&c), "{c:?}");
        let polar = (c.position - c.look_at).normalize().dot(Vec3::Y).acos();
        assert!(polar >= POLE_MARGIN * 0.99, "{polar}");
    }

    #[test]
    fn zoom_and_fly() {
        let mut c = camera();
        zoom(&mut c, 1.0);
        assert!(((c.position - c.look_at).length() - 4.5).abs() < 1e-4);
        let before = c;
        fly(
            &mut c,
            Fly {
                forward: 1.0,
                right: 0.0,
                up: 0.0,
            },
        );
        assert!((c.position.z - (before.position.z - 4.5 * FLY_FRACTION)).abs() < 1e-4);
        assert_eq!(c.look_at - c.position, before.look_at - before.position);
    }
}
