//! Surface materials.
//!
//! The set is closed and small, so it is an enum: the integrators `match`
//! on it to follow a path through glass and dielectrics, and an opaque
//! [`Surface`] answers for its own scattering ([`Surface::sample`],
//! [`Surface::eval`], [`Surface::pdf`]). Glass is thin coloured glass (the paper's §3.3), see [`crate::glass`].

use crate::color::{Rgb, luminance};
use crate::glass::Glass;
use crate::sampling::cosine_hemisphere;
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// Index of a material in [`crate::scene::Scene::materials`].
pub type MaterialId = u32;

/// What a surface does to light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Material {
    /// An opaque surface: Lambertian diffuse plus a reflective layer.
    Opaque(Surface),
    /// An emitter of radiance `radiance` (W·sr⁻¹·m⁻²) from its front face
    /// (both faces if `two_sided`), constant unless an emission map
    /// ([`crate::description::EmissionMap`]) scales it point by point.
    /// Emitters are opaque. The emission adds to the light `surface`
    /// reflects (glTF 2.0 Appendix B: "the emissive term is added to the
    /// BRDF's"; Cycles' Principled BSDF with emission); a pure emitter's
    /// surface is [`Surface::BLACK`] ([`Material::emitter`]).
    Emissive {
        radiance: Rgb,
        two_sided: bool,
        surface: Surface,
    },
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
    /// found by paths that happen to reach an emitter. Its inside absorbs
    /// `absorption` σa per scene unit and channel (Beer–Lambert, a
    /// homogeneous absorbing medium: glTF's `KHR_materials_volume`); zero
    /// is clear.
    Dielectric { ior: f32, absorption: Rgb },
}

/// A solid dielectric's surface as a path meets it: its index of
/// refraction `ior` relative to the side its normal faces, and the
/// absorption σa (per scene unit and channel) inside it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interface {
    pub ior: f32,
    pub absorption: Rgb,
}

/// What a ray does where it meets a material: the material's answer, so
/// that integrators act on it without naming the material's kind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceEvent {
    /// An emitter. `emitted` is the radiance leaving towards the ray,
    /// `None` from the dark back of a one-sided emitter; `lamp` marks a
    /// lamp face ([`Material::LampFace`]), which only paths without a
    /// scattering event count. The path ends there unless the emitter
    /// also `reflects` by an opaque surface's lobes.
    Emitter {
        emitted: Option<Rgb>,
        lamp: bool,
        reflects: Option<Surface>,
    },
    /// A thin pane the ray crosses, multiplied by `transmittance` per
    /// crossing (the filter model, the paper's eq. 6 from white).
    Pane { transmittance: Rgb },
    /// A smooth interface where the ray refracts or reflects.
    Interface(Interface),
    /// An opaque surface that reflects by its lobes.
    Reflector(Surface),
}

impl SurfaceEvent {
    /// The event for a path that gathers no emission (light paths, the
    /// guides): an emitter that also reflects is its surface.
    #[inline]
    pub fn without_emission(self) -> Self {
        match self {
            SurfaceEvent::Emitter {
                reflects: Some(surface),
                ..
            } => SurfaceEvent::Reflector(surface),
            event => event,
        }
    }
}

impl Material {
    /// An emitter that reflects nothing (see [`Material::Emissive`]).
    pub fn emitter(radiance: Rgb, two_sided: bool) -> Self {
        Material::Emissive {
            radiance,
            two_sided,
            surface: Surface::BLACK,
        }
    }

    /// The event of a ray arriving on the `front` (normal) side or the
    /// back. With `glass_is_opaque`, thin glass is an opaque diffuse
    /// surface of its colour, as the paper drew it for camera rays.
    #[inline]
    pub fn event(&self, front: bool, glass_is_opaque: bool) -> SurfaceEvent {
        match *self {
            Material::Emissive {
                radiance,
                two_sided,
                surface,
            } => SurfaceEvent::Emitter {
                emitted: (front || two_sided).then_some(radiance),
                lamp: false,
                reflects: surface.reflects().then_some(surface),
            },
            Material::LampFace { radiance } => SurfaceEvent::Emitter {
                emitted: front.then_some(radiance),
                lamp: true,
                reflects: None,
            },
            Material::Glass(glass) if glass_is_opaque => {
                SurfaceEvent::Reflector(Surface::diffuse(glass.color))
            }
            Material::Glass(glass) => SurfaceEvent::Pane {
                transmittance: glass.filter_transmittance(),
            },
            Material::Dielectric { ior, absorption } => {
                SurfaceEvent::Interface(Interface { ior, absorption })
            }
            Material::Opaque(surface) => SurfaceEvent::Reflector(surface),
        }
    }

    /// Whether the material refracts (a dielectric): light focused through
    /// it makes caustics that only light paths find.
    #[inline]
    pub fn refracts(&self) -> bool {
        matches!(self, Material::Dielectric { .. })
    }
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

/// The Fresnel reflectance met by a ray travelling along `incoming` at a
/// dielectric of index `ior` with geometric normal `normal` (either side).
pub fn dielectric_reflectance(incoming: Vec3, normal: Vec3, ior: f32) -> f32 {
    let (n, eta) = dielectric_sides(incoming, normal, ior);
    fresnel_dielectric(-incoming.dot(n), eta)
}

/// The normal facing `incoming` at a dielectric of index `ior` with
/// geometric normal `normal`, and the ratio n_incident / n_transmitted.
fn dielectric_sides(incoming: Vec3, normal: Vec3, ior: f32) -> (Vec3, f32) {
    if incoming.dot(normal) < 0.0 {
        (normal, 1.0 / ior)
    } else {
        (-normal, ior)
    }
}

/// The next direction of a ray travelling along `incoming` that meets a
/// dielectric of index `ior` with geometric normal `normal` (either side):
/// the reflected or the refracted direction, chosen with probability the
/// Fresnel reflectance by `u`, so the path's weight is unchanged (the
/// interface neither absorbs nor emits).
pub fn dielectric_scatter(incoming: Vec3, normal: Vec3, ior: f32, u: f32) -> Vec3 {
    let (n, eta) = dielectric_sides(incoming, normal, ior);
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
    /// A surface that reflects nothing.
    pub const BLACK: Self = Self {
        diffuse: Rgb::ZERO,
        specular: Rgb::ZERO,
        roughness: 0.0,
    };

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

    /// Whether the surface reflects any light (by either lobe).
    pub fn reflects(&self) -> bool {
        self.diffuse.max_element() > 0.0 || self.has_specular()
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

/// glTF's metallic-roughness material (glTF 2.0 §3.9.2 and Appendix B)
/// as a [`Surface`]: base colour `base`, metalness `metallic` and
/// perceptual `roughness` (each in `[0, 1]`), and the dielectric's
/// normal-incidence reflectance `f0` (`((ior − 1)/(ior + 1))²` times
/// `KHR_materials_specular`'s factors). Its surface is the glTF BRDF's
/// mix at normal incidence: diffuse `base·(1 − m)·(1 − max f0)`,
/// specular `base·m + f0·(1 − m)`, and the lobe's roughness `roughness²`
/// (glTF's α). Evaluated once per material, or at each point where
/// textures vary its parameters (`metallicRoughnessTexture`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetallicRoughness {
    pub base: Rgb,
    pub metallic: f32,
    pub roughness: f32,
    pub f0: Rgb,
}

impl MetallicRoughness {
    /// A dielectric's reflectance at normal incidence from its index of
    /// refraction `ior`: `((ior − 1)/(ior + 1))²` (0.04 for 1.5, glTF's
    /// default).
    #[inline]
    pub fn dielectric_f0(ior: f32) -> f32 {
        ((ior - 1.0) / (ior + 1.0)).powi(2)
    }

    /// The surface these parameters make (purely diffuse where nothing
    /// is specular).
    #[inline]
    pub fn surface(&self) -> Surface {
        let m = self.metallic;
        let diffuse = self.base * ((1.0 - m) * (1.0 - self.f0.max_element()));
        let specular = self.base * m + self.f0 * (1.0 - m);
        if specular == Rgb::ZERO {
            return Surface::diffuse(diffuse);
        }
        Surface {
            diffuse,
            specular,
            roughness: self.roughness * self.roughness,
        }
    }
}

/// The lobe of a [`Surface`] a sampled direction came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lobe {
    /// The Lambertian lobe, cosine-sampled: its direction can also be
    /// reached by light sampling, so its density takes part in MIS.
    Diffuse,
    /// The reflective layer (mirror or glossy), followed by its one
    /// reflected ray: no other strategy produces it.
    Specular,
}

/// A direction drawn by [`Surface::sample`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceSample {
    /// Unit direction of the continuing ray.
    pub direction: Vec3,
    /// `f·cos θ / p` with the lobe's choice probability in `p`: `ρ/P_d`
    /// for the Lambertian lobe, `specular/(1 − P_d)` for the reflective
    /// layer (whose lobe is sampled exactly).
    pub weight: Rgb,
    /// Solid-angle density of the direction for the Lambertian lobe,
    /// `P_d·cos θ/π` ([`Surface::pdf`]); not meaningful for the
    /// reflective layer.
    pub pdf: f32,
    pub lobe: Lobe,
}

impl Surface {
    /// The probability `P_d` of continuing a path by the Lambertian lobe
    /// rather than the reflective layer: proportional to the luminance of
    /// each lobe's reflectance. `None` if the surface reflects nothing.
    #[inline]
    pub fn diffuse_probability(&self) -> Option<f32> {
        let (diffuse, specular) = (luminance(self.diffuse), luminance(self.specular));
        if diffuse + specular <= 0.0 {
            return None;
        }
        Some(diffuse / (diffuse + specular))
    }

    /// Continues a path that arrived along `incoming` at a point with unit
    /// normal `normal` (facing the path): the lobe is chosen by `choice`
    /// with probability [`Surface::diffuse_probability`], the direction
    /// from `u` (cosine-distributed, or by [`Surface::reflect`]). `None`
    /// if the surface reflects nothing or the reflected direction falls
    /// below it.
    #[inline]
    pub fn sample(
        &self,
        incoming: Vec3,
        normal: Vec3,
        choice: f32,
        u: Vec2,
    ) -> Option<SurfaceSample> {
        let p_diffuse = self.diffuse_probability()?;
        if choice < p_diffuse {
            let direction = cosine_hemisphere(normal, u);
            // f·cos/pdf = (ρ/π)·cos / (P_d·cos/π) = ρ/P_d.
            Some(SurfaceSample {
                direction,
                weight: self.diffuse / p_diffuse,
                pdf: p_diffuse * normal.dot(direction).max(0.0) * FRAC_1_PI,
                lobe: Lobe::Diffuse,
            })
        } else {
            let direction = self.reflect(incoming, normal, u)?;
            Some(SurfaceSample {
                direction,
                weight: self.specular / (1.0 - p_diffuse),
                pdf: 0.0,
                lobe: Lobe::Specular,
            })
        }
    }

    /// The Lambertian lobe's `f·cos θ` for light leaving along unit
    /// `omega` at a point with unit normal `normal` (the cosine included,
    /// as Mitsuba 3's `BSDF::eval`): `ρ/π·cos θ`, 0 below the surface.
    /// The reflective layer is not evaluated: it is only followed by its
    /// reflected ray.
    #[inline]
    pub fn eval(&self, normal: Vec3, omega: Vec3) -> Rgb {
        let cos = normal.dot(omega);
        if cos > 0.0 {
            self.diffuse * (FRAC_1_PI * cos)
        } else {
            Rgb::ZERO
        }
    }

    /// Solid-angle density with which [`Surface::sample`] picks `omega`
    /// by the Lambertian lobe, `P_d·cos θ/π` (0 below the surface or if
    /// the surface reflects nothing).
    #[inline]
    pub fn pdf(&self, normal: Vec3, omega: Vec3) -> f32 {
        self.diffuse_probability().map_or(0.0, |p_diffuse| {
            p_diffuse * normal.dot(omega).max(0.0) * FRAC_1_PI
        })
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

    /// `sample`, `eval` and `pdf` agree: a Lambertian sample's weight is
    /// `eval/pdf`, the lobe follows `choice` against `P_d` (luminance
    /// ratio), and `pdf` integrates to `P_d` over the hemisphere.
    #[test]
    fn surface_sample_eval_pdf_agree() {
        let s = Surface {
            diffuse: Rgb::new(0.6, 0.5, 0.4),
            specular: Rgb::splat(0.3),
            roughness: 0.0,
        };
        let n = Vec3::Y;
        let incoming = Vec3::new(0.3, -1.0, 0.2).normalize();
        let p_d = s.diffuse_probability().unwrap();
        let expected = luminance(s.diffuse) / (luminance(s.diffuse) + luminance(s.specular));
        assert!((p_d - expected).abs() < 1e-6);
        let diffuse = s
            .sample(incoming, n, 0.5 * p_d, Vec2::new(0.3, 0.8))
            .unwrap();
        assert_eq!(diffuse.lobe, Lobe::Diffuse);
        assert!((diffuse.pdf - s.pdf(n, diffuse.direction)).abs() < 1e-6);
        let ratio = s.eval(n, diffuse.direction) / diffuse.pdf;
        assert!((ratio - diffuse.weight).abs().max_element() < 1e-5);
        let specular = s.sample(incoming, n, 0.5 + 0.5 * p_d, Vec2::ZERO).unwrap();
        assert_eq!(specular.lobe, Lobe::Specular);
        assert!((specular.direction - s.reflect(incoming, n, Vec2::ZERO).unwrap()).length() < 1e-6);
        assert!(
            (specular.weight - s.specular / (1.0 - p_d))
                .abs()
                .max_element()
                < 1e-6
        );
        // ∫ pdf dω over the hemisphere (midpoint rule in cos θ and φ).
        let k = 200;
        let mut total = 0.0;
        for i in 0..k {
            let cos = (i as f32 + 0.5) / k as f32;
            let sin = (1.0 - cos * cos).sqrt();
            for j in 0..k {
                let phi = 2.0 * PI * (j as f32 + 0.5) / k as f32;
                let omega = Vec3::new(sin * phi.cos(), cos, sin * phi.sin());
                total += s.pdf(n, omega) * (2.0 * PI / (k * k) as f32);
            }
        }
        assert!((total - p_d).abs() < 1e-3, "{total} vs {p_d}");
        assert_eq!(s.eval(n, -Vec3::Y), Rgb::ZERO);
        assert_eq!(Surface::diffuse(Rgb::ZERO).diffuse_probability(), None);
    }

    /// What a ray meets, by side: a one-sided emitter is dark from behind,
    /// a lamp face is a lamp, glass is a pane unless drawn opaque.
    #[test]
    fn events_by_side_and_glass_setting() {
        use crate::glass::Glass;
        let le = Rgb::new(1.0, 2.0, 3.0);
        let one_sided = Material::emitter(le, false);
        let emitted = |m: Material, front| match m.event(front, false) {
            SurfaceEvent::Emitter {
                emitted,
                lamp,
                reflects,
            } => (emitted, lamp, reflects),
            other => panic!("{other:?}"),
        };
        assert_eq!(emitted(one_sided, true), (Some(le), false, None));
        assert_eq!(emitted(one_sided, false), (None, false, None));
        let two_sided = Material::emitter(le, true);
        assert_eq!(emitted(two_sided, false), (Some(le), false, None));
        // An emitter over a reflecting surface reflects from both sides.
        let grey = Surface::diffuse(Rgb::splat(0.5));
        let glowing = Material::Emissive {
            radiance: le,
            two_sided: false,
            surface: grey,
        };
        assert_eq!(emitted(glowing, true), (Some(le), false, Some(grey)));
        assert_eq!(emitted(glowing, false), (None, false, Some(grey)));
        let lamp = Material::LampFace { radiance: le };
        assert_eq!(emitted(lamp, true), (Some(le), true, None));
        assert_eq!(emitted(lamp, false), (None, true, None));
        let glass = Glass {
            color: Rgb::new(0.9, 0.2, 0.1),
            alpha: 0.5,
        };
        assert_eq!(
            Material::Glass(glass).event(true, false),
            SurfaceEvent::Pane {
                transmittance: Rgb::new(0.95, 0.6, 0.55)
            }
        );
        assert_eq!(
            Material::Glass(glass).event(false, true),
            SurfaceEvent::Reflector(Surface::diffuse(glass.color))
        );
        assert_eq!(
            Material::Dielectric {
                ior: 1.5,
                absorption: Rgb::ZERO
            }
            .event(false, true),
            SurfaceEvent::Interface(Interface {
                ior: 1.5,
                absorption: Rgb::ZERO
            })
        );
        assert!(
            Material::Dielectric {
                ior: 1.5,
                absorption: Rgb::ZERO
            }
            .refracts()
        );
        assert!(!Material::Glass(glass).refracts());
    }
}
