//! `type = "principled"` materials: glTF's metallic-roughness surface
//! (the subset of Blender's Principled BSDF that glTF carries, and that
//! Blender's glTF exporter writes), optionally emitting and textured.

use super::Loader;
use super::tables::PrincipledTable;
use crate::source::SceneError;
use std::ops::Range;
use std::sync::Arc;
use tyndall::color::Rgb;
use tyndall::description::SceneDesc;
use tyndall::materials::{Clearcoat, Material, MetallicRoughness};
use tyndall::texture::{TextureId, Wrap};

/// The index of refraction whose F0 is the default (glTF's).
const DEFAULT_IOR: f32 = 1.5;

/// A principled material's base colour texture, bound to each mesh that
/// uses the material at the mesh's own `uvs`.
#[derive(Clone, Copy)]
pub(super) struct BaseColorTexture {
    pub(super) texture: TextureId,
    /// The material's parameters, evaluated per point where it is a
    /// metal (its specular colour then follows the texture too).
    pub(super) factors: MetallicRoughness,
}

impl Loader<'_> {
    /// The material of a principled table spanning `span`: the surface of
    /// [`MetallicRoughness::surface`], under `emission` (radiance, W/(m²·sr))
    /// where that is non-zero, as glTF adds emission to the BRDF; and its
    /// base colour texture (PNG or JPEG, sRGB, repeating), read and added
    /// to `scene`.
    pub(super) fn principled(
        &self,
        span: &Range<usize>,
        table: &PrincipledTable,
        scene: &mut SceneDesc,
    ) -> Result<(Material, Option<BaseColorTexture>), SceneError> {
        let unit = |key: &str, v: f32| self.number(span, key, v, (0.0, 1.0), "in [0, 1]");
        let factors = MetallicRoughness {
            base: self.color(span, "base_color", table.base_color, true)?,
            metallic: unit("metallic", table.metallic)?,
            roughness: unit("roughness", table.roughness)?,
            f0: match table.f0 {
                Some(f0) => self.color(span, "f0", f0, true)?,
                None => Rgb::splat(MetallicRoughness::dielectric_f0(DEFAULT_IOR)),
            },
            clearcoat: Clearcoat {
                factor: unit("coat", table.coat)?,
                roughness: unit("coat_roughness", table.coat_roughness)?,
            },
        };
        let emission = match table.emission {
            Some(e) => self.emission(span, "emission", e)?,
            None => Rgb::ZERO,
        };
        let surface = factors.surface();
        let material = if emission == Rgb::ZERO {
            Material::Opaque(surface)
        } else {
            Material::Emissive {
                radiance: emission,
                two_sided: table.two_sided,
                surface,
            }
        };
        let texture = match &table.base_color_texture {
            Some(file) => {
                let path = self.relative(file);
                let texture = self
                    .base_color_images
                    .get_or_read(&path, |path| {
                        let image = crate::images::load_texture(path, [Wrap::Repeat; 2])?;
                        Ok(scene.add_texture(Arc::new(image), self.origin(span)))
                    })
                    .map_err(|e: String| self.err(span, "base_color_texture", e))?;
                Some(BaseColorTexture { texture, factors })
            }
            None => None,
        };
        Ok((material, texture))
    }
}
