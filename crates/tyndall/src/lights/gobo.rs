//! Projected patterns: a gobo in a spot (stage lighting's etched metal or
//! glass disc in the beam) or a projector's slide. The light leaving the
//! spot along ω is filtered by the image's colour where ω meets the image
//! plane, as pbrt-v4's projection light and Mitsuba's projector filter
//! theirs.
//!
//! The image lies on the plane at distance 1 along the spot's axis,
//! filling the square circumscribing the cone there (side `2·tan θc`):
//! the cone's disc is inscribed in it, as a gobo's round aperture is. Its
//! up edge points along the world's +Y made perpendicular to the axis
//! (world −Z for an axis within 25° of ±Y, so a spot pointing down at a
//! floor projects its image's top away from +Z), right along axis × up,
//! seen looking along the beam; `rotate_deg` turns it counter-clockwise
//! about the axis as seen so.

use crate::color::Rgb;
use crate::texture::Texture;
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// Widest cone a gobo may fill: beyond it the image plane's square grows
/// without bound (tan θc → ∞ at 90°).
pub const MAX_GOBO_CUTOFF_DEG: f32 = 80.0;

/// An image projected along a spot's cone (see the module's
/// documentation for its placement).
#[derive(Clone, Debug, PartialEq)]
pub struct Gobo {
    pub image: Arc<Texture>,
    axis: Vec3,
    right: Vec3,
    up: Vec3,
    /// `tan θc`: half the image's side on the plane at distance 1.
    half_side: f32,
}

impl Gobo {
    /// The image along the unit `axis` filling the cone of cutoff
    /// `cutoff_deg` ≤ [`MAX_GOBO_CUTOFF_DEG`], turned `rotate_deg`.
    pub fn new(
        image: Arc<Texture>,
        axis: Vec3,
        cutoff_deg: f32,
        rotate_deg: f32,
    ) -> Result<Self, String> {
        if !(cutoff_deg > 0.0 && cutoff_deg <= MAX_GOBO_CUTOFF_DEG) {
            return Err(format!(
                "a gobo needs a cone of at most {MAX_GOBO_CUTOFF_DEG}° (its image fills the cone's \
                 square at unit distance, which grows without bound towards 90°), not {cutoff_deg}°"
            ));
        }
        let axis = axis.normalize();
        let reference = if axis.y.abs() > 0.9 {
            -Vec3::Z
        } else {
            Vec3::Y
        };
        let up0 = (reference - reference.dot(axis) * axis).normalize();
        let right0 = axis.cross(up0);
        let (s, c) = rotate_deg.to_radians().sin_cos();
        // Counter-clockwise seen along the beam: up turns towards −right.
        let up = up0 * c - right0 * s;
        Ok(Self {
            image,
            axis,
            right: axis.cross(up),
            up,
            half_side: cutoff_deg.to_radians().tan(),
        })
    }

    /// The image coordinates (u right, v down, in [0, 1]² on the image)
    /// that the unit direction `emitted` meets, or `None` behind the
    /// plane.
    #[inline]
    pub fn uv(&self, emitted: Vec3) -> Option<Vec2> {
        let along = emitted.dot(self.axis);
        if along <= 0.0 {
            return None;
        }
        let p = Vec2::new(emitted.dot(self.right), emitted.dot(self.up)) / (along * self.half_side);
        Some(Vec2::new(0.5 + 0.5 * p.x, 0.5 - 0.5 * p.y))
    }

    /// The filter colour along the unit direction `emitted`: the image's
    /// linear colour there, black off the image.
    #[inline]
    pub fn colour(&self, emitted: Vec3) -> Rgb {
        match self.uv(emitted) {
            Some(uv) if (0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y) => {
                self.image.lookup(uv)
            }
            _ => Rgb::ZERO,
        }
    }
}
