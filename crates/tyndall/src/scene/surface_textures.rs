//! Colour textures bound to mesh triangles: which texture multiplies a
//! primitive's diffuse reflectance, and its texture coordinates at the
//! triangle's corners, interpolated by barycentric weights.

use crate::color::Rgb;
use crate::shapes::Triangle;
use crate::texture::{Texture, TextureId};
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// A primitive's texture and its corners' texture coordinates (`None`:
/// the texture's mean colour).
#[derive(Clone, Copy, Debug)]
struct Binding {
    texture: TextureId,
    uvs: Option<[Vec2; 3]>,
}

/// The textures of a scene and the primitives they are bound to.
#[derive(Debug, Default)]
pub(crate) struct SurfaceTextures {
    textures: Vec<Arc<Texture>>,
    /// Per primitive, its index in `bindings` or [`NONE`]; empty while no
    /// primitive is textured.
    slot: Vec<u32>,
    bindings: Vec<Binding>,
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
    /// coordinates `uvs`.
    pub fn bind(&mut self, primitive: u32, texture: TextureId, uvs: Option<[Vec2; 3]>) {
        let index = primitive as usize;
        if self.slot.len() <= index {
            self.slot.resize(index + 1, NONE);
        }
        self.slot[index] = self.bindings.len() as u32;
        self.bindings.push(Binding { texture, uvs });
    }

    /// Whether any primitive is textured.
    pub fn is_used(&self) -> bool {
        !self.bindings.is_empty()
    }

    /// The texture colour at the point `p` of triangle `triangle`
    /// (primitive `primitive`), if it is textured: the texture looked up
    /// at the corners' coordinates interpolated (weights clamped to the
    /// triangle against rounding at its edges).
    #[inline]
    pub fn at(&self, primitive: u32, triangle: &Triangle, p: Vec3) -> Option<Rgb> {
        let slot = *self.slot.get(primitive as usize)?;
        if slot == NONE {
            return None;
        }
        let binding = self.bindings[slot as usize];
        let texture = &self.textures[binding.texture as usize];
        let Some([t0, t1, t2]) = binding.uvs else {
            return Some(texture.mean());
        };
        let (b1, b2) = triangle.barycentric(p);
        let (b1, b2) = (b1.clamp(0.0, 1.0), b2.clamp(0.0, 1.0));
        let b0 = (1.0 - b1 - b2).max(0.0);
        Some(texture.lookup(t0 * b0 + t1 * b1 + t2 * b2))
    }
}
