//! glTF materials mapped to Tyndall's closed set (docs/scene-format.md,
//! "glTF input"): emitters, thin glass, dielectrics and opaque surfaces
//! from `pbrMetallicRoughness` and the KHR material extensions.

use super::{DEFAULT_IOR, GltfLoader};
use crate::source::SceneError;
use ::gltf::image::Format;
use tyndall::color::{Rgb, srgb_to_linear};
use tyndall::description::SceneDesc;
use tyndall::glass::Glass;
use tyndall::materials::{Material, MaterialId, Surface};

impl GltfLoader<'_> {
    pub(super) fn material_id(
        &mut self,
        material: &::gltf::Material,
        scene: &mut SceneDesc,
    ) -> Result<MaterialId, SceneError> {
        if let Some(&id) = self.materials.get(&material.index()) {
            return Ok(id);
        }
        let converted = self.material(material)?;
        let element = match material.index() {
            Some(i) => format!("materials[{i}]"),
            None => "the default material".into(),
        };
        let id = scene.add_material(converted, self.origin(element));
        self.materials.insert(material.index(), id);
        Ok(id)
    }

    /// Tyndall's material for a glTF material, first match wins:
    ///
    /// 1. `emissiveFactor × emissive_strength` non-zero → an emitter of
    ///    that radiance (W·sr⁻¹·m⁻², the number Blender's emission
    ///    strength gives Cycles), two-sided if `doubleSided`; emitters do
    ///    not reflect.
    /// 2. KHR_materials_transmission factor > 0: with KHR_materials_volume
    ///    thickness > 0 a refractive dielectric of KHR_materials_ior's
    ///    index (1.5 by default); without, thin coloured glass of the base
    ///    colour (the stained-glass case).
    /// 3. Otherwise an opaque surface: with metallic `m`, base colour `c`
    ///    and dielectric normal-incidence reflectance
    ///    `F0 = ((ior − 1)/(ior + 1))² · specularFactor · specularColorFactor`
    ///    (KHR_materials_specular; Blender writes factor 0 for a pure
    ///    Lambert surface), diffuse `c·(1 − m)·(1 − max F0)` and specular
    ///    `c·m + F0·(1 − m)`, the glTF BRDF's mix at normal incidence; the
    ///    roughness of the reflective lobe is glTF's `roughness²` (its α).
    ///
    /// A base-colour texture multiplies the factor by the texture's mean
    /// linear colour: Tyndall has no textures yet.
    fn material(&mut self, material: &::gltf::Material) -> Result<Material, SceneError> {
        let element = match material.index() {
            Some(i) => format!("materials[{i}]"),
            None => "the default material".to_string(),
        };
        let pbr = material.pbr_metallic_roughness();
        let factor = pbr.base_color_factor();
        let mut base = Rgb::new(factor[0], factor[1], factor[2]);
        if !(base.is_finite() && base.min_element() >= 0.0 && base.max_element() <= 1.0) {
            return Err(self.err(
                &element,
                format!("baseColorFactor must be in [0, 1], got {factor:?}"),
            ));
        }
        if let Some(info) = pbr.base_color_texture() {
            base *= self.texture_average(&element, &info.texture())?;
        }
        let emissive_strength = material.emissive_strength().unwrap_or(1.0);
        let emission = Rgb::from_array(material.emissive_factor()) * emissive_strength;
        if !(emission.is_finite() && emission.min_element() >= 0.0) {
            return Err(self.err(
                &element,
                "emissiveFactor × emissiveStrength must be non-negative and finite",
            ));
        }
        if emission.max_element() > 0.0 {
            if material.emissive_texture().is_some() {
                self.warn(
                    &element,
                    "emissiveTexture is ignored: the surface emits emissiveFactor",
                );
            }
            return Ok(Material::Emissive {
                radiance: emission,
                two_sided: material.double_sided(),
            });
        }
        let ior = material.ior().unwrap_or(DEFAULT_IOR);
        if !(ior.is_finite() && (1.0..=10.0).contains(&ior)) {
            return Err(self.err(
                &element,
                format!("KHR_materials_ior ior must be in [1, 10], got {ior}"),
            ));
        }
        if let Some(transmission) = material.transmission()
            && transmission.transmission_factor() > 0.0
        {
            let t = transmission.transmission_factor();
            if transmission.transmission_texture().is_some() {
                self.warn(&element, "transmissionTexture is ignored");
            }
            let thickness = material.volume().map_or(0.0, |v| v.thickness_factor());
            if thickness > 0.0 {
                if let Some(volume) = material.volume()
                    && volume.attenuation_distance().is_finite()
                {
                    self.warn(
                        &element,
                        "attenuationColor/attenuationDistance are ignored: the dielectric's inside is clear",
                    );
                }
                return Ok(Material::Dielectric { ior });
            }
            if t < 1.0 {
                self.warn(
                    &element,
                    format!(
                        "transmissionFactor {t} is rendered as 1: thin glass passes all light it does not filter"
                    ),
                );
            }
            return Ok(Material::Glass(Glass {
                color: base,
                alpha: 1.0,
            }));
        }
        let metallic = pbr.metallic_factor();
        let roughness = pbr.roughness_factor();
        for (name, v) in [("metallicFactor", metallic), ("roughnessFactor", roughness)] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Err(self.err(&element, format!("{name} must be in [0, 1], got {v}")));
            }
        }
        if pbr.metallic_roughness_texture().is_some() {
            self.warn(
                &element,
                "metallicRoughnessTexture is ignored: the factors apply everywhere",
            );
        }
        let (specular_factor, specular_color) = match material.specular() {
            Some(s) => {
                if s.specular_texture().is_some() || s.specular_color_texture().is_some() {
                    self.warn(&element, "KHR_materials_specular textures are ignored");
                }
                (
                    s.specular_factor(),
                    Rgb::from_array(s.specular_color_factor()),
                )
            }
            None => (1.0, Rgb::ONE),
        };
        let r0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
        let f0 = (Rgb::splat(r0) * specular_color * specular_factor).clamp(Rgb::ZERO, Rgb::ONE);
        if !f0.is_finite() {
            return Err(self.err(&element, "KHR_materials_specular factors must be finite"));
        }
        let diffuse = base * (1.0 - metallic) * (1.0 - f0.max_element());
        let specular = base * metallic + f0 * (1.0 - metallic);
        Ok(Material::Opaque(if specular == Rgb::ZERO {
            Surface::diffuse(diffuse)
        } else {
            Surface {
                diffuse,
                specular,
                roughness: roughness * roughness,
            }
        }))
    }

    /// The mean linear-RGB colour of a texture's image (sRGB-decoded,
    /// alpha ignored).
    fn texture_average(
        &mut self,
        element: &str,
        texture: &::gltf::Texture,
    ) -> Result<Rgb, SceneError> {
        let index = texture.source().index();
        if let Some(&mean) = self.texture_averages.get(&index) {
            return Ok(mean);
        }
        let image = self
            .images
            .get(index)
            .ok_or_else(|| self.err(element, format!("images[{index}] was not loaded")))?;
        let (channels, bytes) = match image.format {
            Format::R8 => (1, 1),
            Format::R8G8 => (2, 1),
            Format::R8G8B8 => (3, 1),
            Format::R8G8B8A8 => (4, 1),
            Format::R16 => (1, 2),
            Format::R16G16 => (2, 2),
            Format::R16G16B16 => (3, 2),
            Format::R16G16B16A16 => (4, 2),
            other => {
                return Err(self.err(
                    element,
                    format!(
                        "images[{index}]: pixel format {other:?} is not supported for a base colour"
                    ),
                ));
            }
        };
        let stride = channels * bytes;
        let mut sum = [0.0f64; 3];
        let mut count = 0usize;
        for pixel in image.pixels.chunks_exact(stride) {
            let channel = |c: usize| -> f32 {
                let c = c.min(channels - 1);
                let v = if bytes == 1 {
                    pixel[c] as f32 / 255.0
                } else {
                    u16::from_ne_bytes([pixel[2 * c], pixel[2 * c + 1]]) as f32 / 65535.0
                };
                srgb_to_linear(v)
            };
            // One and two channels are grey (+ alpha).
            let rgb = if channels <= 2 {
                [channel(0); 3]
            } else {
                [channel(0), channel(1), channel(2)]
            };
            for (s, v) in sum.iter_mut().zip(rgb) {
                *s += v as f64;
            }
            count += 1;
        }
        if count == 0 {
            return Err(self.err(element, format!("images[{index}] has no pixels")));
        }
        let mean = Rgb::new(
            (sum[0] / count as f64) as f32,
            (sum[1] / count as f64) as f32,
            (sum[2] / count as f64) as f32,
        );
        self.warn(
            element,
            format!(
                "baseColorTexture (images[{index}]) is averaged to one colour {:?}: Tyndall has no textures",
                mean.to_array()
            ),
        );
        self.texture_averages.insert(index, mean);
        Ok(mean)
    }
}
