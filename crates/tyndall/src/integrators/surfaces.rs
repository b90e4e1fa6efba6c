//! What a path does at a surface, shared by every integrator: where it
//! meets it and which way it faces, how deep inside solid dielectrics it
//! is, and the ray leaving a dielectric.

use crate::accel::Hit;
use crate::color::Rgb;
use crate::footprint::{Footprint, RayCone};
use crate::materials::{Interface, dielectric_scatter};
use crate::media::chromatic_transmittance;
use crate::ray::{Ray, offset_origin};
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use glam::Vec3;

/// Most glass panes a camera ray crosses before it is cut off (a guard
/// against degenerate scenes of stacked coincident panes).
pub const MAX_GLASS_CROSSINGS: u32 = 64;

/// How many solid dielectrics a path is inside, and what they absorb. A
/// solid displaces the media: no fog or volume exists inside glass, so
/// segments inside one are not in-scattering (where regions and solids
/// overlap, the solid wins); its own absorption
/// ([`crate::materials::Material::Dielectric`]) attenuates them.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SolidDepth {
    depth: u32,
    /// The absorption σa of the solids entered, innermost last (the first
    /// [`MAX_NESTED_SOLIDS`]; deeper ones count as the last of them).
    absorptions: [Rgb; MAX_NESTED_SOLIDS],
}

/// How many nested solids' absorptions a path keeps apart.
const MAX_NESTED_SOLIDS: usize = 4;

impl SolidDepth {
    pub fn inside(self) -> bool {
        self.depth > 0
    }

    /// Records a scattering at a dielectric with geometric normal `n`
    /// and inside absorption `absorption` from `incoming` to `outgoing`: a
    /// transmission into its front enters it, one out of its back leaves
    /// it.
    pub fn cross(&mut self, incoming: Vec3, outgoing: Vec3, n: Vec3, absorption: Rgb) {
        let (din, dout) = (incoming.dot(n), outgoing.dot(n));
        if din < 0.0 && dout < 0.0 {
            if let Some(slot) = self.absorptions.get_mut(self.depth as usize) {
                *slot = absorption;
            }
            self.depth += 1;
        } else if din > 0.0 && dout > 0.0 {
            self.depth = self.depth.saturating_sub(1);
        }
    }

    /// Beer–Lambert transmittance `exp(−σa·d)` over `distance` inside the
    /// innermost solid (1 outside any, and in a clear one even over an
    /// infinite distance).
    pub fn transmittance(self, distance: f32) -> Rgb {
        if self.depth == 0 {
            return Rgb::ONE;
        }
        let sigma = self.absorptions[(self.depth as usize - 1).min(MAX_NESTED_SOLIDS - 1)];
        chromatic_transmittance(sigma, distance)
    }
}

/// The ray leaving a solid dielectric's surface `interface` at `p`
/// (geometric normal `geometric_normal`) for `ray` arriving there: reflected or refracted with the Fresnel
/// probabilities (one sample dimension), its origin moved off the
/// surface; records entering or leaving the solid.
pub(crate) fn refract_or_reflect(
    ray: &Ray,
    p: Vec3,
    geometric_normal: Vec3,
    interface: Interface,
    sampler: &mut PixelSampler,
    solids: &mut SolidDepth,
) -> Ray {
    let direction = dielectric_scatter(
        ray.direction,
        geometric_normal,
        interface.ior,
        sampler.next_1d(),
    );
    solids.cross(
        ray.direction,
        direction,
        geometric_normal,
        interface.absorption,
    );
    Ray {
        origin: offset_origin(p, geometric_normal, direction),
        direction,
    }
}

/// Where a ray meets a surface: the point, the geometric normal, the
/// normals turned to face the arriving ray, whether the ray meets the
/// front (the side the geometric normal points to), and the footprint
/// over which its textures are filtered.
pub(crate) struct SurfaceHit {
    pub p: Vec3,
    pub geometric_normal: Vec3,
    pub normals: SurfaceNormals,
    pub front: bool,
    pub footprint: Footprint,
}

impl SurfaceHit {
    /// The surface `ray` meets at `hit`, its textures filtered over the
    /// footprint of the ray's `cone` there (a camera ray's, until the
    /// path scatters: [`crate::footprint`]), at full resolution without.
    pub fn new(scene: &Scene, ray: &Ray, hit: &Hit, cone: Option<RayCone>) -> Self {
        let p = ray.at(hit.t);
        let geometric_normal = scene.geometry.normal(hit.primitive, p);
        let cos = geometric_normal.dot(ray.direction);
        let front = cos < 0.0;
        let geometric = if front {
            geometric_normal
        } else {
            -geometric_normal
        };
        let footprint = cone.map_or(Footprint::POINT, |c| c.footprint(hit.t, cos));
        let shading = scene
            .shading_normal(hit.primitive, p, footprint)
            .map_or(geometric, |n| if n.dot(geometric) < 0.0 { -n } else { n });
        Self {
            p,
            geometric_normal,
            normals: SurfaceNormals { shading, geometric },
            front,
            footprint,
        }
    }
}

/// The normals of an opaque surface point, both turned to face the side a
/// path arrived from: `shading`, the mesh's vertex normals interpolated
/// (Phong 1975; `geometric` itself on flat shapes), orients the BSDF;
/// `geometric` decides which side a direction leaves on and offsets rays.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SurfaceNormals {
    pub shading: Vec3,
    pub geometric: Vec3,
}

impl SurfaceNormals {
    /// Both normals the geometric one (light paths, flat shapes).
    pub fn flat(geometric: Vec3) -> Self {
        Self {
            shading: geometric,
            geometric,
        }
    }

    /// Whether the unit direction `omega` leaves on the arrival side of
    /// both normals, the only directions an opaque surface scatters to.
    /// Above the shading normal but below the geometric surface a ray
    /// would pass through it and leak light (pbrt-v4 §10.1.1 discards
    /// such directions in the same way).
    #[inline]
    pub fn reflects(&self, omega: Vec3) -> bool {
        self.shading.dot(omega) > 0.0 && self.geometric.dot(omega) > 0.0
    }
}
