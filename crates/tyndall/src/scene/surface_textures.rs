//! Colour textures bound to mesh triangles: which texture multiplies a
//! primitive's diffuse reflectance, and its texture coordinates at the
//! triangle's corners, interpolated by barycentric weights; and the alpha
//! cut-outs that make holes in them.

use crate::color::Rgb;
use crate::shapes::Triangle;
use crate::texture::{AlphaCutout, Texture, TextureId};
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// A primitive's texture and its corners' texture coordinates (`None`:
/// the texture's mean colour).
#[derive(Clone, Copy, Debug)]
struct Binding {
    texture: TextureId,
    uvs: Option<[Vec2; 3]>,
    cutout: Option<AlphaCutout>,
}

/// The textures of a scene and the primitives they are bound to.
#[derive(Debug, Default)]
pub(crate) struct SurfaceTextures {
    textures: Vec<Arc<Texture>>,
    /// Per primitive, its index in `bindings` or [`NONE`]; empty while no
    /// primitive is textured.
    slot: Vec<u32>,
    bindings: Vec<Binding>,
    /// Whether some binding has a cut-out.
    cutouts: bool,
}

const NONE: u32 = u32::MAX;

impl SurfaceTextures {
    pub fn new(textures: Vec<Arc<Texture>>) -> Self {
        Self {
            textures,
            ..Self::default()
        }
    }

    /// Binds `texture` to primitive `primitive` with its corners'
    /// coordinates `uvs`, and the texture's alpha `cutout` if given.
    pub fn bind(
        &mut self,
        primitive: u32,
        texture: TextureId,
        uvs: Option<[Vec2; 3]>,
        cutout: Option<AlphaCutout>,
    ) {
        let index = primitive as usize;
        if self.slot.len() <= index {
            self.slot.resize(index + 1, NONE);
        }
        self.slot[index] = self.bindings.len() as u32;
        self.cutouts |= cutout.is_some();
        self.bindings.push(Binding {
            texture,
            uvs,
            cutout,
        });
    }

    /// Whether some primitive has an alpha cut-out.
    pub fn has_cutouts(&self) -> bool {
        self.cutouts
    }

    /// Whether the point `p` of triangle `triangle` (primitive
    /// `primitive`) lies in a hole of the primitive's cut-out: its
    /// texture's alpha at `p` (at the texture's mean coverage without
    /// coordinates) below the cutoff.
    #[inline]
    pub fn is_hole(&self, primitive: u32, triangle: &Triangle, p: Vec3) -> bool {
        let Some((binding, texture)) = self.binding(primitive) else {
            return false;
        };
        let Some(cutout) = binding.cutout else {
            return false;
        };
        let alpha = match binding.uvs {
            Some(uvs) => texture.alpha(interpolate(uvs, triangle, p)),
            None => texture.mean_alpha(),
        };
        cutout.is_hole(alpha)
    }

    /// Whether any primitive is textured.
    pub fn is_used(&self) -> bool {
        !self.bindings.is_empty()
    }

    /// The texture colour at the point `p` of triangle `triangle`
    /// (primitive `primitive`), if it is textured: the texture looked up
    /// at the corners' coordinates interpolated.
    #[inline]
    pub fn at(&self, primitive: u32, triangle: &Triangle, p: Vec3) -> Option<Rgb> {
        let (binding, texture) = self.binding(primitive)?;
        let Some(uvs) = binding.uvs else {
            return Some(texture.mean());
        };
        Some(texture.lookup(interpolate(uvs, triangle, p)))
    }

    /// Primitive `primitive`'s binding and its texture, if it is textured.
    #[inline]
    fn binding(&self, primitive: u32) -> Option<(Binding, &Texture)> {
        let slot = *self.slot.get(primitive as usize)?;
        if slot == NONE {
            return None;
        }
        let binding = self.bindings[slot as usize];
        Some((binding, &self.textures[binding.texture as usize]))
    }
}

/// The texture coordinates at the point `p` of `triangle`, interpolated
/// from its corners' `uvs` by [`Triangle::corner_weights`].
#[inline]
fn interpolate([t0, t1, t2]: [Vec2; 3], triangle: &Triangle, p: Vec3) -> Vec2 {
    let [b0, b1, b2] = triangle.corner_weights(p);
    t0 * b0 + t1 * b1 + t2 * b2
}
