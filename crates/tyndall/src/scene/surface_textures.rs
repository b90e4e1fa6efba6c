//! Textures bound to mesh triangles: which colour texture multiplies a
//! primitive's diffuse reflectance, and its texture coordinates at the
//! triangle's corners, interpolated by barycentric weights; the alpha
//! coverage ([`Coverage`]) that makes holes in them; tangent-space normal maps
//! ([`crate::description::NormalMap`]) that bend the shading normal; and
//! glTF metallic-roughness surfaces evaluated point by point
//! ([`crate::description::MetallicRoughnessMap`]).

use crate::color::Rgb;
use crate::coverage::{self, Coverage};
use crate::footprint::Footprint;
use crate::materials::MetallicRoughness;
use crate::ray::Ray;
use crate::shapes::Triangle;
use crate::texture::{Texture, TextureId};
use glam::{Vec2, Vec3, Vec4};
use std::sync::Arc;

/// Values bound to some primitives, found by primitive index: a slot per
/// primitive up to the last bound one, so that scenes without bindings
/// store nothing.
#[derive(Debug)]
struct PerPrimitive<T> {
    /// Per primitive, its index in `values` or [`NONE`].
    slot: Vec<u32>,
    values: Vec<T>,
}

impl<T> Default for PerPrimitive<T> {
    fn default() -> Self {
        Self {
            slot: Vec::new(),
            values: Vec::new(),
        }
    }
}

impl<T> PerPrimitive<T> {
    fn insert(&mut self, primitive: u32, value: T) {
        let index = primitive as usize;
        if self.slot.len() <= index {
            self.slot.resize(index + 1, NONE);
        }
        self.slot[index] = self.values.len() as u32;
        self.values.push(value);
    }

    #[inline]
    fn get(&self, primitive: u32) -> Option<&T> {
        let slot = *self.slot.get(primitive as usize)?;
        (slot != NONE).then(|| &self.values[slot as usize])
    }

    fn is_empty(&self) -> bool {
        self.values.is_empty()
    }
}

/// A primitive's texture and its corners' texture coordinates (`None`:
/// the texture's mean colour).
#[derive(Clone, Copy, Debug)]
struct Binding {
    texture: TextureId,
    uvs: Option<[Vec2; 3]>,
}

/// A primitive's coverage rule and the texture whose alpha it reads, with
/// the corners' coordinates (`None`: the texture's mean coverage), if it
/// has one.
#[derive(Clone, Copy, Debug)]
struct CoverageBinding {
    rule: Coverage,
    alpha: Option<(TextureId, Option<[Vec2; 3]>)>,
}

/// A primitive's normal map: its texture, its corners' coordinates, its
/// scale, and its tangent frame.
#[derive(Clone, Copy, Debug)]
struct NormalBinding {
    texture: TextureId,
    uvs: [Vec2; 3],
    scale: f32,
    frame: TangentFrame,
}

/// Where a normal map's tangent frame comes from (see
/// [`crate::description::NormalMap`]).
#[derive(Clone, Copy, Debug)]
enum TangentFrame {
    /// The corners' tangents (xyz) and handedness (w), interpolated.
    Corners([Vec4; 3]),
    /// The triangle's own `∂P/∂u` and `−∂P/∂v`, before they are made
    /// perpendicular to the shading normal.
    Triangle { tangent: Vec3, bitangent: Vec3 },
}

/// A primitive's metallic-roughness surface: its factors, and its
/// texture with the corners' coordinates, if it has one.
#[derive(Clone, Copy, Debug)]
struct MetallicRoughnessBinding {
    factors: MetallicRoughness,
    texture: Option<(TextureId, [Vec2; 3])>,
}

/// The textures of a scene and the primitives they are bound to.
#[derive(Debug, Default)]
pub(crate) struct SurfaceTextures {
    textures: Vec<Arc<Texture>>,
    colours: PerPrimitive<Binding>,
    coverage: PerPrimitive<CoverageBinding>,
    normal_maps: PerPrimitive<NormalBinding>,
    metallic_roughness: PerPrimitive<MetallicRoughnessBinding>,
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
        self.colours.insert(primitive, Binding { texture, uvs });
    }

    /// Binds the coverage `rule` to primitive `primitive`, on the alpha of
    /// its colour texture if it is bound one that has alpha ([`Self::bind`]
    /// first).
    pub fn bind_coverage(&mut self, primitive: u32, rule: Coverage) {
        let alpha = self
            .colours
            .get(primitive)
            .filter(|b| self.textures[b.texture as usize].has_alpha())
            .map(|b| (b.texture, b.uvs));
        self.coverage
            .insert(primitive, CoverageBinding { rule, alpha });
    }

    /// Binds a metallic-roughness surface of `factors` to primitive
    /// `primitive`, with its texture at the corners' coordinates if given.
    pub fn bind_metallic_roughness(
        &mut self,
        primitive: u32,
        factors: MetallicRoughness,
        texture: Option<(TextureId, [Vec2; 3])>,
    ) {
        self.metallic_roughness
            .insert(primitive, MetallicRoughnessBinding { factors, texture });
    }

    /// The metallic-roughness parameters at the point `p` of `triangle`
    /// (primitive `primitive`), if it has them: its factors, the metalness
    /// times the texture's blue channel and the roughness times its green
    /// there (read as data, filtered over `footprint`), where it has a
    /// texture. The base colour is the factor's alone; the caller
    /// multiplies it by the point's colour.
    #[inline]
    pub fn metallic_roughness_at(
        &self,
        primitive: u32,
        triangle: &Triangle,
        p: Vec3,
        footprint: Footprint,
    ) -> Option<MetallicRoughness> {
        let binding = self.metallic_roughness.get(primitive)?;
        let mut parameters = binding.factors;
        if let Some((texture, uvs)) = binding.texture
            && let Some(c) = lookup_data(
                &self.textures[texture as usize],
                triangle,
                uvs,
                p,
                footprint,
            )
        {
            parameters.roughness *= c.y;
            parameters.metallic *= c.z;
        }
        Some(parameters)
    }

    /// Binds a normal map to `triangle` (primitive `primitive`): `texture`
    /// at the corners' coordinates `uvs`, its x and y times `scale`, in
    /// the frame of the corners' `tangents` if given. Without them, a
    /// triangle whose coordinates do not span the plane (no tangent frame)
    /// is left without.
    pub fn bind_normal_map(
        &mut self,
        primitive: u32,
        triangle: &Triangle,
        texture: TextureId,
        uvs: [Vec2; 3],
        scale: f32,
        tangents: Option<[Vec4; 3]>,
    ) {
        let frame = match tangents {
            Some(corners) => TangentFrame::Corners(corners),
            None => {
                // e1 = T·Δu₁ + P_v·Δv₁ and e2 = T·Δu₂ + P_v·Δv₂, solved
                // for the surface's derivatives T = ∂P/∂u and P_v = ∂P/∂v.
                let (d1, d2) = (uvs[1] - uvs[0], uvs[2] - uvs[0]);
                let det = d1.x * d2.y - d2.x * d1.y;
                let tangent = (triangle.e1 * d2.y - triangle.e2 * d1.y) / det;
                let along_v = (triangle.e2 * d1.x - triangle.e1 * d2.x) / det;
                if !(det != 0.0 && tangent.is_finite() && along_v.is_finite()) {
                    return;
                }
                TangentFrame::Triangle {
                    tangent,
                    bitangent: -along_v,
                }
            }
        };
        self.normal_maps.insert(
            primitive,
            NormalBinding {
                texture,
                uvs,
                scale,
                frame,
            },
        );
    }

    /// The shading normal at the point `p` of `triangle` (primitive
    /// `primitive`) bent by its normal map, if it has one (filtered over
    /// `footprint`), from the unbent unit normal `n` (see
    /// [`crate::description::NormalMap`]); `None` where the map leaves no
    /// direction (a zero vector, a vector into the surface, or a tangent
    /// along `n`).
    #[inline]
    pub fn normal_at(
        &self,
        primitive: u32,
        triangle: &Triangle,
        p: Vec3,
        n: Vec3,
        footprint: Footprint,
    ) -> Option<Vec3> {
        let binding = self.normal_maps.get(primitive)?;
        let texture = &self.textures[binding.texture as usize];
        let c = lookup_data(texture, triangle, binding.uvs, p, footprint)?;
        let m = (c * 2.0 - Vec3::ONE) * Vec3::new(binding.scale, binding.scale, 1.0);
        // A texel whose vector points into the surface bends nothing.
        if m.z <= 0.0 {
            return None;
        }
        let (t, b) = match binding.frame {
            TangentFrame::Corners(corners) => {
                // MikkTSpace's own use: the tangent interpolated as it
                // is, the bitangent w·(n × T) from it, the sum normalised
                // once. The handedness is the triangle's (one per
                // triangle where the frame is not split across it).
                let [w0, w1, w2] = triangle.corner_weights(p);
                let t = (corners[0] * w0 + corners[1] * w1 + corners[2] * w2).truncate();
                (t, n.cross(t) * corners[0].w)
            }
            TangentFrame::Triangle { tangent, bitangent } => {
                // Gram–Schmidt: the tangent made perpendicular to n, and
                // the bitangent n × T on the side the triangle's −∂P/∂v
                // lies.
                let t = (tangent - n * n.dot(tangent)).try_normalize()?;
                let b = n.cross(t);
                (t, if b.dot(bitangent) < 0.0 { -b } else { b })
            }
        };
        (t * m.x + b * m.y + n * m.z).try_normalize()
    }

    /// Whether some primitive has alpha coverage.
    pub fn has_coverage(&self) -> bool {
        !self.coverage.is_empty()
    }

    /// Whether `ray` passes triangle `triangle` (primitive `primitive`)
    /// where it meets it, at distance `t`: by the primitive's coverage
    /// rule ([`Coverage::passes`]) on its texture's alpha at that point
    /// (at the texture's mean coverage without coordinates), with the
    /// number [`coverage::ray_number`] gives the ray and the primitive.
    #[inline]
    pub fn passes(&self, primitive: u32, triangle: &Triangle, ray: &Ray, t: f32) -> bool {
        let Some(binding) = self.coverage.get(primitive) else {
            return false;
        };
        let alpha = match binding.alpha {
            Some((texture, uvs)) => {
                let texture = &self.textures[texture as usize];
                match uvs {
                    Some(uvs) => texture.alpha(triangle.uv_at(uvs, ray.at(t))),
                    None => texture.mean_alpha(),
                }
            }
            None => 1.0,
        };
        let u = match binding.rule.is_stochastic() {
            true => coverage::ray_number(ray, primitive),
            false => 0.0,
        };
        binding.rule.passes(alpha, u)
    }

    /// Whether any primitive is textured, normal-mapped or has a
    /// metallic-roughness surface.
    pub fn is_used(&self) -> bool {
        !(self.colours.is_empty()
            && self.normal_maps.is_empty()
            && self.metallic_roughness.is_empty())
    }

    /// The texture colour at the point `p` of triangle `triangle`
    /// (primitive `primitive`), if it is textured: the texture looked up
    /// at the corners' coordinates interpolated, filtered over
    /// `footprint`.
    #[inline]
    pub fn at(
        &self,
        primitive: u32,
        triangle: &Triangle,
        p: Vec3,
        footprint: Footprint,
    ) -> Option<Rgb> {
        let (binding, texture) = self.binding(primitive)?;
        let Some(uvs) = binding.uvs else {
            return Some(texture.mean());
        };
        let lod = footprint.level_of_detail((texture.width(), texture.height()), triangle, uvs);
        Some(texture.lookup_lod(triangle.uv_at(uvs, p), lod))
    }

    /// Primitive `primitive`'s binding and its texture, if it is textured.
    #[inline]
    fn binding(&self, primitive: u32) -> Option<(Binding, &Texture)> {
        let binding = *self.colours.get(primitive)?;
        Some((binding, &self.textures[binding.texture as usize]))
    }
}

/// `texture` read as data at the point `p` of `triangle`, whose corners
/// map it by `uvs`, filtered over `footprint`.
#[inline]
fn lookup_data(
    texture: &Texture,
    triangle: &Triangle,
    uvs: [Vec2; 3],
    p: Vec3,
    footprint: Footprint,
) -> Option<Vec3> {
    let lod = footprint.level_of_detail((texture.width(), texture.height()), triangle, uvs);
    texture.lookup_data(triangle.uv_at(uvs, p), lod)
}
