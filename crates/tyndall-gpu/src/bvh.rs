//! The GPU's ray-intersection structure: a binary BVH built on the host
//! by obvhs (PLOC with reinsertion, leaves collapsed by the surface area
//! heuristic; the CPU's `tyndall::accel` uses the same builder for its
//! 8-wide tree) and flattened for stackless traversal: nodes in
//! depth-first order, each with the index of the node after its subtree
//! (where a ray that misses its box goes on), leaves holding ranges of a
//! primitive array reordered to match (a "threaded" BVH, as in Smits
//! 1998, "Efficiency issues for ray tracing"). `bvh_next` in `bvh.wgsl`
//! walks it; camera rays, shadow rays and shadow-map texels all use it.
//!
//! Why a BVH and not rasterised primary visibility: one structure serves
//! every ray the GPU traces (camera, reflection, shadow and map texel
//! rays), so the paper's scenes and glTF meshes alike cost about log N
//! box tests a ray instead of N primitive tests, in compute kernels that
//! run the same under lavapipe.

use bytemuck::{Pod, Zeroable};
use obvhs::bvh2::Bvh2;
use tyndall::accel::{Primitive, build_boxes, builds_tree, tree_build_params};
use tyndall::shapes::Bounds;

/// One node (`BvhNode` in `scene.wgsl`): its box, grown by a relative
/// margin so that flat shapes and rounding cannot make a ray miss it;
/// `skip` the node after its subtree; for a leaf, `count` > 0 primitives
/// from `first` in the reordered primitive array.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct GpuBvhNode {
    min: [f32; 3],
    skip: u32,
    max: [f32; 3],
    first: u32,
    count: u32,
    pad: [u32; 3],
}

/// A flattened BVH and the order its leaves put the primitives in.
pub(crate) struct FlatBvh {
    pub nodes: Vec<GpuBvhNode>,
    /// `order[j]` is the scene's index of the j-th primitive of the
    /// reordered array.
    pub order: Vec<u32>,
}

/// `b` grown by a margin relative to its size and position.
fn padded(b: Bounds) -> ([f32; 3], [f32; 3]) {
    let margin =
        1e-4 * (1.0 + b.extent().max_element()) + 1e-6 * b.min.abs().max(b.max.abs()).max_element();
    ((b.min - margin).into(), (b.max + margin).into())
}

impl FlatBvh {
    pub(crate) fn new(primitives: &[Primitive]) -> Self {
        let bounds = primitives
            .iter()
            .fold(Bounds::EMPTY, |b, p| b.union(p.shape.bounds()));
        if primitives.is_empty() {
            return Self {
                nodes: Vec::new(),
                order: Vec::new(),
            };
        }
        // Where the CPU scans linearly, one leaf holds every primitive.
        if !builds_tree(primitives.len(), bounds) {
            let (min, max) = padded(bounds);
            return Self {
                nodes: vec![GpuBvhNode {
                    min,
                    max,
                    skip: 1,
                    first: 0,
                    count: primitives.len() as u32,
                    pad: [0; 3],
                }],
                order: (0..primitives.len() as u32).collect(),
            };
        }
        let mut build_time = std::time::Duration::default();
        let boxes = build_boxes(primitives, bounds);
        let bvh = obvhs::bvh2::builder::build_bvh2(&boxes, tree_build_params(), &mut build_time);
        let mut flat = Self {
            nodes: Vec::with_capacity(bvh.nodes.len()),
            order: Vec::with_capacity(primitives.len()),
        };
        flat.append(&bvh, 0);
        flat
    }

    /// Appends node `index` of `bvh` and its subtree in depth-first order.
    fn append(&mut self, bvh: &Bvh2, index: usize) {
        let node = bvh.nodes[index];
        let aabb = node.aabb;
        let (min, max) = padded(Bounds {
            min: glam::Vec3::from(aabb.min),
            max: glam::Vec3::from(aabb.max),
        });
        let at = self.nodes.len();
        self.nodes.push(GpuBvhNode {
            min,
            max,
            ..Default::default()
        });
        if node.prim_count > 0 {
            let range = node.first_index as usize..(node.first_index + node.prim_count) as usize;
            self.nodes[at].first = self.order.len() as u32;
            self.nodes[at].count = node.prim_count;
            self.order.extend_from_slice(&bvh.primitive_indices[range]);
        } else {
            self.append(bvh, node.first_index as usize);
            self.append(bvh, node.first_index as usize + 1);
        }
        self.nodes[at].skip = self.nodes.len() as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use tyndall::shapes::{Shape, Sphere};

    fn spheres(n: usize) -> Vec<Primitive> {
        (0..n)
            .map(|i| Primitive {
                shape: Shape::Sphere(Sphere {
                    center: Vec3::new(i as f32 * 3.0, (i % 3) as f32, 0.0),
                    radius: 1.0,
                }),
                material: 0,
            })
            .collect()
    }

    /// Every primitive sits in exactly one leaf, each subtree's nodes lie
    /// between it and its `skip`, and every box holds its subtree's
    /// primitives' boxes.
    #[test]
    fn flattened_tree_is_threaded_and_covers_every_primitive_once() {
        for n in [1, 3, 4, 5, 17, 64] {
            let primitives = spheres(n);
            let bvh = FlatBvh::new(&primitives);
            let mut sorted = bvh.order.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..n as u32).collect::<Vec<_>>(), "{n} primitives");
            assert_eq!(bvh.nodes[0].skip as usize, bvh.nodes.len());
            for (i, node) in bvh.nodes.iter().enumerate() {
                assert!(node.skip as usize > i && node.skip as usize <= bvh.nodes.len());
                let leaves = &bvh.nodes[i..node.skip as usize];
                if node.count > 0 {
                    assert_eq!(node.skip as usize, i + 1, "a leaf's subtree is itself");
                }
                for leaf in leaves.iter().filter(|l| l.count > 0) {
                    for &p in &bvh.order[leaf.first as usize..(leaf.first + leaf.count) as usize] {
                        let b = primitives[p as usize].shape.bounds();
                        for axis in 0..3 {
                            assert!(node.min[axis] <= b.min[axis] && b.max[axis] <= node.max[axis]);
                        }
                    }
                }
            }
            let in_leaves: u32 = bvh.nodes.iter().map(|l| l.count).sum();
            assert_eq!(in_leaves as usize, n);
        }
    }

    #[test]
    fn no_primitives_no_nodes() {
        let bvh = FlatBvh::new(&[]);
        assert!(bvh.nodes.is_empty() && bvh.order.is_empty());
    }
}
