//! Visibility between a point and a light: opaque occlusion and the tint
//! of the glass crossed on the way (the paper's §4.5).
//!
//! [`Visibility`] is the one place the integrators ask "how much of this
//! light's radiance gets here past the geometry": exactly, by a shadow ray
//! through the BVH, or fast, from per-light shadow and transmittance maps
//! ([`crate::shadow_maps`]) rendered once per frame.

use crate::color::Rgb;
use crate::glass::{Glass, GlassModel};
use crate::lights::Incident;
use crate::materials::Material;
use crate::ray::{Ray, shadow_ray_end};
use crate::scene::Scene;
use crate::shadow_maps::{MapScene, ShadowMaps};
use glam::Vec3;
use std::ops::ControlFlow;

pub use crate::settings::VisibilityMode;

/// Visibility ready for a render.
pub enum Visibility {
    ShadowRays,
    /// Per-light maps; area lights, which have none, use shadow rays.
    Maps(ShadowMaps),
}

/// Counts of rays traced and map lookups, for the end-of-render statistics.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Rays followed from the camera: camera rays and, for `volpath`, the
    /// path segments after them.
    pub camera: u64,
    pub shadow: u64,
    pub map_lookups: u64,
}

impl RayCounts {
    /// Rays traced (camera and shadow; map lookups are not rays).
    pub fn total(&self) -> u64 {
        self.camera + self.shadow
    }
}

/// Most glass crossings a blend-model shadow ray orders on the stack;
/// more spill to the heap.
const INLINE_PANES: usize = 16;

impl Visibility {
    /// Prepares visibility for `scene`: renders the maps if asked for.
    pub fn new(scene: &Scene, mode: VisibilityMode) -> Self {
        match mode {
            VisibilityMode::ShadowRays => Visibility::ShadowRays,
            VisibilityMode::Maps { resolution } => {
                let map_scene = MapScene {
                    geometry: &scene.geometry,
                    materials: &scene.materials,
                    model: scene.glass.model,
                };
                Visibility::Maps(ShadowMaps::build(&map_scene, &scene.lights, resolution))
            }
        }
    }

    /// The fraction of light `light` reaching `origin` along `incident`
    /// past geometry: 0 if an opaque surface is in the way, otherwise the
    /// glass tint of the panes crossed under the scene's glass model.
    /// `origin` must already be offset off any surface it lies on, whose
    /// normal is `normal` (`None` in fog), and `incident.distance` measured
    /// from it. Fog is not included.
    pub fn transmittance(
        &self,
        scene: &Scene,
        light: usize,
        origin: Vec3,
        normal: Option<Vec3>,
        incident: &Incident,
        counts: &mut RayCounts,
    ) -> Rgb {
        if let Visibility::Maps(maps) = self
            && let Some(t) = maps.transmittance(light, origin, normal, incident.direction)
        {
            counts.map_lookups += 1;
            return t;
        }
        counts.shadow += 1;
        shadow_ray(scene, origin, incident, scene.light_primitive(light))
    }
}

/// The glass tint along the segment from `origin` (already offset off
/// any surface) over `distance` along unit `direction`, 0 if an opaque
/// surface is in the way: a shadow ray to a point that is no light's
/// (a point of an emitting medium). Always traced: shadow maps are made
/// for lights.
pub(crate) fn segment_transmittance(
    scene: &Scene,
    origin: Vec3,
    direction: Vec3,
    distance: f32,
    counts: &mut RayCounts,
) -> Rgb {
    counts.shadow += 1;
    let incident = Incident {
        direction,
        distance,
        irradiance: Rgb::ONE,
        light_normal: None,
    };
    shadow_ray(scene, origin, &incident, None)
}

/// Hits of a light's own geometry past this fraction of a shadow ray
/// towards it do not block it. A ray that meets a curved emitter (a
/// sphere) near its silhouette meets it at a distance known only to
/// about √ε of the radius in f32, which the end margin of
/// [`shadow_ray_end`] cannot cover; on the way to a point of a convex
/// emitter's visible side, the emitter itself is met only there.
const OWN_HIT_FRACTION: f32 = 0.999;

/// The glass tint along `incident` from `origin`, 0 if an opaque surface
/// is in the way; hits of `own` (the light's own primitive) near the end
/// and the holes of alpha cut-outs are passed.
fn shadow_ray(scene: &Scene, origin: Vec3, incident: &Incident, own: Option<u32>) -> Rgb {
    let (geometry, materials, model) = (&scene.geometry, &scene.materials, scene.glass.model);
    let coverage = scene.has_coverage();
    let ray = Ray {
        origin,
        direction: incident.direction,
    };
    let t_max = if incident.distance.is_finite() {
        shadow_ray_end(origin, incident.direction, incident.distance)
    } else {
        f32::INFINITY
    };
    let mut filter = Rgb::ONE;
    let mut inline: [(f32, Glass); INLINE_PANES] = [(0.0, NO_GLASS); INLINE_PANES];
    let mut spilled: Vec<(f32, Glass)> = Vec::new();
    let mut count = 0usize;
    let mut blocked = false;
    geometry.for_each_hit(&ray, t_max, |t, index| {
        if own == Some(index) && t > OWN_HIT_FRACTION * t_max {
            return ControlFlow::Continue(());
        }
        if coverage && scene.passes(index, &ray, t) {
            return ControlFlow::Continue(());
        }
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
            Material::Opaque(_)
            | Material::Emissive { .. }
            | Material::LampFace { .. }
            | Material::Dielectric { .. } => {
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
