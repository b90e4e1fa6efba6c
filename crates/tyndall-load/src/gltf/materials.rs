//! glTF materials mapped to Tyndall's closed set (docs/scene-format.md,
//! "glTF input"): emitters, thin glass, dielectrics and opaque surfaces
//! from `pbrMetallicRoughness` and the KHR material extensions.

use super::{DEFAULT_IOR, GltfLoader};
use crate::source::SceneError;
use ::gltf::material::AlphaMode;
use tyndall::color::Rgb;
use tyndall::coverage::Coverage;
use tyndall::description::SceneDesc;
use tyndall::glass::Glass;
use tyndall::materials::{Clearcoat, Material, MaterialId, MetallicRoughness};
use tyndall::texture::{Encoding, TextureId};

/// glTF's `alphaCutoff` when a `MASK` material does not give it
/// (glTF 2.0 §5.19, material.alphaCutoff).
const DEFAULT_ALPHA_CUTOFF: f32 = 0.5;

/// The base colour texture of an opaque material: the scene's texture
/// that multiplies its diffuse reflectance, and which TEXCOORD set its
/// coordinates come from.
#[derive(Clone, Copy, Debug)]
pub(super) struct BaseTexture {
    pub texture: TextureId,
    pub tex_coord: u32,
    /// `KHR_texture_transform` of the texture's coordinates.
    pub transform: UvTransform,
}

/// A texture of a material: the scene's texture, which TEXCOORD set its
/// coordinates come from and how they are transformed.
#[derive(Clone, Copy, Debug)]
pub(super) struct MappedTexture {
    pub texture: TextureId,
    pub tex_coord: u32,
    pub transform: UvTransform,
}

/// The normal map of an opaque material (`normalTexture`) and its
/// `scale`.
#[derive(Clone, Copy, Debug)]
pub(super) struct NormalTexture {
    pub map: MappedTexture,
    pub scale: f32,
}

/// A metallic-roughness surface evaluated point by point: the material's
/// factors, and its `metallicRoughnessTexture` if it has one.
#[derive(Clone, Copy, Debug)]
pub(super) struct MetallicRoughnessTexture {
    pub factors: MetallicRoughness,
    pub map: Option<MappedTexture>,
}

/// The textures a converted material binds to its primitives.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct MaterialTextures {
    pub base: Option<BaseTexture>,
    pub normal: Option<NormalTexture>,
    /// An emitter's `emissiveTexture`.
    pub emission: Option<MappedTexture>,
    pub metallic_roughness: Option<MetallicRoughnessTexture>,
    /// The surface's alpha coverage (`alphaMode` `MASK` or `BLEND`), on
    /// the base colour texture's alpha where it has one.
    pub coverage: Option<Coverage>,
}

/// An affine map of texture coordinates, `KHR_texture_transform`'s
/// `T(offset)·R(rotation)·S(scale)` (its README: the rotation matrix
/// `[cos sin; −sin cos]` of the extension's texture space). Affine, so it
/// commutes with interpolation across a triangle: it is applied to the
/// corners' coordinates once, at load.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct UvTransform {
    /// Rows of the 2×3 matrix.
    rows: [[f32; 3]; 2],
}

impl UvTransform {
    pub const IDENTITY: Self = Self {
        rows: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    };

    /// `T·R·S` of `offset`, `rotation` (radians) and `scale`.
    pub fn new(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> Self {
        let (sin, cos) = rotation.sin_cos();
        Self {
            rows: [
                [cos * scale[0], sin * scale[1], offset[0]],
                [-sin * scale[0], cos * scale[1], offset[1]],
            ],
        }
    }

    pub fn apply(&self, [u, v]: [f32; 2]) -> [f32; 2] {
        self.rows.map(|[a, b, c]| a * u + b * v + c)
    }
}

impl GltfLoader<'_> {
    /// The scene's material for a glTF material (added on first use) and
    /// the textures it binds: its base colour texture, its normal map and
    /// its emission texture, if the material keeps them.
    pub(super) fn material_id(
        &mut self,
        material: &::gltf::Material,
        scene: &mut SceneDesc,
    ) -> Result<(MaterialId, MaterialTextures), SceneError> {
        if let Some(&converted) = self.materials.get(&material.index()) {
            return Ok(converted);
        }
        let (converted, mut textures) = self.material(material, scene)?;
        let element = match material.index() {
            Some(i) => format!("materials[{i}]"),
            None => "the default material".into(),
        };
        // A surface that reflects is normal-mapped, whether it emits too
        // or not.
        let reflects = match converted {
            Material::Opaque(_) => true,
            Material::Emissive { surface, .. } => surface.reflects(),
            _ => false,
        };
        textures.normal = match material.normal_texture() {
            Some(info) if reflects => {
                let map = self.mapped(
                    &element,
                    (&info.texture(), Encoding::Linear),
                    info.extensions(),
                    info.tex_coord(),
                    scene,
                )?;
                // A tangent-space map's vectors point out of the surface
                // (blue above ½); one whose mean points in (an all-black
                // image) is no normal map.
                if scene.textures[map.texture as usize].value.mean().z < 0.5 {
                    self.warn(
                        &element,
                        format!(
                            "normalTexture (images[{}]) is ignored: its vectors point into the \
                             surface (blue below 128 on average), which is no tangent-space \
                             normal map",
                            info.texture().source().index()
                        ),
                    );
                    None
                } else {
                    Some(NormalTexture {
                        map,
                        scale: info.scale(),
                    })
                }
            }
            Some(_) => {
                self.warn(
                    &element,
                    "normalTexture is ignored: only opaque surfaces are normal-mapped",
                );
                None
            }
            None => None,
        };
        textures.emission = match (material.emissive_texture(), converted) {
            (Some(info), Material::Emissive { .. }) => {
                Some(self.mapped_info(&element, (&info, Encoding::Srgb), scene)?)
            }
            _ => None,
        };
        // A surface that no texture's alpha can make more than a hole is
        // left out.
        if textures.coverage.is_some_and(|c| c.is_empty()) {
            self.hidden_materials.insert(material.index());
        }
        let id = scene.add_material(converted, self.origin(element));
        self.materials.insert(material.index(), (id, textures));
        Ok((id, textures))
    }

    /// The scene's texture for a material's `texture` and the coordinates
    /// it reads: its `tex_coord` set, or `KHR_texture_transform`'s (in
    /// `extensions`) with its transform.
    fn mapped(
        &mut self,
        element: &str,
        (texture, encoding): (&::gltf::Texture, Encoding),
        extensions: Option<&serde_json::Map<String, serde_json::Value>>,
        tex_coord: u32,
        scene: &mut SceneDesc,
    ) -> Result<MappedTexture, SceneError> {
        let (id, _) = self.texture(element, texture, encoding, scene)?;
        let (transform, tex_coord) = texture_transform(extensions, tex_coord);
        Ok(MappedTexture {
            texture: id,
            tex_coord,
            transform,
        })
    }

    /// [`GltfLoader::mapped`] for a texture reference of the common kind
    /// (emissive, colour: `Encoding::Srgb`; metallic-roughness, data:
    /// `Encoding::Linear`).
    fn mapped_info(
        &mut self,
        element: &str,
        (info, encoding): (&::gltf::texture::Info, Encoding),
        scene: &mut SceneDesc,
    ) -> Result<MappedTexture, SceneError> {
        self.mapped(
            element,
            (&info.texture(), encoding),
            info.extensions(),
            info.tex_coord(),
            scene,
        )
    }

    /// Tyndall's material for a glTF material, first match wins:
    ///
    /// 1. `emissiveFactor × emissive_strength` non-zero → an emitter of
    ///    that radiance (W·sr⁻¹·m⁻², the number Blender's emission
    ///    strength gives Cycles), two-sided if `doubleSided`, times its
    ///    `emissiveTexture` (returned to be bound), over the opaque
    ///    surface of rule 3, which reflects as well (glTF adds emission
    ///    to the BRDF, as Cycles' Principled BSDF does); its transmission
    ///    is ignored, with a warning.
    /// 2. KHR_materials_transmission factor > 0: with KHR_materials_volume
    ///    thickness > 0 a refractive dielectric of KHR_materials_ior's
    ///    index (1.5 by default); without, thin coloured glass of the base
    ///    colour (the stained-glass case).
    /// 3. Otherwise an opaque surface: glTF's metallic-roughness BRDF as
    ///    [`MetallicRoughness::surface`] makes it, with the dielectric's
    ///    normal-incidence reflectance
    ///    `F0 = ((ior − 1)/(ior + 1))² · specularFactor · specularColorFactor`
    ///    (KHR_materials_specular; Blender writes factor 0 for a pure
    ///    Lambert surface).
    ///
    /// A base colour texture (sRGB-decoded, bilinear, the sampler's wrap
    /// modes) multiplies an opaque surface's diffuse reflectance at each
    /// point, and is returned to be bound to the primitives, as is a
    /// `metallicRoughnessTexture` (metalness in blue, roughness in green)
    /// with the factors: where it is given, or where the base colour
    /// colours a metal's specular layer too, the surface is evaluated at
    /// each point. Where one colour must stand for the texture — thin
    /// glass — the texture's mean colour applies, with a warning.
    fn material(
        &mut self,
        material: &::gltf::Material,
        scene: &mut SceneDesc,
    ) -> Result<(Material, MaterialTextures), SceneError> {
        let element = match material.index() {
            Some(i) => format!("materials[{i}]"),
            None => "the default material".to_string(),
        };
        let pbr = material.pbr_metallic_roughness();
        let factor = pbr.base_color_factor();
        let base_factor = Rgb::new(factor[0], factor[1], factor[2]);
        if !(base_factor.is_finite()
            && base_factor.min_element() >= 0.0
            && base_factor.max_element() <= 1.0)
        {
            return Err(self.err(
                &element,
                format!("baseColorFactor must be in [0, 1], got {factor:?}"),
            ));
        }
        // The base colour's mean over the texture, where one colour must
        // stand for it.
        let (base, texture) = match pbr.base_color_texture() {
            Some(info) => {
                let (id, mean) = self.texture(&element, &info.texture(), Encoding::Srgb, scene)?;
                let transform = info.texture_transform();
                let texture = BaseTexture {
                    texture: id,
                    // The extension's own set, where it names one.
                    tex_coord: transform
                        .as_ref()
                        .and_then(|t| t.tex_coord())
                        .unwrap_or(info.tex_coord()),
                    transform: transform.map_or(UvTransform::IDENTITY, |t| {
                        UvTransform::new(t.offset(), t.rotation(), t.scale())
                    }),
                };
                (base_factor * mean, Some(texture))
            }
            None => (base_factor, None),
        };
        if material.occlusion_texture().is_some() {
            self.warn(
                &element,
                "occlusionTexture is ignored, as Cycles ignores it: a path tracer finds the \
                 occlusion it bakes",
            );
        }
        let emissive_strength = material.emissive_strength().unwrap_or(1.0);
        let emission = Rgb::from_array(material.emissive_factor()) * emissive_strength;
        if !(emission.is_finite() && emission.min_element() >= 0.0) {
            return Err(self.err(
                &element,
                "emissiveFactor × emissiveStrength must be non-negative and finite",
            ));
        }
        // The alpha mode, where it asks for partial coverage.
        let covered = match material.alpha_mode() {
            AlphaMode::Opaque => None,
            AlphaMode::Mask => Some("MASK"),
            AlphaMode::Blend => Some("BLEND"),
        };
        let emits = emission.max_element() > 0.0;
        if let Some(mode) = covered
            && emits
        {
            self.warn(
                &element,
                format!(
                    "alphaMode {mode} is ignored on an emitter: it emits over its whole surface"
                ),
            );
        }
        let ior = material.ior().unwrap_or(DEFAULT_IOR);
        if !(ior.is_finite() && (1.0..=10.0).contains(&ior)) {
            return Err(self.err(
                &element,
                format!("KHR_materials_ior ior must be in [1, 10], got {ior}"),
            ));
        }
        let transmits = material
            .transmission()
            .is_some_and(|t| t.transmission_factor() > 0.0);
        if emits && transmits {
            self.warn(
                &element,
                "KHR_materials_transmission is ignored on an emitter: it is rendered opaque",
            );
        }
        if let Some(transmission) = material.transmission()
            && transmits
            && !emits
        {
            let t = transmission.transmission_factor();
            if let Some(mode) = covered {
                self.warn(
                    &element,
                    format!("alphaMode {mode} is ignored on glass: the whole surface transmits"),
                );
            }
            if transmission.transmission_texture().is_some() {
                self.warn(&element, "transmissionTexture is ignored");
            }
            if self.clearcoat(material, &element)?.factor > 0.0 {
                self.warn(
                    &element,
                    "KHR_materials_clearcoat is ignored on glass: its surface is the glass's own",
                );
            }
            let thickness = material.volume().map_or(0.0, |v| v.thickness_factor());
            if thickness > 0.0 {
                let absorption = match material.volume() {
                    Some(volume) => self.absorption(
                        &element,
                        volume.attenuation_color(),
                        volume.attenuation_distance(),
                    )?,
                    None => Rgb::ZERO,
                };
                return Ok((
                    Material::Dielectric { ior, absorption },
                    MaterialTextures::default(),
                ));
            }
            if t < 1.0 {
                self.warn(
                    &element,
                    format!(
                        "transmissionFactor {t} is rendered as 1: thin glass passes all light it does not filter"
                    ),
                );
            }
            if texture.is_some() {
                self.warn(
                    &element,
                    "baseColorTexture of thin glass is averaged to one colour",
                );
            }
            return Ok((
                Material::Glass(Glass {
                    color: base,
                    alpha: 1.0,
                }),
                MaterialTextures::default(),
            ));
        }
        let metallic = pbr.metallic_factor();
        let roughness = pbr.roughness_factor();
        for (name, v) in [("metallicFactor", metallic), ("roughnessFactor", roughness)] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Err(self.err(&element, format!("{name} must be in [0, 1], got {v}")));
            }
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
        let r0 = MetallicRoughness::dielectric_f0(ior);
        let f0 = (Rgb::splat(r0) * specular_color * specular_factor).clamp(Rgb::ZERO, Rgb::ONE);
        if !f0.is_finite() {
            return Err(self.err(&element, "KHR_materials_specular factors must be finite"));
        }
        let factors = MetallicRoughness {
            base: base_factor,
            metallic,
            roughness,
            f0,
            clearcoat: self.clearcoat(material, &element)?,
        };
        // A metallic-roughness texture, or a metal's colour that follows
        // its base colour texture, makes the surface vary point by
        // point: it is then evaluated at each (the material's own surface,
        // of the texture's mean colour, stands for it where one must).
        let metallic_roughness = match pbr.metallic_roughness_texture() {
            Some(info) => Some(MetallicRoughnessTexture {
                factors,
                map: Some(self.mapped_info(&element, (&info, Encoding::Linear), scene)?),
            }),
            None if texture.is_some() && metallic > 0.0 => {
                Some(MetallicRoughnessTexture { factors, map: None })
            }
            None => None,
        };
        // With a texture the diffuse reflectance is the factor's, which
        // the texture multiplies point by point.
        let constant_base = match (&texture, &metallic_roughness) {
            (Some(_), None) => base_factor,
            _ => base,
        };
        let surface = MetallicRoughness {
            base: constant_base,
            ..factors
        }
        .surface();
        let diffuse = surface.diffuse;
        let coverage = match emits {
            true => None,
            false => self.coverage(material, &element)?,
        };
        // A surface with no diffuse reflectance has nothing to texture,
        // unless the texture's alpha covers it or colours its metal.
        let texture = match (texture, coverage) {
            (Some(t), Some(_)) if scene.textures[t.texture as usize].value.has_alpha() => Some(t),
            (t, _) => t.filter(|_| diffuse != Rgb::ZERO || metallic_roughness.is_some()),
        };
        let converted = match emits {
            true => Material::Emissive {
                radiance: emission,
                two_sided: material.double_sided(),
                surface,
            },
            false => Material::Opaque(surface),
        };
        Ok((
            converted,
            MaterialTextures {
                base: texture,
                metallic_roughness,
                coverage,
                ..MaterialTextures::default()
            },
        ))
    }

    /// A material's `KHR_materials_clearcoat` factors (none without the
    /// extension). The gltf crate does not parse the extension, so it is
    /// read from the material's `extensions`. Its textures are not
    /// applied: each is named in a warning, the factors holding
    /// everywhere.
    fn clearcoat(
        &mut self,
        material: &::gltf::Material,
        element: &str,
    ) -> Result<Clearcoat, SceneError> {
        let Some(coat) = material
            .extensions()
            .and_then(|e| e.get("KHR_materials_clearcoat"))
        else {
            return Ok(Clearcoat::default());
        };
        let factor = |key: &str| -> Result<f32, SceneError> {
            match coat.get(key) {
                None => Ok(0.0),
                Some(v) => match v.as_f64() {
                    Some(x) if (0.0..=1.0).contains(&x) => Ok(x as f32),
                    _ => Err(self.err(
                        element,
                        format!(
                            "KHR_materials_clearcoat {key} must be a number in [0, 1], got {v}"
                        ),
                    )),
                },
            }
        };
        let clearcoat = Clearcoat {
            factor: factor("clearcoatFactor")?,
            roughness: factor("clearcoatRoughnessFactor")?,
        };
        for (texture, outcome) in [
            ("clearcoatTexture", "clearcoatFactor holds everywhere"),
            (
                "clearcoatRoughnessTexture",
                "clearcoatRoughnessFactor holds everywhere",
            ),
            (
                "clearcoatNormalTexture",
                "the coat takes the base's shading normal",
            ),
        ] {
            if clearcoat.factor > 0.0 && coat.get(texture).is_some() {
                self.warn(
                    element,
                    format!("KHR_materials_clearcoat {texture} is ignored: {outcome}"),
                );
            }
        }
        Ok(clearcoat)
    }

    /// The alpha coverage of a `MASK` material (a cut-out at
    /// `alphaCutoff`, 0.5 by default) or a `BLEND` one (partial
    /// coverage), on `baseColorFactor`'s alpha; `None` for `OPAQUE`.
    fn coverage(
        &self,
        material: &::gltf::Material,
        element: &str,
    ) -> Result<Option<Coverage>, SceneError> {
        let factor = material.pbr_metallic_roughness().base_color_factor()[3];
        if !(0.0..=1.0).contains(&factor) {
            return Err(self.err(
                element,
                format!("baseColorFactor's alpha must be in [0, 1], got {factor}"),
            ));
        }
        Ok(match material.alpha_mode() {
            AlphaMode::Opaque => None,
            AlphaMode::Blend => Some(Coverage::Partial { factor }),
            AlphaMode::Mask => {
                let cutoff = material.alpha_cutoff().unwrap_or(DEFAULT_ALPHA_CUTOFF);
                if !(cutoff.is_finite() && (0.0..=1.0).contains(&cutoff)) {
                    return Err(self.err(
                        element,
                        format!("alphaCutoff must be in [0, 1], got {cutoff}"),
                    ));
                }
                Some(Coverage::Cutout { cutoff, factor })
            }
        })
    }

    /// The absorption σa per unit length inside a dielectric from
    /// `KHR_materials_volume`: light crossing `attenuationDistance` keeps
    /// `attenuationColor` of itself (Beer–Lambert), `σa = −ln(c)/d` per
    /// channel; clear for an infinite distance (the default). A channel of
    /// 0 is taken as 10⁻⁶ (opaque within the distance: the ratio stays
    /// finite).
    fn absorption(&self, element: &str, color: [f32; 3], distance: f32) -> Result<Rgb, SceneError> {
        if distance.is_nan() || distance <= 0.0 {
            return Err(self.err(
                element,
                format!("KHR_materials_volume attenuationDistance must be > 0, got {distance}"),
            ));
        }
        let color = Rgb::from_array(color);
        if !(color.is_finite() && color.min_element() >= 0.0 && color.max_element() <= 1.0) {
            return Err(self.err(
                element,
                format!("KHR_materials_volume attenuationColor must be in [0, 1], got {color}"),
            ));
        }
        if distance == f32::INFINITY {
            return Ok(Rgb::ZERO);
        }
        let c = color.max(Rgb::splat(1e-6));
        Ok(Rgb::new(-c.x.ln(), -c.y.ln(), -c.z.ln()) / distance)
    }
}

/// The `KHR_texture_transform` of a texture reference whose `gltf` type
/// has no accessor for it (`normalTexture`), read from its `extensions`,
/// and the TEXCOORD set it names (else `tex_coord`).
fn texture_transform(
    extensions: Option<&serde_json::Map<String, serde_json::Value>>,
    tex_coord: u32,
) -> (UvTransform, u32) {
    let Some(t) = extensions.and_then(|e| e.get("KHR_texture_transform")) else {
        return (UvTransform::IDENTITY, tex_coord);
    };
    let pair = |key: &str, default: [f32; 2]| {
        t.get(key)
            .and_then(|v| v.as_array())
            .and_then(|a| Some([a.first()?.as_f64()? as f32, a.get(1)?.as_f64()? as f32]))
            .unwrap_or(default)
    };
    let rotation = t.get("rotation").and_then(|v| v.as_f64()).unwrap_or(0.0) as f32;
    let set = t
        .get("texCoord")
        .and_then(|v| v.as_u64())
        .and_then(|n| u32::try_from(n).ok())
        .unwrap_or(tex_coord);
    (
        UvTransform::new(
            pair("offset", [0.0, 0.0]),
            rotation,
            pair("scale", [1.0, 1.0]),
        ),
        set,
    )
}
