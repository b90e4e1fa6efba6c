//! `type = "triangles"` shapes: a mesh written into the scene itself as
//! flat arrays, as a program that builds scenes in memory (the Blender
//! add-on, `tyndall.Scene.from_dict`) gives it without a file.

use super::Loader;
use super::principled::BaseColorTexture;
use super::tables::{InlineMeshTable, NumberArray, TrianglesTable};
use crate::mesh::MAX_TRIANGLES;
use crate::source::SceneError;
use glam::{Vec2, Vec3};
use std::borrow::Cow;
use std::ops::Range;
use tyndall::description::{MeshAttributes, MetallicRoughnessMap, SurfaceTexture};
use tyndall::limits::check_coordinates;
use tyndall::shapes::Triangle;

/// A 32-bit number from its four little-endian bytes.
trait FromLittleEndian {
    fn from_le_bytes(bytes: [u8; 4]) -> Self;
}

impl FromLittleEndian for f32 {
    fn from_le_bytes(bytes: [u8; 4]) -> Self {
        f32::from_le_bytes(bytes)
    }
}

impl FromLittleEndian for u32 {
    fn from_le_bytes(bytes: [u8; 4]) -> Self {
        u32::from_le_bytes(bytes)
    }
}

/// The flat arrays of a mesh written into the scene (see
/// [`Loader::triangles`]).
struct TriangleArrays<'a> {
    positions: &'a [f32],
    indices: &'a [u32],
    normals: Option<&'a [f32]>,
    uvs: Option<&'a [f32]>,
}

impl Loader<'_> {
    /// The triangles of a `triangles` table spanning `span` and their
    /// per-corner attributes: `positions` (x, y, z per vertex), `indices`
    /// (three vertex numbers per triangle, counter-clockwise seen from
    /// the front), optional unit `normals` (x, y, z per vertex: smooth
    /// shading) and `uvs` (u, v per vertex, v down from the image's top
    /// row as glTF's), with `texture`, the material's base colour texture,
    /// bound at the `uvs`. Zero-area triangles are dropped with a warning.
    pub(super) fn triangles(
        &mut self,
        span: &Range<usize>,
        table: &TrianglesTable,
        texture: Option<BaseColorTexture>,
    ) -> Result<(Vec<Triangle>, MeshAttributes), SceneError> {
        let TrianglesTable {
            positions,
            indices,
            normals,
            uvs,
            ..
        } = table;
        let positions = self.numbers(span, "positions", positions)?;
        let indices = self.numbers(span, "indices", indices)?;
        let normals = normals
            .as_ref()
            .map(|n| self.numbers(span, "normals", n))
            .transpose()?;
        let uvs = uvs
            .as_ref()
            .map(|u| self.numbers(span, "uvs", u))
            .transpose()?;
        let arrays = TriangleArrays {
            positions: &positions,
            indices: &indices,
            normals: normals.as_deref(),
            uvs: uvs.as_deref(),
        };
        self.triangle_arrays(span, arrays, texture)
    }

    /// The numbers of a flat array, written in the text or given beside
    /// it (`"@array:K"`, [`super::parse_with_arrays`]); `key` names it in
    /// errors.
    fn numbers<'t, T: Copy + FromLittleEndian>(
        &self,
        span: &Range<usize>,
        key: &str,
        array: &'t NumberArray<T>,
    ) -> Result<Cow<'t, [T]>, SceneError> {
        let name = match array {
            NumberArray::Inline(values) => return Ok(Cow::Borrowed(values)),
            NumberArray::Beside(name) => name,
        };
        let index = name
            .strip_prefix("@array:")
            .and_then(|k| k.parse::<usize>().ok())
            .ok_or_else(|| {
                self.err(
                    span,
                    key,
                    format!("`{key}` is a string \"{name}\": give numbers, or \"@array:K\" for an array given beside the text"),
                )
            })?;
        let bytes = self.arrays.get(index).ok_or_else(|| {
            self.err(
                span,
                key,
                format!(
                    "`{key}` names array {index}, and {} were given",
                    self.arrays.len()
                ),
            )
        })?;
        if bytes.len() % 4 != 0 {
            return Err(self.err(
                span,
                key,
                format!(
                    "array {index} holds {} bytes, not whole 32-bit numbers",
                    bytes.len()
                ),
            ));
        }
        Ok(Cow::Owned(
            bytes
                .chunks_exact(4)
                .map(|c| T::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect(),
        ))
    }

    /// The triangles of a medium's inline `mesh` region (no attributes).
    pub(super) fn region_triangles(
        &mut self,
        span: &Range<usize>,
        table: &InlineMeshTable,
    ) -> Result<Vec<Triangle>, SceneError> {
        let positions = self.numbers(span, "positions", &table.positions)?;
        let indices = self.numbers(span, "indices", &table.indices)?;
        let arrays = TriangleArrays {
            positions: &positions,
            indices: &indices,
            normals: None,
            uvs: None,
        };
        Ok(self.triangle_arrays(span, arrays, None)?.0)
    }

    /// [`Self::triangles`] from the arrays themselves.
    fn triangle_arrays(
        &mut self,
        span: &Range<usize>,
        arrays: TriangleArrays,
        texture: Option<BaseColorTexture>,
    ) -> Result<(Vec<Triangle>, MeshAttributes), SceneError> {
        let fail = |key: &str, m: String| self.err(span, key, m);
        let TriangleArrays {
            positions,
            indices,
            normals,
            uvs,
        } = arrays;
        if positions.len() % 3 != 0 {
            return Err(fail(
                "positions",
                format!(
                    "`positions` holds three numbers per vertex, got {}",
                    positions.len()
                ),
            ));
        }
        let vertices = positions.len() / 3;
        if indices.len() % 3 != 0 || indices.is_empty() {
            return Err(fail(
                "indices",
                format!(
                    "`indices` holds three vertex numbers per triangle (at least one), got {}",
                    indices.len()
                ),
            ));
        }
        if indices.len() as u64 / 3 > MAX_TRIANGLES {
            return Err(fail(
                "indices",
                format!("at most {MAX_TRIANGLES} triangles are supported"),
            ));
        }
        let per_vertex = |key: &str, values: Option<&[f32]>, n: usize| match values {
            Some(v) if v.len() != n * vertices => Err(fail(
                key,
                format!(
                    "`{key}` holds {n} numbers per vertex ({} for {vertices} vertices), got {}",
                    n * vertices,
                    v.len()
                ),
            )),
            _ => Ok(()),
        };
        per_vertex("normals", normals, 3)?;
        per_vertex("uvs", uvs, 2)?;
        let vertex =
            |i: usize| Vec3::new(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
        for i in 0..vertices {
            check_coordinates(&format!("vertex {i}"), vertex(i))
                .map_err(|m| fail("positions", m))?;
        }
        if let Some(i) = indices.iter().position(|&i| i as usize >= vertices) {
            return Err(fail(
                "indices",
                format!(
                    "index {i} is vertex {}, and there are {vertices} vertices",
                    indices[i]
                ),
            ));
        }
        let normal = |i: usize| -> Option<Result<Vec3, SceneError>> {
            normals.as_ref().map(|n| {
                Vec3::new(n[3 * i], n[3 * i + 1], n[3 * i + 2])
                    .try_normalize()
                    .ok_or_else(|| fail("normals", format!("normal {i} is zero or not finite")))
            })
        };
        let uv = |i: usize| uvs.as_ref().map(|u| Vec2::new(u[2 * i], u[2 * i + 1]));
        let mut triangles = Vec::with_capacity(indices.len() / 3);
        let mut attributes = MeshAttributes::default();
        let mut corner_uvs = Vec::new();
        let mut skipped = 0;
        for corners in indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| corners[k] as usize);
            let Some(t) = Triangle::new(vertex(a), vertex(b), vertex(c)) else {
                skipped += 1;
                continue;
            };
            triangles.push(t);
            if let (Some(na), Some(nb), Some(nc)) = (normal(a), normal(b), normal(c)) {
                attributes.vertex_normals.push([na?, nb?, nc?]);
            }
            if let (Some(ua), Some(ub), Some(uc)) = (uv(a), uv(b), uv(c)) {
                if !(ua.is_finite() && ub.is_finite() && uc.is_finite()) {
                    return Err(fail("uvs", "`uvs` must be finite numbers".into()));
                }
                corner_uvs.push([ua, ub, uc]);
            }
        }
        if triangles.is_empty() {
            return Err(fail(
                "indices",
                "every triangle has zero area: the shape has none to draw".into(),
            ));
        }
        if let Some(BaseColorTexture { texture, factors }) = texture {
            if uvs.is_none() {
                return Err(fail(
                    "material",
                    "its material has a `base_color_texture`: give the shape `uvs`".into(),
                ));
            }
            attributes.texture = Some(SurfaceTexture {
                texture,
                uvs: corner_uvs,
            });
            // A textured metal's specular colour follows its texture, as
            // the glTF loader binds it.
            if factors.metallic > 0.0 {
                attributes.metallic_roughness = Some(MetallicRoughnessMap {
                    factors,
                    texture: None,
                    uvs: Vec::new(),
                });
            }
        }
        if skipped > 0 {
            self.warnings.push(format!(
                "{}: a `triangles` shape: skipped {skipped} degenerate triangles",
                self.source.path.display()
            ));
        }
        Ok((triangles, attributes))
    }
}
