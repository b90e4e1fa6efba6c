//! Triangle primitives (glTF 2.0 §3.7.2): accessors checked, then read
//! into triangles placed by their node's world matrix, with their vertex
//! normals and base colour texture coordinates.

use super::GltfLoader;
use super::materials::UvTransform;
use super::tangents::{self, TangentInput};
use crate::source::SceneError;
use ::gltf::mesh::Mode;
use ::gltf::{Accessor, Semantic};
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use tyndall::color::Rgb;
use tyndall::description::{
    EmissionMap, MeshAttributes, MetallicRoughnessMap, NormalMap, SceneDesc, SurfaceTexture,
};
use tyndall::materials::Material;
use tyndall::shapes::Triangle;

impl GltfLoader<'_> {
    /// A primitive's `TANGENT`s, one per vertex, placed by the node's
    /// `world` matrix: the tangent as a direction along the surface, the
    /// handedness (the sign of w) flipped by a mirroring matrix, which
    /// turns `N × T` against the bitangent the file's frame has.
    fn file_tangents(
        &self,
        element: &str,
        tangents: impl Iterator<Item = [f32; 4]>,
        world: Mat4,
        vertices: usize,
    ) -> Result<Vec<Vec4>, SceneError> {
        let linear = Mat3::from_mat4(world);
        let flip = world.determinant().signum();
        let tangents: Vec<Vec4> = tangents
            .map(|[x, y, z, w]| (linear * Vec3::new(x, y, z)).extend(w.signum() * flip))
            .collect();
        if tangents.len() != vertices {
            return Err(self.err(
                element,
                format!(
                    "TANGENT has {} entries but POSITION has {vertices}",
                    tangents.len()
                ),
            ));
        }
        Ok(tangents)
    }

    /// Checks that an accessor holds `dimensions` × f32 or integer data
    /// as expected, naming `element` in the error.
    fn check_accessor(
        &self,
        element: &str,
        what: &str,
        accessor: &Accessor,
        dimensions: ::gltf::accessor::Dimensions,
        float: bool,
    ) -> Result<(), SceneError> {
        use ::gltf::accessor::DataType;
        let type_ok = if float {
            accessor.data_type() == DataType::F32
        } else {
            matches!(
                accessor.data_type(),
                DataType::U8 | DataType::U16 | DataType::U32
            )
        };
        if accessor.dimensions() != dimensions || !type_ok {
            return Err(self.err(
                element,
                format!(
                    "{what} must be {dimensions:?} of {}, got {:?} of {:?}",
                    if float { "floats" } else { "unsigned integers" },
                    accessor.dimensions(),
                    accessor.data_type()
                ),
            ));
        }
        if accessor.count() == 0 {
            return Err(self.err(element, format!("{what} is empty")));
        }
        Ok(())
    }

    pub(super) fn mesh(
        &mut self,
        mesh: &::gltf::Mesh,
        world: Mat4,
        scene: &mut SceneDesc,
    ) -> Result<(), SceneError> {
        // A mirroring transform reverses the winding, and with it the
        // front face (glTF §3.7.4): swap two corners to keep it.
        let mirrored = world.determinant() < 0.0;
        // Normals transform by the inverse transpose (glTF §3.7.2.1 asks
        // for unit normals; they are renormalised after it).
        let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
        for primitive in mesh.primitives() {
            let element = format!("meshes[{}].primitives[{}]", mesh.index(), primitive.index());
            if primitive.mode() != Mode::Triangles {
                return Err(self.err(
                    &element,
                    format!(
                        "primitive mode {:?} is not supported: only triangles (mode 4) are",
                        primitive.mode()
                    ),
                ));
            }
            let positions_accessor = primitive
                .get(&Semantic::Positions)
                .ok_or_else(|| self.err(&element, "the primitive has no POSITION attribute"))?;
            self.check_accessor(
                &element,
                "POSITION",
                &positions_accessor,
                ::gltf::accessor::Dimensions::Vec3,
                true,
            )?;
            if let Some(indices) = primitive.indices() {
                self.check_accessor(
                    &element,
                    "the indices",
                    &indices,
                    ::gltf::accessor::Dimensions::Scalar,
                    false,
                )?;
            }
            if let Some(normals) = primitive.get(&Semantic::Normals) {
                self.check_accessor(
                    &element,
                    "NORMAL",
                    &normals,
                    ::gltf::accessor::Dimensions::Vec3,
                    true,
                )?;
            }
            if let Some(tangents) = primitive.get(&Semantic::Tangents) {
                self.check_accessor(
                    &element,
                    "TANGENT",
                    &tangents,
                    ::gltf::accessor::Dimensions::Vec4,
                    true,
                )?;
            }
            let (material, textures) = self.material_id(&primitive.material(), scene)?;
            let base_texture = textures.base;
            if self
                .hidden_materials
                .contains(&primitive.material().index())
            {
                continue;
            }
            let mut triangles = Vec::new();
            let buffers = &self.buffers;
            let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
            let positions: Vec<Vec3> = reader
                .read_positions()
                .ok_or_else(|| {
                    self.err(
                        &element,
                        "cannot read POSITION: its accessor lies outside its buffer",
                    )
                })?
                .map(|p| world.transform_point3(Vec3::from_array(p)))
                .collect();
            // Vertex normals, for shading; a primitive without them is
            // flat-shaded (glTF §3.7.2.1).
            let normals: Option<Vec<Vec3>> = match reader.read_normals() {
                Some(normals) => Some(
                    normals
                        .map(|n| (normal_matrix * Vec3::from_array(n)).normalize_or_zero())
                        .collect(),
                ),
                None if primitive.get(&Semantic::Normals).is_some() => {
                    return Err(self.err(
                        &element,
                        "cannot read NORMAL: its accessor lies outside its buffer",
                    ));
                }
                None => None,
            };
            if let Some(normals) = &normals
                && normals.len() != positions.len()
            {
                return Err(self.err(
                    &element,
                    format!(
                        "NORMAL has {} entries but POSITION has {}",
                        normals.len(),
                        positions.len()
                    ),
                ));
            }
            // The file's tangents, where a normal map needs them.
            let file_tangents = match reader.read_tangents() {
                Some(tangents) if textures.normal.is_some() => {
                    Some(self.file_tangents(&element, tangents, world, positions.len())?)
                }
                None if primitive.get(&Semantic::Tangents).is_some() => {
                    return Err(self.err(
                        &element,
                        "cannot read TANGENT: its accessor lies outside its buffer",
                    ));
                }
                _ => None,
            };
            // A texture's coordinates (its TEXCOORD_n set, transformed):
            // `Err(n)` where the primitive has no set n.
            let read_coords = |set: u32, transform: UvTransform| {
                let Some(coords) = reader.read_tex_coords(set) else {
                    return Ok(Err(set));
                };
                let coords: Vec<[f32; 2]> =
                    coords.into_f32().map(|uv| transform.apply(uv)).collect();
                if coords.len() != positions.len() {
                    return Err(self.err(
                        &element,
                        format!(
                            "TEXCOORD_{set} has {} entries but POSITION has {}",
                            coords.len(),
                            positions.len()
                        ),
                    ));
                }
                Ok(Ok(coords))
            };
            // The base colour texture's coordinates, if the material has
            // one, the normal map's and the emission texture's.
            let base_coords = base_texture
                .map(|t| read_coords(t.tex_coord, t.transform))
                .transpose()?;
            let normal_coords = textures
                .normal
                .map(|m| read_coords(m.map.tex_coord, m.map.transform))
                .transpose()?;
            let emission_coords = textures
                .emission
                .map(|m| read_coords(m.tex_coord, m.transform))
                .transpose()?;
            let pbr_coords = textures
                .metallic_roughness
                .and_then(|m| m.map)
                .map(|m| read_coords(m.tex_coord, m.transform))
                .transpose()?;
            let tex_coords = base_coords.as_ref().and_then(|c| c.as_ref().ok());
            let map_coords = normal_coords.as_ref().and_then(|c| c.as_ref().ok());
            let glow_coords = emission_coords.as_ref().and_then(|c| c.as_ref().ok());
            let pbr_uvs = pbr_coords.as_ref().and_then(|c| c.as_ref().ok());
            // Vertex colours (COLOR_0, linear, glTF §3.7.2.1), which
            // multiply the base colour: of an opaque surface's diffuse
            // reflectance here.
            let mut colour_warning = None;
            let colours: Option<Vec<Rgb>> = match reader.read_colors(0) {
                Some(colours) => {
                    let colours: Vec<Rgb> = colours.into_rgb_f32().map(Rgb::from_array).collect();
                    if colours.len() != positions.len() {
                        return Err(self.err(
                            &element,
                            format!(
                                "COLOR_0 has {} entries but POSITION has {}",
                                colours.len(),
                                positions.len()
                            ),
                        ));
                    }
                    if colours.iter().any(|c| {
                        !(c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0)
                    }) {
                        return Err(self.err(&element, "COLOR_0 values must be in [0, 1]"));
                    }
                    match scene.materials[material as usize].value {
                        // A metallic-roughness surface is coloured whole.
                        _ if textures.metallic_roughness.is_some() => Some(colours),
                        Material::Opaque(surface) | Material::Emissive { surface, .. }
                            if surface.diffuse != Rgb::ZERO =>
                        {
                            if surface.specular != Rgb::ZERO {
                                colour_warning = Some(
                                    "COLOR_0 colours the diffuse reflectance only, not the specular",
                                );
                            }
                            Some(colours)
                        }
                        _ => {
                            colour_warning = Some(
                                "COLOR_0 is ignored: the material has no diffuse reflectance to colour",
                            );
                            None
                        }
                    }
                }
                None if primitive.get(&Semantic::Colors(0)).is_some() => {
                    return Err(self.err(
                        &element,
                        "cannot read COLOR_0: its accessor lies outside its buffer",
                    ));
                }
                None => None,
            };
            let mut kept = Vec::new();
            let mut corner_uvs = Vec::new();
            let mut corner_normal_uvs = Vec::new();
            let mut corner_emission_uvs = Vec::new();
            let mut corner_pbr_uvs = Vec::new();
            let mut corner_colours = Vec::new();
            let mut corner_normals = Vec::new();
            let indices: Vec<u32> = match primitive.indices() {
                Some(_) => reader
                    .read_indices()
                    .ok_or_else(|| {
                        self.err(
                            &element,
                            "cannot read the indices: their accessor lies outside its buffer",
                        )
                    })?
                    .into_u32()
                    .collect(),
                None => (0..positions.len() as u32).collect(),
            };
            if !indices.len().is_multiple_of(3) {
                return Err(self.err(
                    &element,
                    format!("{} vertices do not form whole triangles", indices.len()),
                ));
            }
            for (t, corners) in indices.chunks_exact(3).enumerate() {
                let vertex = |i: u32| {
                    positions.get(i as usize).copied().ok_or_else(|| {
                        self.err(
                            &element,
                            format!(
                                "triangle {t} refers to vertex {i}, but POSITION has {} vertices",
                                positions.len()
                            ),
                        )
                    })
                };
                let (a, mut b, mut c) = (
                    vertex(corners[0])?,
                    vertex(corners[1])?,
                    vertex(corners[2])?,
                );
                if !(a.is_finite() && b.is_finite() && c.is_finite()) {
                    return Err(self.err(&element, "vertex positions must be finite"));
                }
                let mut order = [corners[0], corners[1], corners[2]];
                if mirrored {
                    std::mem::swap(&mut b, &mut c);
                    order.swap(1, 2);
                }
                match Triangle::new(a, b, c) {
                    Some(triangle) => {
                        self.bounds = self.bounds.union(triangle.bounds());
                        let corners = |coords: &Vec<[f32; 2]>| {
                            order.map(|i| Vec2::from_array(coords[i as usize]))
                        };
                        corner_uvs.extend(tex_coords.map(corners));
                        corner_normal_uvs.extend(map_coords.map(corners));
                        corner_emission_uvs.extend(glow_coords.map(corners));
                        corner_pbr_uvs.extend(pbr_uvs.map(corners));
                        if let Some(colours) = &colours {
                            corner_colours.push(order.map(|i| colours[i as usize]));
                        }
                        if let Some(normals) = &normals {
                            let corner = |i: u32| normals[i as usize];
                            let n = order.map(corner);
                            if n.contains(&Vec3::ZERO) {
                                return Err(self.err(
                                    &element,
                                    format!("triangle {t} has a zero or non-finite NORMAL"),
                                ));
                            }
                            corner_normals.push(n);
                        }
                        triangles.push(triangle);
                        kept.push(order);
                    }
                    None => self.skipped_degenerate += 1,
                }
            }
            if let Some(warning) = colour_warning {
                self.warn(&element, warning);
            }
            for (coords, texture, outcome) in [
                (
                    &base_coords,
                    "baseColorTexture",
                    "the texture's mean colour applies",
                ),
                (&normal_coords, "normalTexture", "it is not applied"),
                (
                    &emission_coords,
                    "emissiveTexture",
                    "it is not applied: the surface emits emissiveFactor",
                ),
                (
                    &pbr_coords,
                    "metallicRoughnessTexture",
                    "it is not applied: the factors hold everywhere",
                ),
            ] {
                if let Some(Err(n)) = coords {
                    self.warn(
                        &element,
                        format!(
                            "the material's {texture} uses TEXCOORD_{n}, which the primitive \
                             does not have: {outcome}"
                        ),
                    );
                }
            }
            let origin = self.origin(element);
            let texture = base_texture.map(|t| SurfaceTexture {
                texture: t.texture,
                uvs: corner_uvs,
            });
            let normal_map = match (textures.normal, map_coords) {
                (Some(normal), Some(_)) => {
                    let tangents = match &file_tangents {
                        Some(tangents) => kept
                            .iter()
                            .map(|order| order.map(|i| tangents[i as usize]))
                            .collect(),
                        None => tangents::mikktspace(&TangentInput {
                            positions: &kept
                                .iter()
                                .map(|order| order.map(|i| positions[i as usize]))
                                .collect::<Vec<_>>(),
                            normals: &corner_normals,
                            uvs: &corner_normal_uvs,
                        }),
                    };
                    Some(NormalMap {
                        texture: normal.map.texture,
                        uvs: corner_normal_uvs,
                        scale: normal.scale,
                        tangents,
                    })
                }
                _ => None,
            };
            let emission_map = match (textures.emission, glow_coords) {
                (Some(map), Some(_)) => Some(EmissionMap {
                    texture: map.texture,
                    uvs: corner_emission_uvs,
                }),
                _ => None,
            };
            let metallic_roughness = textures.metallic_roughness.map(|m| {
                let texture = m.map.filter(|_| pbr_uvs.is_some()).map(|map| map.texture);
                MetallicRoughnessMap {
                    factors: m.factors,
                    texture,
                    uvs: if texture.is_some() {
                        corner_pbr_uvs
                    } else {
                        Vec::new()
                    },
                }
            });
            let attributes = MeshAttributes {
                vertex_normals: corner_normals,
                vertex_colours: corner_colours,
                texture,
                normal_map,
                emission_map,
                metallic_roughness,
                coverage: textures.coverage,
            };
            scene.add_mesh(triangles, attributes, material, origin);
        }
        Ok(())
    }
}
