//! glTF's metallic-roughness parameters (and `KHR_materials_clearcoat`'s)
//! made into a [`Surface`].

use super::surface::{Coat, Surface};
use crate::color::Rgb;

/// glTF's metallic-roughness material (glTF 2.0 §3.9.2 and Appendix B)
/// as a [`Surface`]: base colour `base`, metalness `metallic` and
/// perceptual `roughness` (each in `[0, 1]`), and the dielectric's
/// normal-incidence reflectance `f0` (`((ior − 1)/(ior + 1))²` times
/// `KHR_materials_specular`'s factors). Its surface is the glTF BRDF's
/// mix at normal incidence: diffuse `base·(1 − m)·(1 − max f0)`,
/// specular `base·m + f0·(1 − m)`, and the lobe's roughness `roughness²`
/// (glTF's α). With a `clearcoat` (`KHR_materials_clearcoat`: its factor
/// `c` and perceptual roughness `r_c`) the extension's
/// `mix(base, coat, c·F_c)` at normal incidence: both layers times
/// `1 − c·F_c` under a [`Coat`] of reflectance `c·F_c` and roughness
/// `r_c²`, where `F_c` = 0.04 (the coat's IOR 1.5). Evaluated once per
/// material, or at each point where textures vary its parameters
/// (`metallicRoughnessTexture`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetallicRoughness {
    pub base: Rgb,
    pub metallic: f32,
    pub roughness: f32,
    pub f0: Rgb,
    pub clearcoat: Clearcoat,
}

/// `KHR_materials_clearcoat`'s factors: the coat's weight `factor` and
/// perceptual `roughness`, each in `[0, 1]` (0 and 0 without a coat).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Clearcoat {
    pub factor: f32,
    pub roughness: f32,
}

impl Clearcoat {
    /// The coat's normal-incidence Fresnel reflectance, F0 of its IOR 1.5
    /// (`KHR_materials_clearcoat`: the layer's IOR is fixed at 1.5).
    pub const F0: f32 = 0.04;
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
        let coat = Coat {
            reflectance: self.clearcoat.factor * Clearcoat::F0,
            roughness: self.clearcoat.roughness * self.clearcoat.roughness,
        };
        let below = 1.0 - coat.reflectance;
        let diffuse = self.base * ((1.0 - m) * (1.0 - self.f0.max_element()) * below);
        let specular = (self.base * m + self.f0 * (1.0 - m)) * below;
        Surface {
            diffuse,
            specular,
            roughness: if specular == Rgb::ZERO {
                0.0
            } else {
                self.roughness * self.roughness
            },
            coat: if coat.reflectance > 0.0 {
                coat
            } else {
                Coat::NONE
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::luminance;
    use crate::materials::Lobe;
    use glam::{Vec2, Vec3};

    /// A coated surface's lobes: the choice of [`Surface::sample`] and of
    /// [`Surface::reflect_layers`] over `choice` ∈ [0, 1) gives each lobe
    /// its luminance's share, so the weights' expectations (of mirror
    /// layers, whose weight is their reflectance) are the layers'
    /// reflectances summed — the albedo, which
    /// [`MetallicRoughness::surface`] keeps: a clear coat of factor c takes
    /// `0.04·c` off the layers beneath and reflects it itself.
    #[test]
    fn coat_lobes_share_the_albedo() {
        let factors = MetallicRoughness {
            base: Rgb::new(0.8, 0.5, 0.2),
            metallic: 0.3,
            roughness: 0.5,
            f0: Rgb::splat(0.04),
            clearcoat: Clearcoat {
                factor: 0.75,
                roughness: 0.2,
            },
        };
        let coated = factors.surface();
        let uncoated = MetallicRoughness {
            clearcoat: Clearcoat::default(),
            ..factors
        }
        .surface();
        assert!((coated.coat.reflectance - 0.03).abs() < 1e-7);
        assert!((coated.coat.roughness - 0.04).abs() < 1e-7);
        assert_eq!(uncoated.coat, Coat::NONE);
        for (a, b) in [
            (coated.diffuse, uncoated.diffuse * 0.97),
            (coated.specular, uncoated.specular * 0.97),
        ] {
            assert!((a - b).abs().max_element() < 1e-6, "{a} vs {b}");
        }
        assert!((coated.roughness_of(Lobe::Coat) - 0.04).abs() < 1e-7);
        // The lobes' choice and weights, on the same layers made mirrors
        // (whose weight is their reflectance, whatever the direction).
        let mirrors = Surface {
            roughness: 0.0,
            coat: Coat {
                roughness: 0.0,
                ..coated.coat
            },
            ..coated
        };
        let n = Vec3::Y;
        let incoming = Vec3::new(0.3, -1.0, 0.2).normalize();
        let k = 10_000;
        let (mut all, mut reflected) = (Rgb::ZERO, Rgb::ZERO);
        let mut coat_share = 0.0;
        for i in 0..k {
            let choice = (i as f32 + 0.5) / k as f32;
            let s = mirrors.sample(incoming, n, choice, Vec2::ZERO).unwrap();
            all += s.weight / k as f32;
            coat_share += f32::from(u8::from(s.lobe == Lobe::Coat)) / k as f32;
            let r = mirrors
                .reflect_layers(incoming, n, choice, Vec2::ZERO)
                .unwrap();
            assert_ne!(r.lobe, Lobe::Diffuse);
            reflected += r.weight / k as f32;
        }
        let total = luminance(coated.diffuse) + luminance(coated.specular) + 0.03;
        assert!((coat_share - 0.03 / total).abs() < 2e-4, "{coat_share}");
        assert!((all - coated.albedo()).abs().max_element() < 1e-3, "{all}");
        let layers = coated.specular + Rgb::splat(0.03);
        assert!(
            (reflected - layers).abs().max_element() < 1e-3,
            "{reflected}"
        );
        // Without a coat, the specular layer whatever the choice.
        let plain = Surface {
            roughness: 0.0,
            ..uncoated
        };
        let r = plain
            .reflect_layers(incoming, n, 0.999, Vec2::ZERO)
            .unwrap();
        assert_eq!((r.lobe, r.weight), (Lobe::Specular, uncoated.specular));
    }
}
