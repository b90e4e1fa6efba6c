//! Surface materials.
//!
//! The set is closed and small, so it is an enum: the integrators `match`
//! on it. Glass is thin coloured glass (the paper's §3.3), see [`crate::glass`].

use crate::color::Rgb;
use crate::glass::Glass;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Index of a material in [`crate::scene::Scene::materials`].
pub type MaterialId = u32;

/// What a surface does to light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Material {
    /// An opaque surface: Lambertian diffuse plus a reflective layer.
    Opaque(Surface),
    /// An emitter of constant radiance `radiance` (W·sr⁻¹·m⁻²) from its
    /// front face (both faces if `two_sided`). Emitters are opaque.
    Emissive { radiance: Rgb, two_sided: bool },
    /// Thin coloured glass: tints rays crossing it, never stops them.
    Glass(Glass),
}

/// Lambertian diffuse reflectance `diffuse` (BRDF `diffuse/π`) plus a
/// specular layer of reflectance `specular`: a perfect mirror when
/// `roughness` is 0, otherwise a glossy lobe around the mirror direction.
///
/// The reflective layer is followed by tracing one reflected ray (the
/// course code base's model, which the paper's scenes use); it reflects
/// what that ray sees (emitters, lit surfaces, fog) but not delta lights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    pub diffuse: Rgb,
    pub specular: Rgb,
    pub roughness: f32,
}

impl Surface {
    /// A purely diffuse surface.
    pub fn diffuse(reflectance: Rgb) -> Self {
        Self {
            diffuse: reflectance,
            specular: Rgb::ZERO,
            roughness: 0.0,
        }
    }

    /// Lambert BRDF value `ρ/π` (sr⁻¹).
    #[inline]
    pub fn diffuse_brdf(&self) -> Rgb {
        self.diffuse / PI
    }

    pub fn has_specular(&self) -> bool {
        self.specular.max_element() > 0.0
    }

    /// Direction of the reflected ray for a ray travelling along
    /// `incoming`, at a surface with unit normal `normal` facing the
    /// incoming ray. With roughness `r > 0` the direction is drawn from a
    /// normalised Phong lobe `cosⁿ` around the mirror direction, with
    /// `n = 2/r² − 2` (the Beckmann-equivalent exponent, Walter et al.
    /// 2007). Returns `None` when the drawn direction lies below the
    /// surface (that sample carries no light).
    pub fn reflect(&self, incoming: Vec3, normal: Vec3, u: Vec2) -> Option<Vec3> {
        let mirror = incoming - 2.0 * incoming.dot(normal) * normal;
        if self.roughness <= 0.0 {
            return Some(mirror);
        }
        let r2 = (self.roughness * self.roughness).max(1e-6);
        let exponent = (2.0 / r2 - 2.0).max(0.0);
        let cos_t = u.x.powf(1.0 / (exponent + 1.0));
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let (t, b) = mirror.any_orthonormal_pair();
        let dir = (t * (sin_t * phi.cos()) + b * (sin_t * phi.sin()) + mirror * cos_t).normalize();
        (dir.dot(normal) > 0.0).then_some(dir)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirror_reflects_about_normal() {
        let s = Surface {
            diffuse: Rgb::ZERO,
            specular: Rgb::ONE,
            roughness: 0.0,
        };
        let d = Vec3::new(1.0, -1.0, 0.0).normalize();
        let r = s.reflect(d, Vec3::Y, Vec2::ZERO).unwrap();
        assert!((r - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn rough_reflection_stays_near_mirror() {
        let s = Surface {
            diffuse: Rgb::ZERO,
            specular: Rgb::ONE,
            roughness: 0.05,
        };
        let mirror = Vec3::Y;
        for i in 0..64 {
            let u = Vec2::new((i as f32 + 0.5) / 64.0, (i * 37 % 64) as f32 / 64.0);
            let r = s.reflect(-Vec3::Y, Vec3::Y, u).unwrap();
            assert!(r.dot(mirror) > 0.9);
        }
    }
}
