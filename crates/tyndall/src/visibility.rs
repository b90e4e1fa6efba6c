//! Visibility between a point and a light: opaque occlusion and the tint
//! of the glass crossed on the way (the paper's §4.5).
//!
//! [`Visibility`] is the one place the integrators ask "how much of this
//! light's radiance gets here past the geometry". Today it casts a shadow
//! ray through the BVH; a shadow-map backend can answer the same question
//! per light from a depth and a transmittance map.

use crate::accel::Geometry;
use crate::color::Rgb;
use crate::glass::{Glass, GlassModel};
use crate::lights::Incident;
use crate::materials::Material;
use crate::ray::{Ray, shadow_ray_end};
use glam::Vec3;
use std::ops::ControlFlow;

/// How visibility towards lights is computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Visibility {
    /// Exact: a shadow ray through the BVH per query.
    #[default]
    ShadowRays,
}

/// Counts of rays traced, for the end-of-render statistics.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    pub camera: u64,
    pub shadow: u64,
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.camera + self.shadow
    }
}

/// Most glass crossings a blend-model shadow ray orders on the stack;
/// more spill to the heap.
const INLINE_PANES: usize = 16;

impl Visibility {
    /// The fraction of light reaching `origin` along `incident` past
    /// geometry: 0 if an opaque surface is in the way, otherwise the glass
    /// tint of the panes crossed under `model`. `origin` must already be
    /// offset off any surface it lies on. Fog is not included.
    pub fn transmittance(
        &self,
        geometry: &Geometry,
        materials: &[Material],
        model: GlassModel,
        origin: Vec3,
        incident: &Incident,
        counts: &mut RayCounts,
    ) -> Rgb {
        match self {
            Visibility::ShadowRays => {
                counts.shadow += 1;
                shadow_ray(geometry, materials, model, origin, incident)
            }
        }
    }
}

fn shadow_ray(
    geometry: &Geometry,
    materials: &[Material],
    model: GlassModel,
    origin: Vec3,
    incident: &Incident,
) -> Rgb {
    let ray = Ray {
        origin,
        direction: incident.direction,
    };
    let t_max = if incident.distance.is_finite() {
        shadow_ray_end(incident.distance)
    } else {
        f32::INFINITY
    };
    let mut filter = Rgb::ONE;
    let mut inline: [(f32, Glass); INLINE_PANES] = [(0.0, NO_GLASS); INLINE_PANES];
    let mut spilled: Vec<(f32, Glass)> = Vec::new();
    let mut count = 0usize;
    let mut blocked = false;
    geometry.for_each_hit(&ray, t_max, |t, index| {
        match &materials[geometry.primitive(index).material as usize] {
            Material::Glass(glass) => match model {
                GlassModel::Filter => filter *= glass.filter_transmittance(),
                GlassModel::Blend => {
                    if count < INLINE_PANES {
                        inline[count] = (t, *glass);
                    } else {
                        spilled.push((t, *glass));
                    }
                    count += 1;
                }
            },
            Material::Opaque(_) | Material::Emissive { .. } => {
                blocked = true;
                return ControlFlow::Break(());
            }
        }
        ControlFlow::Continue(())
    });
    if blocked {
        return Rgb::ZERO;
    }
    match model {
        GlassModel::Filter => filter,
        GlassModel::Blend => {
            let mut panes: Vec<(f32, Glass)>;
            let panes: &mut [(f32, Glass)] = if count <= INLINE_PANES {
                &mut inline[..count]
            } else {
                panes = inline.to_vec();
                panes.append(&mut spilled);
                &mut panes
            };
            // Light meets the pane farthest from `origin` first.
            panes.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
            model.tint(panes.iter().map(|(_, g)| g))
        }
    }
}

const NO_GLASS: Glass = Glass {
    color: Rgb::ONE,
    alpha: 0.0,
};
