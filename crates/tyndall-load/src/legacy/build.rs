//! Phase 3 of reading a legacy file: the [`SceneDesc`] of its statements
//! and cutoff reading — materials, quads (spots where an emissive face
//! has a cutoff, area lights where it has none), triangles for faces that
//! are not parallelograms, spheres, the camera (a default one if the file
//! has none) and the render settings the paper used; then the
//! description's own validation, located in the file.

use super::LegacyOptions;
use super::cutoffs::CutoffReading;
use super::statements::{SphereStatement, Statements};
use crate::source::{SceneError, SourceText};
use glam::Vec3;
use std::path::Path;
use std::sync::Arc;
use tyndall::camera::{Aperture, CameraSpec, FieldOfView};
use tyndall::color::Rgb;
use tyndall::description::{LightDesc, Origin, SceneDesc, Sourced};
use tyndall::glass::{Glass, GlassModel};
use tyndall::lights::{SpotLight, SpotProfile};
use tyndall::limits;
use tyndall::materials::{Material, Surface};
use tyndall::settings::{IntegratorKind, RenderSettings};
use tyndall::shapes::{Bounds, Quad, Shape, Triangle};

/// Phase 3: builds the scene description. Quads are one-sided unless
/// `options.two_sided`.
pub(super) fn build(
    statements: Statements,
    cutoffs: CutoffReading,
    source: &SourceText,
    options: LegacyOptions,
) -> Result<SceneDesc, SceneError> {
    let Statements {
        vertices,
        materials,
        faces,
        spheres,
        cutoffs: _,
        background,
        camera,
    } = statements;
    let CutoffReading {
        face_cutoff,
        mut warnings,
    } = cutoffs;
    let camera = match camera {
        Some(c) => c,
        None => {
            let camera = default_camera(&vertices, &spheres);
            // Far from the origin a small scene's offset camera can round
            // onto its target (issue 11: every ray NaN, a black image).
            camera.check().map_err(|m| {
                source.error(format!(
                    "the default camera (the file has no `PerspectiveCamera`) cannot be placed: {m}; give a `PerspectiveCamera`"
                ))
            })?;
            camera
        }
    };
    let file: Arc<Path> = Arc::from(source.path.as_path());
    let at = |offset: usize| {
        let (line, column) = source.line_col(offset);
        Origin::Location {
            file: file.clone(),
            line,
            column,
        }
    };
    let mut desc = SceneDesc::new(Sourced::new(
        camera,
        Origin::Element {
            file: file.clone(),
            path: "PerspectiveCamera".into(),
        },
    ));
    desc.background = background;
    desc.glass.model = GlassModel::Blend;
    let one_sided = !options.two_sided;
    let ids: Vec<u32> = materials
        .iter()
        .map(|m| {
            let material = if m.emitted.max_element() > 0.0 {
                Material::emitter(m.emitted, !one_sided)
            } else if m.alpha < 1.0 {
                Material::Glass(Glass {
                    color: m.diffuse.min(Rgb::ONE),
                    alpha: m.alpha,
                })
            } else {
                Material::Opaque(Surface::layered(m.diffuse, m.reflective, m.roughness))
            };
            desc.add_material(material, at(m.offset))
        })
        .collect();
    if materials.iter().any(|m| m.textured) {
        warnings.push(format!(
            "{}: texture files are not supported; textured materials are drawn mid-grey",
            source.path.display()
        ));
    }
    // The lamp-face material of each emissive material used by spots.
    let mut lamp_ids: Vec<Option<u32>> = vec![None; materials.len()];
    for (face, cutoff) in faces.iter().zip(&face_cutoff) {
        let m = &materials[face.material];
        let c = face.vertices.map(|i| vertices[i]);
        let offset = face.offset;
        let quad = Quad::from_corners(c, one_sided);
        if m.emitted.max_element() > 0.0 {
            let quad = quad.map_err(|e| source.error_at(offset, format!("emissive face: {e}")))?;
            match *cutoff {
                Some(cutoff) => {
                    // The spot's intensity is radiance × area (W/sr).
                    let intensity = m.emitted * quad.area();
                    limits::check_emission(
                        "the spotlight's intensity (`emitted` × face area)",
                        intensity,
                    )
                    .map_err(|e| source.error_at(offset, format!("emissive face: {e}")))?;
                    // The quad is the lamp seen by the camera; the spot
                    // carries its light into the scene (counted once).
                    let lamp = *lamp_ids[face.material].get_or_insert_with(|| {
                        let lamp = Material::LampFace {
                            radiance: m.emitted,
                        };
                        desc.add_material(lamp, at(m.offset))
                    });
                    desc.add_shapes(vec![Shape::Quad(quad)], lamp, at(offset));
                    let spot = SpotLight {
                        gobo: None,
                        luminaire: None,
                        position: quad.centroid(),
                        direction: quad.normal,
                        cos_cutoff: cutoff.to_radians().cos(),
                        profile: SpotProfile::Linear,
                        intensity,
                    };
                    desc.add_light(LightDesc::Spot(spot), at(offset));
                }
                None => desc.add_quad_light(quad, m.emitted, !one_sided, at(offset)),
            }
            continue;
        }
        match quad {
            Ok(q) => desc.add_shapes(vec![Shape::Quad(q)], ids[face.material], at(offset)),
            Err(_) => {
                // A planar or non-planar general quad: two triangles.
                let make = if one_sided {
                    Triangle::new_one_sided
                } else {
                    Triangle::new
                };
                let tris = [make(c[0], c[1], c[2]), make(c[0], c[2], c[3])];
                if tris.iter().all(Option::is_none) {
                    return Err(source.error_at(
                        offset,
                        "the face has no area (its vertices are collinear or repeated)",
                    ));
                }
                let triangles = tris.into_iter().flatten().map(Shape::Triangle).collect();
                desc.add_shapes(triangles, ids[face.material], at(offset));
            }
        }
    }
    for s in &spheres {
        desc.add_shapes(vec![Shape::Sphere(s.sphere)], ids[s.material], at(s.offset));
    }
    desc.settings = RenderSettings {
        integrator: IntegratorKind::March,
        ..RenderSettings::default()
    };
    if let Some(e) = source.locate_all(&desc.errors()) {
        return Err(e);
    }
    warnings.extend(desc.lighting_warnings());
    desc.warnings = warnings;
    Ok(desc)
}

/// The legacy format (docs/scene-format.md): without a camera, look at the centre of the scene's
/// bounds from 4 × its largest dimension along +z, 20° field of view.
fn default_camera(vertices: &[Vec3], spheres: &[SphereStatement]) -> CameraSpec {
    let bounds = vertices.iter().fold(Bounds::EMPTY, |b, v| b.include(*v));
    let bounds = spheres
        .iter()
        .fold(bounds, |b, s| b.union(s.sphere.bounds()));
    let (center, size) = if bounds.is_empty() {
        (Vec3::ZERO, 1.0)
    } else {
        (bounds.center(), bounds.extent().max_element().max(1e-3))
    };
    CameraSpec {
        position: center + Vec3::Z * (4.0 * size),
        look_at: center,
        up: Vec3::Y,
        fov: FieldOfView::ShorterSide(20.0),
        aperture: Aperture::Pinhole,
    }
}

#[cfg(test)]
mod tests {
    use super::super::statements::{Face, LegacyMaterial};
    use super::*;
    use tyndall::shapes::Sphere;

    fn square() -> Vec<Vec3> {
        vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ]
    }

    fn statements(emitted: f32) -> Statements {
        Statements {
            vertices: square(),
            materials: vec![LegacyMaterial {
                diffuse: Rgb::splat(0.5),
                emitted: Rgb::splat(emitted),
                alpha: 1.0,
                ..Default::default()
            }],
            faces: vec![Face {
                vertices: [0, 1, 2, 3],
                material: 0,
                statements: 0,
                offset: 0,
            }],
            spheres: vec![SphereStatement {
                sphere: Sphere {
                    center: Vec3::new(0.5, 0.5, 2.0),
                    radius: 0.25,
                },
                material: 0,
                offset: 0,
            }],
            ..Default::default()
        }
    }

    fn reading(cutoff: Option<f32>) -> CutoffReading {
        CutoffReading {
            face_cutoff: vec![cutoff],
            warnings: vec!["a warning".into()],
        }
    }

    fn source() -> SourceText {
        SourceText::new("t.obj", "f 1 2 3 4\n")
    }

    #[test]
    fn an_emissive_face_with_a_cutoff_is_a_lamp_face_and_a_spot() {
        let desc = build(
            statements(2.0),
            reading(Some(30.0)),
            &source(),
            LegacyOptions::default(),
        )
        .expect("valid");
        assert_eq!(desc.lights.len(), 1);
        let LightDesc::Spot(spot) = &desc.lights[0].value else {
            panic!("a spot: {:?}", desc.lights[0].value);
        };
        assert!((spot.cos_cutoff - 30f32.to_radians().cos()).abs() < 1e-6);
        assert_eq!(spot.position, Vec3::new(0.5, 0.5, 0.0));
        assert_eq!(spot.intensity, Rgb::splat(2.0));
        assert!(
            desc.materials
                .iter()
                .any(|m| matches!(m.value, Material::LampFace { .. }))
        );
        assert_eq!(desc.warnings.first().map(String::as_str), Some("a warning"));
        assert_eq!(desc.settings.integrator, IntegratorKind::March);
        assert_eq!(desc.glass.model, GlassModel::Blend);
    }

    #[test]
    fn a_dark_face_is_a_quad_and_the_default_camera_looks_at_the_bounds() {
        let desc = build(
            statements(0.0),
            reading(None),
            &source(),
            LegacyOptions::default(),
        )
        .expect("valid");
        assert!(desc.lights.is_empty());
        assert_eq!(desc.shapes.len(), 2);
        assert!(matches!(desc.shapes[0].shapes[0], Shape::Quad(_)));
        assert!(matches!(desc.shapes[1].shapes[0], Shape::Sphere(_)));
        let camera = desc.camera.value;
        // Bounds [0, 1]² × [0, 2.25]: centre (0.5, 0.5, 1.125), size 2.25.
        assert_eq!(camera.look_at, Vec3::new(0.5, 0.5, 1.125));
        assert_eq!(camera.position, Vec3::new(0.5, 0.5, 1.125 + 9.0));
    }

    #[test]
    fn a_face_without_area_is_an_error_at_the_face() {
        let mut s = statements(0.0);
        s.vertices = vec![Vec3::ZERO; 4];
        let e = build(s, reading(None), &source(), LegacyOptions::default()).expect_err("an error");
        assert_eq!((e.line, e.column), (1, 1));
        assert!(e.message.contains("no area"), "{}", e.message);
    }
}
