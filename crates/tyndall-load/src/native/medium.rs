//! `[[media]]` tables: general media (RGB extinction, densities from noise,
//! `.tgrid` voxel grids or OpenVDB grids, regions bounded by a box or a
//! mesh), and their emission (a colour times a field, blackbody emission
//! from a temperature grid: docs/physics.md §2.5).

use super::Loader;
use super::tables::{MediumMesh, MediumTable};
use crate::source::SceneError;
use glam::Vec3;
use serde_spanned::Spanned;
use tyndall::color::Rgb;
use tyndall::description::{MediumDesc, RegionDesc};
use tyndall::media::emission::{Blackbody, BlackbodyLaw, Emission};
use tyndall::media::noise::SmokeNoise;
use tyndall::media::sparse::{SparseDensity, SparseGrid};
use tyndall::media::volume::Density;
use tyndall::phase::PhaseFunction;
use tyndall::shapes::Bounds;

impl Loader<'_> {
    /// A `[[media]]` volume.
    pub(super) fn medium(&mut self, desc: &Spanned<MediumTable>) -> Result<MediumDesc, SceneError> {
        let span = desc.span();
        let m = desc.get_ref();
        let (sigma_t, albedo) = (Rgb::from_array(m.sigma_t.0), Rgb::from_array(m.albedo.0));
        let placement = (m.translate, m.scale, m.rotate_deg);
        let placed = m.translate.is_some() || m.scale.is_some() || m.rotate_deg.is_some();
        let kind = m.density.as_deref().unwrap_or("uniform");
        let mesh_file = matches!(m.mesh, Some(MediumMesh::File(_)));
        if !mesh_file && placed && kind != "vdb" {
            let key = if m.translate.is_some() {
                "translate"
            } else if m.scale.is_some() {
                "scale"
            } else {
                "rotate_deg"
            };
            return Err(self.err(
                &span,
                key,
                format!("`{key}` places a `mesh` file or a \"vdb\" density; this medium has neither (an inline `mesh` is in world coordinates)"),
            ));
        }
        // An OpenVDB grid, placed: its index-to-world transform, then the
        // medium's translate/scale/rotate_deg.
        let vdb = if kind == "vdb" {
            let name = m.grid.as_deref().unwrap_or("density");
            Some(self.vdb_file_grid(&span, m, "file", name)?)
        } else {
            None
        };
        for (key, given) in [
            ("emission_grid", m.emission_grid.is_some()),
            ("temperature_grid", m.temperature_grid.is_some()),
        ] {
            if given && vdb.is_none() {
                return Err(self.err(
                    &span,
                    key,
                    format!("`{key}` names another grid of a density \"vdb\" medium's file; this medium's density is \"{kind}\""),
                ));
            }
        }
        for (key, given) in [
            ("temperature_scale", m.temperature_scale.is_some()),
            ("temperature_offset", m.temperature_offset.is_some()),
            ("blackbody_intensity", m.blackbody_intensity.is_some()),
            ("blackbody_law", m.blackbody_law.is_some()),
            ("blackbody_tint", m.blackbody_tint.is_some()),
        ] {
            if given && m.temperature_grid.is_none() {
                return Err(self.err(
                    &span,
                    key,
                    format!("`{key}` applies to blackbody emission, which needs `temperature_grid = \"…\"`"),
                ));
            }
        }
        if m.emission_grid.is_some() && m.emission.is_none() {
            return Err(self.err(
                &span,
                "emission_grid",
                "`emission_grid` scales an `emission = [r, g, b]` colour, which this medium lacks",
            ));
        }
        if m.grid.is_some() && vdb.is_none() {
            return Err(self.err(&span, "grid", "`grid` applies to density \"vdb\" only"));
        }
        let region = match (&m.bounds, &m.mesh) {
            (Some(_), Some(_)) => {
                return Err(self.err(&span, "mesh", "give a medium a `box` or a `mesh`, not both"));
            }
            (Some(b), None) => RegionDesc::Box(self.bounds(&span, "box", b.min, b.max)?),
            (None, Some(MediumMesh::File(file))) => {
                RegionDesc::Mesh(self.mesh(&span, "mesh", file, placement)?.triangles)
            }
            (None, Some(MediumMesh::Inline(table))) => {
                RegionDesc::Mesh(self.region_triangles(&span, table)?)
            }
            (None, None) => match &vdb {
                Some((grid, world)) => {
                    RegionDesc::Box(vdb_world_bounds(grid, *world).ok_or_else(|| {
                        self.err(
                            &span,
                            "file",
                            "the grid has no active voxels: nothing to render",
                        )
                    })?)
                }
                None => RegionDesc::Everywhere,
            },
        };
        let misplaced = |key: &str, given: bool| {
            if given {
                Err(self.err(
                    &span,
                    key,
                    format!("`{key}` does not apply to density \"{kind}\""),
                ))
            } else {
                Ok(())
            }
        };
        let noise_keys = [
            ("frequency", m.frequency.is_some()),
            ("octaves", m.octaves.is_some()),
            ("bias", m.bias.is_some()),
            ("seed", m.seed.is_some()),
        ];
        let density = match kind {
            "uniform" => {
                misplaced("file", m.file.is_some())?;
                for (key, given) in noise_keys {
                    misplaced(key, given)?;
                }
                Density::Uniform
            }
            "noise" => {
                misplaced("file", m.file.is_some())?;
                Density::Noise(SmokeNoise {
                    frequency: self.number(
                        &span,
                        "frequency",
                        m.frequency.unwrap_or(3.0),
                        (0.01, 1024.0),
                        "between 0.01 and 1024 lattice cells across the box",
                    )?,
                    octaves: match m.octaves.unwrap_or(5) {
                        o @ 1..=8 => o,
                        o => {
                            return Err(self.err(
                                &span,
                                "octaves",
                                format!("`octaves` must be between 1 and 8, got {o}"),
                            ));
                        }
                    },
                    bias: self.number(
                        &span,
                        "bias",
                        m.bias.unwrap_or(0.0),
                        (-1.0, 1.0),
                        "in [−1, 1]",
                    )?,
                    seed: m.seed.unwrap_or(1),
                })
            }
            "grid" => {
                for (key, given) in noise_keys {
                    misplaced(key, given)?;
                }
                let file = m.file.as_ref().ok_or_else(|| {
                    self.err(
                        &span,
                        "density",
                        "density \"grid\" needs `file = \"….tgrid\"`",
                    )
                })?;
                let path = self.data_file(&span, "file", file)?;
                let grid = crate::tgrid::read(&path).map_err(|e| self.err(&span, "file", e))?;
                Density::Grid(grid)
            }
            "vdb" => {
                for (key, given) in noise_keys {
                    misplaced(key, given)?;
                }
                let (grid, world) = vdb.expect("read above for density \"vdb\"");
                // A vdb medium has a box or a mesh (from the grid's
                // active voxels if not given).
                let unit_to_index = self.unit_to_index(&span, "file", &region, world)?;
                Density::Sparse(Box::new(SparseDensity {
                    grid,
                    unit_to_index,
                }))
            }
            other => {
                return Err(self.err(
                    &span,
                    "density",
                    format!(
                        "unknown density \"{other}\": expected \"uniform\", \"noise\", \"grid\" or \"vdb\""
                    ),
                ));
            }
        };
        // Another grid of the file as a field in the medium's unit cube,
        // placed like the density.
        let field = |key: &str, name: &str| -> Result<Density, SceneError> {
            let (grid, world) = self.vdb_file_grid(&span, m, key, name)?;
            Ok(Density::Sparse(Box::new(SparseDensity {
                grid,
                unit_to_index: self.unit_to_index(&span, key, &region, world)?,
            })))
        };
        let emission = if m.emission.is_some() || m.temperature_grid.is_some() {
            let color = match m.emission {
                Some(c) => self.emission(&span, "emission", c)?,
                None => Rgb::ZERO,
            };
            let field_grid = match &m.emission_grid {
                Some(name) => Some(field("emission_grid", name)?),
                None => None,
            };
            let law = match (m.blackbody_law.as_deref(), m.blackbody_tint) {
                (None | Some("kirchhoff"), None) => BlackbodyLaw::Kirchhoff,
                (None | Some("kirchhoff"), Some(_)) => {
                    return Err(self.err(
                        &span,
                        "blackbody_tint",
                        "`blackbody_tint` applies to `blackbody_law = \"cycles\"` (Kirchhoff's law has no tint: its colour is the absorption's)",
                    ));
                }
                (Some("cycles"), tint) => BlackbodyLaw::Cycles {
                    tint: match tint {
                        Some(c) => self.emission(&span, "blackbody_tint", c)?,
                        None => Rgb::ONE,
                    },
                },
                (Some(other), _) => {
                    return Err(self.err(
                        &span,
                        "blackbody_law",
                        format!("unknown blackbody law \"{other}\": expected \"kirchhoff\" (σa·B(T), the default) or \"cycles\" (Cycles' Principled Volume)"),
                    ));
                }
            };
            let blackbody = match &m.temperature_grid {
                Some(name) => Some(Blackbody {
                    temperature: field("temperature_grid", name)?,
                    scale: m.temperature_scale.unwrap_or(1.0),
                    offset: m.temperature_offset.unwrap_or(0.0),
                    intensity: m.blackbody_intensity.unwrap_or(1.0),
                    law,
                }),
                None => None,
            };
            Some(Emission {
                color,
                field: field_grid,
                blackbody,
            })
        } else {
            None
        };
        Ok(MediumDesc {
            sigma_t,
            albedo,
            phase: PhaseFunction::from_asymmetry(m.g),
            density,
            region,
            emission,
            origin: self.origin(&span),
        })
    }

    /// Grid `name` of the medium's VDB `file` and its placed
    /// index-to-world transform; errors name `key`.
    fn vdb_file_grid(
        &self,
        span: &std::ops::Range<usize>,
        m: &MediumTable,
        key: &str,
        name: &str,
    ) -> Result<(SparseGrid, glam::Mat4), SceneError> {
        let file = m
            .file
            .as_ref()
            .ok_or_else(|| self.err(span, "density", "density \"vdb\" needs `file = \"….vdb\"`"))?;
        let path = self.data_file(span, "file", file)?;
        let grid = crate::vdb_grid(&path, name).map_err(|e| self.err(span, key, e))?;
        let placement = (m.translate, m.scale, m.rotate_deg);
        let world = self.placement(span, placement)?.matrix() * grid.index_to_world();
        Ok((grid, world))
    }

    /// The map from a medium's unit cube (its region's bounds) to the
    /// index space of a grid placed at `world`.
    fn unit_to_index(
        &self,
        span: &std::ops::Range<usize>,
        key: &str,
        region: &RegionDesc,
        world: glam::Mat4,
    ) -> Result<glam::Mat4, SceneError> {
        let field_box = region.bounds();
        let unit_to_world = glam::Mat4::from_scale_rotation_translation(
            field_box.extent(),
            glam::Quat::IDENTITY,
            field_box.min,
        );
        let unit_to_index = world.inverse() * unit_to_world;
        if !unit_to_index.is_finite() {
            return Err(self.err(
                span,
                key,
                "the grid's transform (with the medium's placement) cannot be inverted",
            ));
        }
        Ok(unit_to_index)
    }
}

/// World bounds of a sparse grid's active voxels (their cells, half a
/// voxel around the outermost centres) under `world`; `None` if empty.
fn vdb_world_bounds(grid: &SparseGrid, world: glam::Mat4) -> Option<Bounds> {
    let (lo, hi) = grid.active_bounds()?;
    let (lo, hi) = (lo.as_vec3() - 0.5, hi.as_vec3() + 0.5);
    let mut b = Bounds::EMPTY;
    for k in 0..8 {
        let corner = Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        b = b.include(world.transform_point3(corner));
    }
    Some(b)
}
