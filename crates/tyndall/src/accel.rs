//! The ray-intersection acceleration structure over all scene primitives.
//!
//! Wraps obvhs's compressed wide BVH (CWBVH, 8-wide; Ylitie et al. 2017)
//! built by PLOC with reinsertion, whose collapse to 8-wide nodes uses the
//! surface area heuristic. We use obvhs rather than our own BVH because it
//! was the fastest maintained option measured here: one thread, a
//! 100k-triangle soup, 1M rays, CWBVH 1.3 / 2.7 Mrays/s (incoherent /
//! coherent) against 0.8 / 2.3 for obvhs's binary BVH and 0.18 / 0.44 for
//! the `bvh` crate (Embree 3: 2.9 / 4.8). It stays behind this module so
//! another backend (Embree) can replace it.

use crate::materials::MaterialId;
use crate::ray::Ray;
use crate::shapes::{Bounds, Shape};
use glam::{UVec2, Vec3, Vec3A};
use obvhs::cwbvh::CwBvh;
use obvhs::{Boundable, BvhBuildParams, traverse};
use std::ops::ControlFlow;
use std::time::Duration;

/// Below this many primitives a linear scan replaces the tree: it is as
/// fast for a handful of shapes, and obvhs builds no usable root for a
/// single primitive.
const MIN_BVH_PRIMITIVES: usize = 4;

/// Largest scene extent the BVH is built for: the widest scene the
/// loaders accept, spheres of the largest radius at the largest
/// coordinates on either side (4 × [`crate::limits::MAX_COORDINATE`]).
const MAX_BVH_EXTENT: f32 = 4.0 * crate::limits::MAX_COORDINATE;

/// Whether `count` primitives within `bounds` get a tree; otherwise a
/// linear scan (too few to gain, or too wide for obvhs). One rule for the
/// CPU's tree here and the GPU's (crate `tyndall-gpu`, `bvh.rs`).
pub fn builds_tree(count: usize, bounds: Bounds) -> bool {
    let tree_safe = bounds.is_empty() || bounds.extent().max_element() <= MAX_BVH_EXTENT;
    count >= MIN_BVH_PRIMITIVES && tree_safe
}

/// obvhs's build parameters for every Tyndall tree: its medium build
/// (PLOC with reinsertion) without spatial pre-splits, so that every
/// primitive is referenced by exactly one leaf, which the any-hit glass
/// traversal (and the GPU's, which counts panes) relies on.
pub fn tree_build_params() -> BvhBuildParams {
    let mut params = BvhBuildParams::medium_build();
    params.pre_split = false;
    params
}

/// The largest padding of a build box, relative to its primitive's size
/// (or to the scene's, for a flat or point-like primitive): 2⁻¹², about
/// 2000 distinct f32 steps of a box's extent, far below the 8-bit
/// quantisation of a CWBVH node's child boxes, so the tree's quality is
/// unchanged.
const BUILD_PAD: f32 = 1.0 / 4096.0;

/// A primitive's box as the tree builder sees it: its bounds padded by a
/// small amount that varies from primitive to primitive (a fixed hash of
/// its index, so builds stay deterministic).
///
/// PLOC (Meister & Bittner 2018) merges mutual nearest neighbours along
/// the Morton order, and obvhs breaks a tie in merge cost towards one
/// side: where every neighbouring pair costs the same — primitives all in
/// one place (32,768 copies of one triangle took 30 s), or a regular row
/// of equal ones — only one pair per sweep is mutual, and the build takes
/// quadratic time. Padding each box by its own amount makes neighbouring
/// costs differ, so a fixed share of the nodes merges in every sweep, as
/// in a generic scene. A padded box still encloses its primitive, so
/// traversal stays exact.
#[derive(Clone, Copy, Debug)]
pub struct BuildBox(obvhs::aabb::Aabb);

impl Boundable for BuildBox {
    fn aabb(&self) -> obvhs::aabb::Aabb {
        self.0
    }
}

/// The [`BuildBox`] of each primitive, in order: the input of every tree
/// Tyndall builds (the CPU's here, the GPU's in crate `tyndall-gpu`).
pub fn build_boxes(primitives: &[Primitive], scene: Bounds) -> Vec<BuildBox> {
    let scene_size = if scene.is_empty() {
        0.0
    } else {
        scene.extent().max_element()
    };
    primitives
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let b = p.shape.bounds();
            let size = b.extent().max_element().max(scene_size * BUILD_PAD);
            let pad = Vec3::splat(size * BUILD_PAD * unit_hash(i as u64));
            BuildBox(obvhs::aabb::Aabb::new(
                (b.min - pad).into(),
                (b.max + pad).into(),
            ))
        })
        .collect()
}

/// A fixed hash of `i` in [0, 1) (the SplitMix64 finaliser).
fn unit_hash(i: u64) -> f32 {
    let mut z = i.wrapping_add(1).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 40) as f32 / (1u64 << 24) as f32
}

/// A shape with its material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Primitive {
    pub shape: Shape,
    pub material: MaterialId,
}

/// The nearest intersection of a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the ray.
    pub t: f32,
    /// Index of the primitive in [`Geometry::primitive`].
    pub primitive: u32,
}

/// All primitives of a scene under a BVH.
pub struct Geometry {
    bvh: Option<CwBvh>,
    primitives: Vec<Primitive>,
    bounds: Bounds,
}

impl Geometry {
    /// Builds the BVH (none for an empty scene).
    pub fn new(primitives: Vec<Primitive>) -> Self {
        let bounds = primitives
            .iter()
            .fold(Bounds::EMPTY, |b, p| b.union(p.shape.bounds()));
        // obvhs panics (an index out of bounds in its CWBVH collapse) on
        // primitives about 10¹⁹ across, and quantises badly long before;
        // the loaders refuse coordinates beyond `MAX_COORDINATE`, and
        // geometry built past that by other means gets a linear scan:
        // slow, but correct.
        let bvh = builds_tree(primitives.len(), bounds).then(|| {
            let mut build_time = Duration::default();
            let boxes = build_boxes(&primitives, bounds);
            obvhs::cwbvh::builder::build_cwbvh(&boxes, tree_build_params(), &mut build_time)
        });
        Self {
            bvh,
            primitives,
            bounds,
        }
    }

    pub fn primitive(&self, index: u32) -> &Primitive {
        &self.primitives[index as usize]
    }

    pub fn primitives(&self) -> &[Primitive] {
        &self.primitives
    }

    /// Bounds of all geometry (empty if there is none).
    pub fn bounds(&self) -> Bounds {
        self.bounds
    }

    /// The nearest intersection with `t ∈ (0, t_max)`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.intersect_where(ray, t_max, |_, _| true)
    }

    /// The nearest intersection with `t ∈ (0, t_max)` that `accept(t,
    /// primitive_index)` keeps: the others (the holes of an alpha
    /// cut-out) are passed through, as an any-hit filter does.
    pub fn intersect_where(
        &self,
        ray: &Ray,
        t_max: f32,
        accept: impl Fn(f32, u32) -> bool,
    ) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.for_each_candidate(ray, t_max, |bvh_ray, index| {
            let prim = &self.primitives[index as usize];
            if let Some(t) = prim.shape.intersect(ray, bvh_ray.tmax)
                && accept(t, index)
            {
                bvh_ray.tmax = t;
                best = Some(Hit {
                    t,
                    primitive: index,
                });
            }
            ControlFlow::Continue(())
        });
        best
    }

    /// Whether any primitive meets `ray` before `t_max`: an any-hit query
    /// that stops at the first hit.
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let mut hit = false;
        self.for_each_hit(ray, t_max, |_, _| {
            hit = true;
            ControlFlow::Break(())
        });
        hit
    }

    /// Calls `visit(t, primitive_index)` for every intersection with
    /// `t ∈ (0, t_max)`, in no particular order, until it breaks.
    pub fn for_each_hit(
        &self,
        ray: &Ray,
        t_max: f32,
        visit: impl FnMut(f32, u32) -> ControlFlow<()>,
    ) {
        self.for_each_hit_by(ray, t_max, Shape::intersect, visit);
    }

    /// [`Geometry::for_each_hit`] for a ray traced along the light's flow
    /// (from a light): one-sided shapes are met from the side a ray
    /// towards the light would meet ([`Shape::intersect_from_light`]).
    pub fn for_each_hit_from_light(
        &self,
        ray: &Ray,
        t_max: f32,
        visit: impl FnMut(f32, u32) -> ControlFlow<()>,
    ) {
        self.for_each_hit_by(ray, t_max, Shape::intersect_from_light, visit);
    }

    /// Every intersection `intersect` finds with `t ∈ (0, t_max)`.
    fn for_each_hit_by(
        &self,
        ray: &Ray,
        t_max: f32,
        intersect: impl Fn(&Shape, &Ray, f32) -> Option<f32>,
        mut visit: impl FnMut(f32, u32) -> ControlFlow<()>,
    ) {
        self.for_each_candidate(ray, t_max, |_, index| {
            let prim = &self.primitives[index as usize];
            match intersect(&prim.shape, ray, t_max) {
                Some(t) => visit(t, index),
                None => ControlFlow::Continue(()),
            }
        });
    }

    /// Visits the primitives whose BVH leaves the ray reaches; the visitor
    /// may shorten the ray (`tmax`) to prune the traversal.
    #[inline]
    fn for_each_candidate(
        &self,
        ray: &Ray,
        t_max: f32,
        mut visit: impl FnMut(&mut obvhs::ray::Ray, u32) -> ControlFlow<()>,
    ) {
        let Some(bvh) = &self.bvh else {
            let mut bvh_ray =
                obvhs::ray::Ray::new(ray.origin.into(), ray.direction.into(), 0.0, t_max);
            for index in 0..self.primitives.len() as u32 {
                if visit(&mut bvh_ray, index).is_break() {
                    break;
                }
            }
            return;
        };
        let origin = Vec3A::from(ray.origin);
        // obvhs orders a child box's planes by the test `direction < 0`
        // but inverts a zero component with its sign (−0.0 → −1/ε): for
        // a −0.0 component (from negating a vector such as Y) the two
        // disagree and the ray misses every box — a camera ray straight
        // down, or every shadow ray towards a sun straight overhead.
        // Adding +0.0 turns −0.0 into +0.0 (IEEE 754, round to nearest)
        // and leaves every other value unchanged.
        let direction = Vec3A::from(ray.direction) + Vec3A::ZERO;
        let mut bvh_ray = obvhs::ray::Ray::new(origin, direction, 0.0, t_max);
        let mut state = bvh.new_traversal(direction);
        let mut node;
        traverse!(
            bvh,
            node,
            state,
            node.intersect_ray(&bvh_ray, state.oct_inv4),
            {
                let index = bvh.primitive_indices[state.primitive_id as usize];
                if visit(&mut bvh_ray, index).is_break() {
                    break;
                }
            }
        );
    }

    /// Geometric unit normal of primitive `index` at the point `p` on it.
    pub fn normal(&self, index: u32, p: Vec3) -> Vec3 {
        self.primitives[index as usize].shape.normal(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::{Quad, Sphere};

    fn scene() -> Geometry {
        let mut prims = Vec::new();
        for i in 0..50 {
            prims.push(Primitive {
                shape: Shape::Sphere(Sphere {
                    center: Vec3::new(i as f32 * 0.7 - 17.0, (i % 7) as f32 - 3.0, -(i % 5) as f32),
                    radius: 0.3,
                }),
                material: 0,
            });
        }
        prims.push(Primitive {
            shape: Shape::Quad(
                Quad::new(
                    Vec3::new(-20.0, -5.0, -10.0),
                    Vec3::X * 40.0,
                    Vec3::Y * 10.0,
                    false,
                )
                .unwrap(),
            ),
            material: 1,
        });
        Geometry::new(prims)
    }

    /// The nearest hit of `ray` among all primitives, by a loop over them.
    fn nearest_by_scan(g: &Geometry, ray: &Ray) -> Option<(f32, u32)> {
        g.primitives()
            .iter()
            .enumerate()
            .filter_map(|(i, p)| p.shape.intersect(ray, f32::INFINITY).map(|t| (t, i as u32)))
            .min_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// The BVH's nearest hit equals a brute-force loop over all primitives.
    #[test]
    fn bvh_matches_brute_force() {
        let g = scene();
        for k in 0..500 {
            let a = k as f32 * 0.013;
            let ray = Ray::new(
                Vec3::new(0.0, 0.0, 10.0),
                Vec3::new(a.sin() * 1.5, (a * 3.1).cos() * 0.4, -1.0),
            );
            let hit = g.intersect(&ray, f32::INFINITY).map(|h| (h.t, h.primitive));
            assert_eq!(hit, nearest_by_scan(&g, &ray), "ray {k}");
            let mut count = 0;
            g.for_each_hit(&ray, f32::INFINITY, |_, _| {
                count += 1;
                ControlFlow::Continue(())
            });
            let brute_count = g
                .primitives()
                .iter()
                .filter(|p| p.shape.intersect(&ray, f32::INFINITY).is_some())
                .count();
            assert_eq!(count, brute_count);
        }
    }

    /// Axis-aligned rays, whose other components are +0.0 or −0.0 (as
    /// `-Vec3::Y` gives), find the same nearest hit as a brute-force loop.
    /// With −0.0 components the BVH missed everything: a camera looking
    /// straight down saw no floor, a sun straight overhead cast no shadow.
    #[test]
    fn axis_aligned_rays_with_signed_zeros_hit() {
        let g = scene();
        let mut checked = 0;
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            // −axis has −0.0 components; adding +0.0 makes them +0.0.
            for direction in [axis, -axis, -axis + Vec3::ZERO] {
                for k in 0..40 {
                    let o = Vec3::new(
                        k as f32 * 0.91 - 18.0,
                        (k % 9) as f32 - 4.0,
                        8.0 - k as f32 * 0.2,
                    );
                    let ray = Ray::new(o - direction * 30.0, direction);
                    let brute = nearest_by_scan(&g, &ray);
                    let hit = g.intersect(&ray, f32::INFINITY).map(|h| (h.t, h.primitive));
                    assert_eq!(hit, brute, "{direction} from {}", ray.origin);
                    checked += usize::from(brute.is_some());
                }
            }
        }
        assert!(checked > 20, "the rays must hit something: {checked}");
    }

    #[test]
    fn small_scenes_scan_linearly() {
        let ray = Ray::new(Vec3::Z, -Vec3::Z);
        assert!(Geometry::new(Vec::new()).intersect(&ray, 10.0).is_none());
        let one = Geometry::new(vec![Primitive {
            shape: Shape::Sphere(Sphere {
                center: Vec3::ZERO,
                radius: 0.5,
            }),
            material: 0,
        }]);
        assert!((one.intersect(&ray, 10.0).unwrap().t - 0.5).abs() < 1e-6);
    }
}
