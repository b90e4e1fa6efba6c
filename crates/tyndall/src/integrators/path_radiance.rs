//! A camera sample's radiance as an integrator adds it up, and its
//! components ([`Component`]) when the render keeps them: each
//! contribution is added to the total and to the one component its
//! path's scattering history names.

use crate::aov::{Component, Scattering};
use crate::color::Rgb;

/// A camera sample's radiance, and what it keeps of its components
/// (`K`: [`Split`] keeps them, [`Whole`] does not). The total is added up
/// exactly as a bare `Rgb` would be (the same additions in the same
/// order), so keeping the components changes no sample; and with
/// [`Whole`] (zero-sized, each integrator compiled once per kind) the
/// components and the scattering history that names them compile away: a
/// render without them costs what it did before they existed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathRadiance<K: Keep> {
    total: Rgb,
    kept: K,
}

impl<K: Keep> PathRadiance<K> {
    /// Nothing yet.
    pub fn new() -> Self {
        Self {
            total: Rgb::ZERO,
            kept: K::default(),
        }
    }

    /// Adds `value`, light of `component`.
    #[inline]
    pub fn add(&mut self, component: Component, value: Rgb) {
        self.total += value;
        self.kept.add(component, value);
    }

    pub fn total(&self) -> Rgb {
        self.total
    }

    /// The components, indexed by [`Component::index`], if kept.
    pub fn components(&self) -> Option<[Rgb; 4]> {
        self.kept.components()
    }
}

/// What a sample keeps of its radiance's components.
pub trait Keep: Copy + Default {
    fn add(&mut self, component: Component, value: Rgb);
    fn components(&self) -> Option<[Rgb; 4]>;
}

/// Keeps nothing: only the total.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Whole;

impl Keep for Whole {
    #[inline]
    fn add(&mut self, _: Component, _: Rgb) {}
    fn components(&self) -> Option<[Rgb; 4]> {
        None
    }
}

/// Keeps the four components, indexed by [`Component::index`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Split([Rgb; 4]);

impl Keep for Split {
    #[inline]
    fn add(&mut self, component: Component, value: Rgb) {
        self.0[component.index()] += value;
    }
    fn components(&self) -> Option<[Rgb; 4]> {
        Some(self.0)
    }
}

/// How a path has scattered so far: where it first scattered from the
/// camera, and how many times (specular events do not count).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ScatteringHistory {
    first: Option<Scattering>,
    events: u32,
}

impl ScatteringHistory {
    /// The history after one more scattering event, at `kind`.
    #[inline]
    #[must_use]
    pub fn then(mut self, kind: Scattering) -> Self {
        self.first.get_or_insert(kind);
        self.events += 1;
        self
    }

    /// The component of light arriving at the path's current vertex with
    /// this history.
    #[inline]
    pub fn component(self) -> Component {
        Component::of_path(self.first, self.events)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The components of the paths the docs name (docs/physics.md §6.2).
    #[test]
    fn histories_name_their_components() {
        let none = ScatteringHistory::default();
        let surface = none.then(Scattering::Surface);
        let medium = none.then(Scattering::Medium);
        assert_eq!(none.component(), Component::Emission);
        assert_eq!(surface.component(), Component::Direct);
        assert_eq!(
            surface.then(Scattering::Surface).component(),
            Component::Indirect
        );
        assert_eq!(
            surface.then(Scattering::Medium).component(),
            Component::Indirect
        );
        assert_eq!(medium.component(), Component::Volume);
        assert_eq!(
            medium.then(Scattering::Surface).component(),
            Component::Volume
        );
    }

    /// The total is the same additions as a bare sum, and the components
    /// add up to it.
    #[test]
    fn the_total_is_the_plain_sum_and_the_components_add_up_to_it() {
        let values = [
            (Component::Volume, Rgb::new(0.1, 0.2, 0.3)),
            (Component::Direct, Rgb::new(1e-3, 5.0, 0.7)),
            (Component::Volume, Rgb::new(0.25, 0.0, 1.5)),
            (Component::Emission, Rgb::new(3.0, 3.0, 3.0)),
        ];
        let (mut split, mut plain, mut bare) = (
            PathRadiance::<Split>::new(),
            PathRadiance::<Whole>::new(),
            Rgb::ZERO,
        );
        for (c, v) in values {
            split.add(c, v);
            plain.add(c, v);
            bare += v;
        }
        assert_eq!(split.total(), bare);
        assert_eq!(plain.total(), bare);
        assert_eq!(plain.components(), None);
        let parts = split.components().expect("kept");
        assert_eq!(parts[Component::Indirect.index()], Rgb::ZERO);
        let sum: Rgb = parts.iter().sum();
        assert!((sum - bare).abs().max_element() <= 1e-6 * bare.max_element());
    }
}
