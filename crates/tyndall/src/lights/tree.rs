//! A bounding volume hierarchy over point and spot lights that chooses
//! one light for a receiving point or a fog segment with probability
//! roughly proportional to the light it sends there: pbrt-v4's
//! `BVHLightSampler` (Pharr, Jakob & Humphreys, *Physically Based
//! Rendering*, 4th ed., §12.6.3) and the light tree of Cycles (Conty
//! Estevez & Kulla 2018, "Importance Sampling of Many Lights with
//! Adaptive Tree Splitting"), with the segment importance of
//! [`LightBounds::importance_along`] for the fog along a camera ray.
//!
//! A choice descends from the root, taking each child with probability
//! proportional to its importance ([`LightBounds`]) and multiplying the
//! probabilities on the way: the choice's probability is exact, so an
//! estimate divided by it is unbiased, and a light whose importance is 0
//! sends nothing to the receiver. The tree splits at the median of the
//! lights' positions along the widest axis (pbrt-v4 splits by a surface
//! area and orientation cost: better for uneven rigs, not yet needed by
//! the grids of fixtures measured here, docs/benchmarks.md).

use super::Light;
use super::bounds::LightBounds;
use crate::ray::Ray;
use glam::Vec3;

/// The largest `u` a descent uses, below 1 so that remapped random
/// numbers stay in `[0, 1)`.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// One node: a leaf holds one light, an interior node two children (the
/// first right after it, the second at `second`).
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: LightBounds,
    kind: NodeKind,
}

#[derive(Clone, Copy, Debug)]
enum NodeKind {
    /// The light's index in the scene.
    Leaf(u32),
    /// The second child's node index.
    Interior(u32),
}

/// The hierarchy over the lights [`Light::bounds`] bounds; nodes in
/// depth-first order.
#[derive(Clone, Debug)]
pub struct LightTree {
    nodes: Vec<Node>,
}

/// Where a light is sent to: a point, or a segment of a ray in fog.
#[derive(Clone, Copy)]
enum Receiver<'a> {
    Point(Vec3),
    Segment {
        lights: &'a [Light],
        ray: &'a Ray,
        a: f32,
        b: f32,
    },
}

impl Receiver<'_> {
    /// The importance of `node` to the receiver. At a leaf along a
    /// segment it is taken over the part the light reaches (a spot's
    /// cone, [`Light::reach`]): exactly 0 where the beam misses it.
    fn importance(&self, node: &Node) -> f32 {
        let importance = match (*self, node.kind) {
            (Receiver::Point(x), _) => node.bounds.importance_at(x),
            (Receiver::Segment { lights, ray, a, b }, NodeKind::Leaf(light)) => lights
                [light as usize]
                .reach(ray, a, b)
                .map_or(0.0, |(a, b)| node.bounds.importance_along(ray, a, b)),
            (Receiver::Segment { ray, a, b, .. }, NodeKind::Interior(_)) => {
                node.bounds.importance_along(ray, a, b)
            }
        };
        // Overflow or 0·∞ must not hide a light: such a node stays a
        // candidate with a finite weight.
        if importance.is_finite() {
            importance.max(0.0)
        } else {
            f32::MAX
        }
    }
}

impl LightTree {
    /// The tree over every light of `lights` with [`Light::bounds`];
    /// `None` if there is none. Its leaves name lights by their index in
    /// `lights`.
    pub fn build(lights: &[Light]) -> Option<Self> {
        let mut leaves: Vec<(u32, LightBounds)> = lights
            .iter()
            .enumerate()
            .filter_map(|(i, light)| Some((i as u32, light.bounds()?)))
            .collect();
        if leaves.is_empty() {
            return None;
        }
        let mut nodes = Vec::with_capacity(2 * leaves.len() - 1);
        build_nodes(&mut leaves, &mut nodes);
        Some(Self { nodes })
    }

    /// How many lights the tree holds.
    pub fn len(&self) -> usize {
        self.nodes.len().div_ceil(2)
    }

    /// Never: a tree holds at least one light.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// One light for the receiver at `x`, chosen by `u ∈ [0, 1)`, and the
    /// probability it was chosen with; `None` if no light reaches `x`.
    pub fn sample_at(&self, x: Vec3, u: f32) -> Option<(usize, f32)> {
        self.descend(Receiver::Point(x), u)
    }

    /// One light for the fog segment `[a, b]` of `ray` (`lights` the
    /// scene's, as given to [`LightTree::build`]), chosen by `u`, and its
    /// probability; `None` if no light reaches the segment.
    pub fn sample_along(
        &self,
        lights: &[Light],
        ray: &Ray,
        a: f32,
        b: f32,
        u: f32,
    ) -> Option<(usize, f32)> {
        self.descend(Receiver::Segment { lights, ray, a, b }, u)
    }

    /// The probability with which [`LightTree::sample_at`] chooses light
    /// `index` for the receiver at `x` (pbrt-v4's `PMF`): the product of
    /// the branch probabilities on the way to its leaf; 0 for a light the
    /// tree does not hold.
    pub fn probability_at(&self, x: Vec3, index: usize) -> f32 {
        self.probability_below(Receiver::Point(x), 0, index as u32)
            .unwrap_or(0.0)
    }

    /// The probability with which [`LightTree::sample_along`] chooses
    /// light `index` for the segment `[a, b]` of `ray`.
    pub fn probability_along(
        &self,
        lights: &[Light],
        ray: &Ray,
        a: f32,
        b: f32,
        index: usize,
    ) -> f32 {
        self.probability_below(Receiver::Segment { lights, ray, a, b }, 0, index as u32)
            .unwrap_or(0.0)
    }

    /// The probability of reaching the leaf of `light` from `node`, if
    /// it lies below `node`.
    fn probability_below(&self, receiver: Receiver, node: usize, light: u32) -> Option<f32> {
        match self.nodes[node].kind {
            NodeKind::Leaf(l) if l == light => {
                Some(if node == 0 && receiver.importance(&self.nodes[0]) == 0.0 {
                    0.0
                } else {
                    1.0
                })
            }
            NodeKind::Leaf(_) => None,
            NodeKind::Interior(second) => {
                let children = [node + 1, second as usize];
                let weights = children.map(|c| f64::from(receiver.importance(&self.nodes[c])));
                let total = weights[0] + weights[1];
                children.iter().zip(weights).find_map(|(&child, weight)| {
                    let below = self.probability_below(receiver, child, light)?;
                    Some(if total > 0.0 {
                        (weight / total) as f32 * below
                    } else {
                        0.0
                    })
                })
            }
        }
    }

    /// The descent from the root: at each interior node a child by its
    /// share of the two children's importance, `u` remapped to the chosen
    /// share.
    fn descend(&self, receiver: Receiver, mut u: f32) -> Option<(usize, f32)> {
        let mut node = 0;
        let mut probability = 1.0f32;
        if receiver.importance(&self.nodes[0]) == 0.0 {
            return None;
        }
        loop {
            match self.nodes[node].kind {
                NodeKind::Leaf(light) => return Some((light as usize, probability)),
                NodeKind::Interior(second) => {
                    let (first, second) = (node + 1, second as usize);
                    let w0 = f64::from(receiver.importance(&self.nodes[first]));
                    let w1 = f64::from(receiver.importance(&self.nodes[second]));
                    if w0 + w1 == 0.0 {
                        return None;
                    }
                    let p0 = (w0 / (w0 + w1)) as f32;
                    if u < p0 {
                        node = first;
                        probability *= p0;
                        u = (u / p0).min(ONE_MINUS_EPSILON);
                    } else {
                        node = second;
                        probability *= 1.0 - p0;
                        u = ((u - p0) / (1.0 - p0)).min(ONE_MINUS_EPSILON);
                    }
                }
            }
        }
    }
}

/// Appends the subtree over `leaves` to `nodes` depth first, splitting at
/// the median position along the widest axis of the positions.
fn build_nodes(leaves: &mut [(u32, LightBounds)], nodes: &mut Vec<Node>) -> LightBounds {
    if let [(light, bounds)] = leaves {
        nodes.push(Node {
            bounds: *bounds,
            kind: NodeKind::Leaf(*light),
        });
        return *bounds;
    }
    let centres = leaves
        .iter()
        .fold(crate::shapes::Bounds::EMPTY, |b, (_, l)| {
            b.include(l.bounds.center())
        });
    let axis = centres.extent().max_position();
    let middle = leaves.len() / 2;
    leaves.select_nth_unstable_by(middle, |(_, p), (_, q)| {
        p.bounds.center()[axis].total_cmp(&q.bounds.center()[axis])
    });
    let at = nodes.len();
    // A placeholder until both children are built.
    nodes.push(Node {
        bounds: leaves[0].1,
        kind: NodeKind::Interior(0),
    });
    let (low, high) = leaves.split_at_mut(middle);
    let first = build_nodes(low, nodes);
    let second_index = nodes.len() as u32;
    let second = build_nodes(high, nodes);
    let bounds = first.union(&second);
    nodes[at] = Node {
        bounds,
        kind: NodeKind::Interior(second_index),
    };
    bounds
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Rgb;
    use crate::lights::{PointLight, SpotLight, SpotProfile};

    /// A rig: `n` spots over a stage, tilted by their index, with a few
    /// point lights among them.
    fn rig(n: usize) -> Vec<Light> {
        (0..n)
            .map(|i| {
                let position =
                    Vec3::new((i % 8) as f32, 4.0 + (i % 3) as f32 * 0.2, (i / 8) as f32);
                let tilt =
                    Vec3::new(((i * 7) % 5) as f32 - 2.0, 0.0, ((i * 3) % 5) as f32 - 2.0) * 0.15;
                if i % 11 == 5 {
                    Light::Point(PointLight {
                        position,
                        intensity: Rgb::splat(1.0 + i as f32 * 0.1),
                        luminaire: None,
                    })
                } else {
                    Light::Spot(SpotLight {
                        position,
                        direction: (tilt - Vec3::Y).normalize(),
                        cos_cutoff: (8.0 + (i % 4) as f32 * 4.0).to_radians().cos(),
                        profile: SpotProfile::Hard,
                        intensity: Rgb::new(1.0, 0.5 + (i % 2) as f32, 2.0),
                        luminaire: None,
                        gobo: None,
                    })
                }
            })
            .collect()
    }

    /// The probability a descent reports is the one its leaf is reached
    /// with (recomputed by [`LightTree::probability_at`]), and the
    /// descent realises it: each leaf takes one interval of `u`, so of `N`
    /// stratified `u` a light gets `N·P ± 1`. The probabilities sum to at
    /// most 1 (a descent may end in a cluster whose cones hold the
    /// receiver while none of its lights' cones does: no light, no bias).
    /// Every light that reaches the receiver can be chosen.
    #[test]
    fn choice_probabilities_are_a_distribution() {
        let lights = rig(37);
        let tree = LightTree::build(&lights).unwrap();
        assert_eq!(tree.len(), 37);
        let receivers = [
            Vec3::new(2.0, 0.0, 1.5),
            Vec3::new(7.0, 1.0, 4.0),
            Vec3::new(-3.0, 0.5, 2.0),
        ];
        let n = 10_000;
        for x in receivers {
            let total: f32 = (0..lights.len()).map(|i| tree.probability_at(x, i)).sum();
            assert!(total <= 1.0 + 1e-5, "{total}");
            let mut chosen = vec![0u32; lights.len()];
            for k in 0..n {
                let u = (k as f32 + 0.5) / n as f32;
                if let Some((light, p)) = tree.sample_at(x, u) {
                    let again = tree.probability_at(x, light);
                    assert!((p - again).abs() <= 1e-5 * again, "{p} vs {again}");
                    chosen[light] += 1;
                }
            }
            for (i, light) in lights.iter().enumerate() {
                let p = tree.probability_at(x, i);
                let share = chosen[i] as f32 / n as f32;
                assert!(
                    (share - p).abs() <= 1.5 / n as f32,
                    "light {i}: {share} vs {p}"
                );
                if light
                    .incident(x, light.sample_point(glam::Vec2::ZERO))
                    .is_some()
                {
                    assert!(p > 0.0, "light {i} lights {x} but is never chosen");
                }
            }
        }
        let ray = Ray {
            origin: Vec3::new(-2.0, 1.0, -1.0),
            direction: Vec3::new(1.0, 0.1, 0.6).normalize(),
        };
        assert!(
            lights
                .iter()
                .filter(|l| l.reach(&ray, 0.0, 20.0).is_some())
                .count()
                > 2
        );
        let mut chosen = vec![0u32; lights.len()];
        for k in 0..n {
            let u = (k as f32 + 0.5) / n as f32;
            if let Some((light, p)) = tree.sample_along(&lights, &ray, 0.0, 20.0, u) {
                let again = tree.probability_along(&lights, &ray, 0.0, 20.0, light);
                assert!((p - again).abs() <= 1e-5 * again, "{p} vs {again}");
                chosen[light] += 1;
            }
        }
        for (i, light) in lights.iter().enumerate() {
            let p = tree.probability_along(&lights, &ray, 0.0, 20.0, i);
            let share = chosen[i] as f32 / n as f32;
            assert!(
                (share - p).abs() <= 1.5 / n as f32,
                "light {i}: {share} vs {p}"
            );
            // Exactly the lights whose beams the segment crosses.
            assert_eq!(light.reach(&ray, 0.0, 20.0).is_some(), p > 0.0, "light {i}");
        }
    }

    /// 4096 lights build a tree of 2n − 1 nodes.
    #[test]
    fn builds_for_many_lights() {
        let lights = rig(1 << 12);
        let tree = LightTree::build(&lights).unwrap();
        assert_eq!(tree.nodes.len(), 2 * lights.len() - 1);
    }
}
