//! Which lights an estimate connects to: every light (a handful of lamps),
//! or the lights the tree cannot hold (suns and area lights, whose MIS
//! weights against hits read them all) plus the point and spot lights
//! the [`LightTree`]'s splitting descent chooses. Each chosen light comes
//! with the weight `1/P` that keeps the sum over lights unbiased:
//! `E[Σ_chosen w_l·F_l] = Σ_l F_l`.

use super::Light;
use super::tree::{LightTree, MAX_SPLIT_LIGHTS, SplitChoice};
use crate::ray::Ray;
use glam::Vec3;

/// From how many point and spot lights [`LightSampling::Auto`] chooses
/// by the tree instead of visiting them all. On the stage rig every light
/// took 1.4× less time to relMSE 10⁻³ with 64 spots (a light whose cone
/// misses the receiver costs a dot product, not a shadow ray), and the
/// tree 1.5× less with 256 and 3.3× less with 1024 (docs/benchmarks.md,
/// "Many lights").
pub const TREE_FROM_LIGHTS: usize = 256;

/// How a render chooses the lights an estimate connects to.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightSampling {
    /// The tree from [`TREE_FROM_LIGHTS`] point and spot lights on, every
    /// light below.
    #[default]
    Auto,
    /// Every light at every estimate.
    All,
    /// Point and spot lights from the tree, however few there are.
    Tree,
}

impl LightSampling {
    /// Every choice, in the order of its names.
    pub const ALL: [LightSampling; 3] =
        [LightSampling::Auto, LightSampling::All, LightSampling::Tree];

    /// The name scene files and the CLI give it: `auto`, `all`, `tree`.
    pub fn name(self) -> &'static str {
        match self {
            LightSampling::Auto => "auto",
            LightSampling::All => "all",
            LightSampling::Tree => "tree",
        }
    }

    /// The choice named `name` ([`LightSampling::name`]).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }
}

/// The lights an estimate connects to (see the module's text).
#[derive(Clone, Debug)]
pub struct LightSampler {
    /// The lights every estimate visits, in the scene's order.
    visited: Vec<u32>,
    /// The point and spot lights, when they are chosen from.
    tree: Option<LightTree>,
}

impl LightSampler {
    /// The sampler over `lights` that `sampling` asks for.
    pub fn new(lights: &[Light], sampling: LightSampling) -> Self {
        let held = lights.iter().filter(|l| l.bounds().is_some()).count();
        let use_tree = match sampling {
            LightSampling::All => false,
            LightSampling::Tree => held > 0,
            LightSampling::Auto => held >= TREE_FROM_LIGHTS,
        };
        if !use_tree {
            return Self {
                visited: (0..lights.len() as u32).collect(),
                tree: None,
            };
        }
        Self {
            visited: (0..lights.len() as u32)
                .filter(|&i| lights[i as usize].bounds().is_none())
                .collect(),
            tree: LightTree::build(lights),
        }
    }

    /// Whether a choice takes a random number (the tree is in use): the
    /// caller draws `u` only then, so renders that visit every light keep
    /// their sample dimensions.
    #[inline]
    pub fn chooses(&self) -> bool {
        self.tree.is_some()
    }

    /// The most lights one estimate connects to.
    pub fn most_chosen(&self) -> usize {
        self.visited.len()
            + if self.tree.is_some() {
                MAX_SPLIT_LIGHTS
            } else {
                0
            }
    }

    /// The tree the point and spot lights are chosen from, if they are.
    pub fn tree(&self) -> Option<&LightTree> {
        self.tree.as_ref()
    }

    /// The lights for a receiver at `x`, the tree's choice made by `u`.
    #[inline]
    pub fn at(&self, x: Vec3, u: f32) -> Chosen<'_> {
        Chosen {
            visited: self.visited.iter(),
            drawn: self
                .tree
                .as_ref()
                .map(|t| t.split_at(x, u))
                .unwrap_or_default(),
            next: 0,
        }
    }

    /// The lights for the fog segment `[a, b]` of `ray` (`lights` the
    /// scene's), the tree's choice made by `u`.
    #[inline]
    pub fn along(&self, lights: &[Light], ray: &Ray, a: f32, b: f32, u: f32) -> Chosen<'_> {
        Chosen {
            visited: self.visited.iter(),
            drawn: self
                .tree
                .as_ref()
                .map(|t| t.split_along(lights, ray, a, b, u))
                .unwrap_or_default(),
            next: 0,
        }
    }
}

/// The chosen lights, as `(index, weight)`: the visited lights with
/// weight 1, then the tree's choices with weight `1/P` each.
#[derive(Clone, Debug)]
pub struct Chosen<'a> {
    visited: std::slice::Iter<'a, u32>,
    drawn: SplitChoice,
    /// How many of `drawn` were given.
    next: usize,
}

impl Iterator for Chosen<'_> {
    type Item = (usize, f32);

    #[inline]
    fn next(&mut self) -> Option<(usize, f32)> {
        if let Some(&index) = self.visited.next() {
            return Some((index as usize, 1.0));
        }
        let drawn = self.drawn.lights().nth(self.next)?;
        self.next += 1;
        Some((drawn.0, 1.0 / drawn.1))
    }
}
