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
    /// The visible face of a lamp whose light is sampled as a delta light
    /// elsewhere (the paper's legacy spotlight: an emissive quad with a
    /// cutoff `c`, whose light is a [`crate::lights::SpotLight`] at its
    /// centroid). Camera rays, and paths that reach it only through
    /// specular events, see radiance `radiance` on its front; light
    /// scattered by fog or diffuse surfaces does not count it, because
    /// the spot already carries the lamp's emission — a lamp housing
    /// visible to camera rays only, as Cycles' per-light ray visibility
    /// does. Opaque like an emitter.
    LampFace { radiance: Rgb },
    /// Thin coloured glass: tints rays crossing it, never stops them.
    Glass(Glass),
    /// A smooth refractive interface (solid glass, water) of index of
    /// refraction `ior` relative to the outside (the side its normal
    /// faces). Light reflects or refracts by the Fresnel equations.
    /// Shadow rays cannot follow refraction, so for next event estimation
    /// a dielectric is opaque: light focused through it (caustics) is only
    /// found by paths that happen to reach an emitter.
    Dielectric { ior: f32 },
}

/// Fresnel reflectance of a smooth dielectric interface for unpolarised
/// light arriving at `cos_i` (> 0) to the normal, with `eta` = n_incident
/// / n_transmitted; 1 under total internal reflection.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_parallel = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_perpendicular = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (r_parallel * r_parallel + r_perpendicular * r_perpendicular)
}

/// The next direction of a ray travelling along `incoming` that meets a
/// dielectric of index `ior` with geometric normal `normal` (either side):
/// the reflected or the refracted direction, chosen with probability the
/// Fresnel reflectance by `u`, so the path's weight is unchanged (the
/// interface neither absorbs nor emits).
pub fn dielectric_scatter(incoming: Vec3, normal: Vec3, ior: f32, u: f32) -> Vec3 {
    let entering = incoming.dot(normal) < 0.0;
    let (n, eta) = if entering {
        (normal, 1.0 / ior)
    } else {
        (-normal, ior)
    };
    let cos_i = -incoming.dot(n);
    let reflectance = fresnel_dielectric(cos_i, eta);
    if u < reflectance {
        return incoming + 2.0 * cos_i * n;
    }
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    (incoming * eta + n * (eta * cos_i - cos_t)).normalize()
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

    /// Normal incidence: R = ((n − 1)/(n + 1))² = 0.04 for n = 1.5; total
    /// internal reflection beyond the critical angle asin(1/1.5) = 41.8°.
    #[test]
    fn fresnel_values() {
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!(fresnel_dielectric(40f32.to_radians().cos(), 1.5) < 1.0);
        assert_eq!(fresnel_dielectric(43f32.to_radians().cos(), 1.5), 1.0);
        assert!((fresnel_dielectric(1e-4, 1.0 / 1.5) - 1.0).abs() < 1e-2);
    }

    /// Refraction obeys Snell's law: n₁ sin θ₁ = n₂ sin θ₂.
    #[test]
    fn refraction_obeys_snell() {
        let incoming = Vec3::new(0.5, -1.0, 0.0).normalize();
        // u = 1 never reflects (R < 1 here).
        let out = dielectric_scatter(incoming, Vec3::Y, 1.5, 1.0);
        let sin_in = incoming.x.abs();
        let sin_out = out.x.abs();
        assert!(out.y < 0.0 && (sin_in - 1.5 * sin_out).abs() < 1e-5);
        // Light paths are reversible: sent back, it leaves along −incoming.
        let back = dielectric_scatter(-out, Vec3::Y, 1.5, 1.0);
        assert!(
            (back + incoming).length() < 1e-5,
            "reversible: {back} vs {}",
            -incoming
        );
    }

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
