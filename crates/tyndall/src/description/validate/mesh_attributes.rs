//! Validation of what a mesh carries per triangle corner: texture
//! coordinates and their colour texture, a normal map, an emission
//! texture, a metallic-roughness surface, vertex colours and vertex
//! normals; and its coverage.

use super::Item;
use crate::coverage::Coverage;
use crate::description::{
    DescError, EmissionMap, MetallicRoughnessMap, NormalMap, SceneDesc, ShapeDesc, SurfaceTexture,
};
use glam::{Vec2, Vec3, Vec4};

impl SceneDesc {
    /// The shape's per-corner attributes, each checked against its
    /// triangles.
    pub(super) fn validate_mesh_attributes(
        &self,
        shape: &ShapeDesc,
        item: &Item,
    ) -> Result<(), DescError> {
        if let Some(texture) = &shape.texture {
            self.validate_texture(shape, texture, item)?;
        }
        if let Some(map) = &shape.normal_map {
            self.validate_normal_map(shape, map, item)?;
        }
        if let Some(map) = &shape.emission_map {
            self.validate_emission_map(shape, map, item)?;
        }
        if let Some(map) = &shape.metallic_roughness {
            self.validate_metallic_roughness(shape, map, item)?;
        }
        if let Some(coverage) = shape.coverage {
            validate_coverage(shape, coverage, item)?;
        }
        let colour = |c: Vec3| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0;
        validate_corners(
            shape,
            &shape.vertex_colours,
            ("vertex-colour", "vertex colours", "colors"),
            item,
            colour,
            |t, _| format!("triangle {t} has a vertex colour outside [0, 1]"),
        )?;
        let unit = |n: Vec3| n.is_finite() && (n.length() - 1.0).abs() < 1e-3;
        validate_corners(
            shape,
            &shape.vertex_normals,
            ("vertex-normal", "vertex normals", "normals"),
            item,
            unit,
            |t, n| format!("triangle {t} has a vertex normal {n} that is not a unit vector"),
        )
    }

    /// A normal map names a texture of the scene, has one finite
    /// coordinate triple per triangle and a finite scale.
    fn validate_normal_map(
        &self,
        shape: &ShapeDesc,
        map: &NormalMap,
        item: &Item,
    ) -> Result<(), DescError> {
        item.exists(
            "normal_map",
            "normal map texture",
            map.texture,
            self.textures.len(),
        )?;
        if !shape.is_mesh() {
            return item.fail("normal_map", "only triangle meshes have normal maps".into());
        }
        if !map.scale.is_finite() {
            return item.fail(
                "normal_map",
                format!("the normal map's scale must be finite, got {}", map.scale),
            );
        }
        corner_uvs(shape, &map.uvs, "normal-map coordinate", "normal_map", item)?;
        if map.tangents.is_empty() {
            return Ok(());
        }
        per_triangle(shape, map.tangents.len(), "tangent", "normal_map", item)?;
        let valid =
            |t: &Vec4| t.is_finite() && t.truncate().length_squared() > 0.0 && t.w.abs() == 1.0;
        match map.tangents.iter().position(|c| !c.iter().all(valid)) {
            Some(t) => item.fail(
                "normal_map",
                format!(
                    "triangle {t} has a tangent that is not a finite non-zero vector with \
                     handedness ±1"
                ),
            ),
            None => Ok(()),
        }
    }

    /// An emission map names a texture of the scene, lies on an emissive
    /// mesh and has one finite coordinate triple per triangle.
    fn validate_emission_map(
        &self,
        shape: &ShapeDesc,
        map: &EmissionMap,
        item: &Item,
    ) -> Result<(), DescError> {
        item.exists(
            "emission_map",
            "emission texture",
            map.texture,
            self.textures.len(),
        )?;
        if !shape.is_mesh() {
            return item.fail(
                "emission_map",
                "only triangle meshes have emission textures".into(),
            );
        }
        if !self.is_emissive(shape.material) {
            return item.fail(
                "emission_map",
                "an emission texture needs an emissive material".into(),
            );
        }
        corner_uvs(
            shape,
            &map.uvs,
            "emission-texture coordinate",
            "emission_map",
            item,
        )
    }

    /// A metallic-roughness surface lies on a mesh, has its factors in
    /// range, and, with a texture, names a texture of the scene and has
    /// one finite coordinate triple per triangle.
    fn validate_metallic_roughness(
        &self,
        shape: &ShapeDesc,
        map: &MetallicRoughnessMap,
        item: &Item,
    ) -> Result<(), DescError> {
        const FIELD: &str = "metallic_roughness";
        if !shape.is_mesh() {
            return item.fail(
                FIELD,
                "only triangle meshes have metallic-roughness surfaces".into(),
            );
        }
        let f = &map.factors;
        let unit = |v: f32| (0.0..=1.0).contains(&v);
        for (name, colour) in [("base colour", f.base), ("f0", f.f0)] {
            if !(unit(colour.min_element()) && unit(colour.max_element())) {
                return item.fail(FIELD, format!("the {name} must be in [0, 1], got {colour}"));
            }
        }
        for (name, v) in [("metallic", f.metallic), ("roughness", f.roughness)] {
            if !unit(v) {
                return item.fail(
                    FIELD,
                    format!("the {name} factor must be in [0, 1], got {v}"),
                );
            }
        }
        let Some(texture) = map.texture else {
            return Ok(());
        };
        item.exists(
            FIELD,
            "metallic-roughness texture",
            texture,
            self.textures.len(),
        )?;
        corner_uvs(
            shape,
            &map.uvs,
            "metallic-roughness coordinate",
            FIELD,
            item,
        )
    }

    fn validate_texture(
        &self,
        shape: &ShapeDesc,
        texture: &SurfaceTexture,
        item: &Item,
    ) -> Result<(), DescError> {
        item.exists("texture", "texture", texture.texture, self.textures.len())?;
        if !shape.is_mesh() {
            return item.fail("texture", "only triangle meshes can be textured".into());
        }

        if texture.uvs.is_empty() {
            return Ok(());
        }
        corner_uvs(shape, &texture.uvs, "texture-coordinate", "uvs", item)
    }
}

/// Checks that a mesh attribute (`field`, `what` in the message) has
/// `count` entries, one per triangle.
fn per_triangle(
    shape: &ShapeDesc,
    count: usize,
    what: &str,
    field: &'static str,
    item: &Item,
) -> Result<(), DescError> {
    if count == shape.shapes.len() {
        return Ok(());
    }
    item.fail(
        field,
        format!(
            "{count} {what} triples for {} triangles: a mesh has one per triangle",
            shape.shapes.len()
        ),
    )
}

/// Checks a mesh attribute given per triangle corner (`names`: the
/// triples' name, the attribute's, and its field): none, or a triangle
/// mesh's one triple per triangle whose every value is `valid` (else the
/// message `invalid(triangle, value)`).
fn validate_corners(
    shape: &ShapeDesc,
    values: &[[Vec3; 3]],
    (triples, attribute, field): (&str, &str, &'static str),
    item: &Item,
    valid: impl Fn(Vec3) -> bool,
    invalid: impl Fn(usize, Vec3) -> String,
) -> Result<(), DescError> {
    if values.is_empty() {
        return Ok(());
    }
    if !shape.is_mesh() {
        return item.fail(field, format!("only triangle meshes have {attribute}"));
    }
    per_triangle(shape, values.len(), triples, field, item)?;
    for (t, corners) in values.iter().enumerate() {
        if let Some(&v) = corners.iter().find(|&&v| !valid(v)) {
            return item.fail(field, invalid(t, v));
        }
    }
    Ok(())
}

/// A coverage rule lies on a triangle mesh and its numbers are in
/// `[0, 1]`.
fn validate_coverage(shape: &ShapeDesc, coverage: Coverage, item: &Item) -> Result<(), DescError> {
    if !shape.is_mesh() {
        return item.fail(
            "coverage",
            "only triangle meshes have alpha coverage".into(),
        );
    }
    let numbers = match coverage {
        Coverage::Cutout { cutoff, factor } => [("cutoff", cutoff), ("coverage factor", factor)],
        Coverage::Partial { factor } => [("coverage factor", factor), ("coverage factor", factor)],
    };
    for (name, v) in numbers {
        if !(0.0..=1.0).contains(&v) {
            return item.fail(
                "coverage",
                format!("the alpha coverage's {name} must be in [0, 1], got {v}"),
            );
        }
    }
    Ok(())
}

/// Checks texture coordinates given per triangle corner (`what` the
/// triples' name, `field` theirs): one finite triple per triangle.
fn corner_uvs(
    shape: &ShapeDesc,
    uvs: &[[Vec2; 3]],
    what: &str,
    field: &'static str,
    item: &Item,
) -> Result<(), DescError> {
    per_triangle(shape, uvs.len(), what, field, item)?;
    match uvs.iter().position(|c| !c.iter().all(|uv| uv.is_finite())) {
        Some(t) => item.fail(
            field,
            format!("triangle {t} has texture coordinates that are not finite"),
        ),
        None => Ok(()),
    }
}
