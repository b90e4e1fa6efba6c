//! Surface materials.
//!
//! The set is closed and small, so it is an enum: the integrators `match`
//! on it to follow a path through glass and dielectrics, and an opaque
//! [`Surface`] answers for its own scattering ([`Surface::sample`],
//! [`Surface::eval`], [`Surface::pdf`]). Glass is thin coloured glass (the paper's §3.3), see [`crate::glass`].
//!
//! The physics is a module each: smooth dielectric interfaces
//! (`dielectric`: Fresnel and refraction), the opaque surface's layers
//! and their sampling (`surface`), and glTF's metallic-roughness
//! parameters made into a surface (`metallic_roughness`).

mod dielectric;
mod metallic_roughness;
mod microfacet;
mod surface;

pub use dielectric::{dielectric_reflectance, dielectric_scatter, fresnel_dielectric};
pub use metallic_roughness::{Clearcoat, MetallicRoughness};
pub use microfacet::{
    ALBEDO_COSINES, ALBEDO_ROUGHNESSES, Ggx, albedo_in_row, albedo_row_at, compensated,
};
pub use surface::{Coat, GlossyLayer, Lobe, Surface, SurfaceSample, layer_eval, reflect_layer};

use crate::color::Rgb;
use crate::glass::Glass;

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

#[cfg(test)]
mod tests {
    use super::*;

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
