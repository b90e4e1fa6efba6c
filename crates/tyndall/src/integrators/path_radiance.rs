//! A camera sample's radiance as an integrator adds it up, and its
//! components ([`Component`]) and light groups ([`LightGroup`]) when the
//! render keeps them: each contribution is added to the total, to the one
//! component its path's scattering history names and to the group of the
//! emitter it came from. Estimates that gather light from several lights
//! at once (next event estimation, a fog segment's samples) return it as
//! [`Gathered`], split by group when it is kept.

use crate::aov::{Component, Scattering};
use crate::color::Rgb;
use crate::light_groups::{GroupRadiance, LightGroup};

/// A camera sample's radiance, and what it keeps of its components and
/// light groups (`K`: [`Split`] keeps them, [`Whole`] does not). The
/// total is added up exactly as a bare `Rgb` would be (the same additions
/// in the same order), so keeping them changes no sample; and with
/// [`Whole`] (zero-sized, each integrator compiled once per kind) the
/// split and the scattering history that names the components compile
/// away: a render without them costs what it did before they existed.
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

    /// Adds `value`, light of `component` from an emitter of `group`.
    #[inline]
    pub fn add(&mut self, component: Component, group: LightGroup, value: Rgb) {
        self.total += value;
        self.kept.add(component, group, value);
    }

    /// Adds `scale` times `gathered`, light of `component`.
    #[inline]
    pub fn add_gathered(&mut self, component: Component, scale: Rgb, gathered: &Gathered<K>) {
        let value = scale * gathered.total;
        self.total += value;
        self.kept
            .add_gathered(component, value, scale, &gathered.groups);
    }

    pub fn total(&self) -> Rgb {
        self.total
    }

    /// The components, indexed by [`Component::index`], if kept.
    pub fn components(&self) -> Option<[Rgb; 4]> {
        self.kept.components()
    }

    /// The radiance by light group, indexed by [`LightGroup::index`], if
    /// kept.
    pub fn groups(&self) -> Option<&GroupRadiance> {
        self.kept.groups()
    }
}

/// Light an estimate gathered from one or more emitters: the sum, and its
/// share per light group if `K` keeps them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gathered<K: Keep> {
    total: Rgb,
    groups: K::Groups,
}

impl<K: Keep> Gathered<K> {
    /// Nothing yet.
    #[inline]
    pub fn new() -> Self {
        Self {
            total: Rgb::ZERO,
            groups: K::Groups::default(),
        }
    }

    /// Adds `value`, light from an emitter of `group`.
    #[inline]
    pub fn add(&mut self, group: LightGroup, value: Rgb) {
        self.total += value;
        K::add_to_groups(&mut self.groups, group, value);
    }

    /// Every share times `by`.
    #[inline]
    #[must_use]
    pub fn scaled(mut self, by: Rgb) -> Self {
        self.total *= by;
        K::scale_groups(&mut self.groups, by);
        self
    }

    pub fn total(&self) -> Rgb {
        self.total
    }
}

impl<K: Keep> Default for Gathered<K> {
    fn default() -> Self {
        Self::new()
    }
}

/// What a sample keeps of its radiance's components and light groups.
pub trait Keep: Copy + Default {
    /// What a [`Gathered`] estimate keeps of its light groups.
    type Groups: Copy + Default + std::fmt::Debug + PartialEq;
    fn add(&mut self, component: Component, group: LightGroup, value: Rgb);
    /// Adds `value` = `scale` × (the sum of `groups`) to `component`, and
    /// `scale` × each of `groups` to its group.
    fn add_gathered(&mut self, component: Component, value: Rgb, scale: Rgb, groups: &Self::Groups);
    fn add_to_groups(groups: &mut Self::Groups, group: LightGroup, value: Rgb);
    fn scale_groups(groups: &mut Self::Groups, by: Rgb);
    fn components(&self) -> Option<[Rgb; 4]>;
    fn groups(&self) -> Option<&GroupRadiance>;
}

/// Keeps nothing: only the total.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Whole;

impl Keep for Whole {
    type Groups = ();
    #[inline]
    fn add(&mut self, _: Component, _: LightGroup, _: Rgb) {}
    #[inline]
    fn add_gathered(&mut self, _: Component, _: Rgb, _: Rgb, _: &()) {}
    #[inline]
    fn add_to_groups(_: &mut (), _: LightGroup, _: Rgb) {}
    #[inline]
    fn scale_groups(_: &mut (), _: Rgb) {}
    fn components(&self) -> Option<[Rgb; 4]> {
        None
    }
    fn groups(&self) -> Option<&GroupRadiance> {
        None
    }
}

/// Keeps the four components, indexed by [`Component::index`], and the
/// light groups, indexed by [`LightGroup::index`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Split {
    components: [Rgb; 4],
    groups: GroupRadiance,
}

impl Keep for Split {
    type Groups = GroupRadiance;
    #[inline]
    fn add(&mut self, component: Component, group: LightGroup, value: Rgb) {
        self.components[component.index()] += value;
        self.groups[group.index()] += value;
    }
    #[inline]
    fn add_gathered(
        &mut self,
        component: Component,
        value: Rgb,
        scale: Rgb,
        groups: &GroupRadiance,
    ) {
        self.components[component.index()] += value;
        for (sum, share) in self.groups.iter_mut().zip(groups) {
            *sum += scale * *share;
        }
    }
    #[inline]
    fn add_to_groups(groups: &mut GroupRadiance, group: LightGroup, value: Rgb) {
        groups[group.index()] += value;
    }
    #[inline]
    fn scale_groups(groups: &mut GroupRadiance, by: Rgb) {
        for share in groups {
            *share *= by;
        }
    }
    fn components(&self) -> Option<[Rgb; 4]> {
        Some(self.components)
    }
    fn groups(&self) -> Option<&GroupRadiance> {
        Some(&self.groups)
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
    /// and the light groups each add up to it, gathered light included.
    #[test]
    fn the_total_is_the_plain_sum_and_components_and_groups_add_up_to_it() {
        let (key, fill) = (
            LightGroup::OTHER,
            crate::light_groups::LightGroups::new([Some("key"), Some("fill")]),
        );
        let (g1, g2) = (fill.of(0), fill.of(1));
        let values = [
            (Component::Volume, g1, Rgb::new(0.1, 0.2, 0.3)),
            (Component::Direct, key, Rgb::new(1e-3, 5.0, 0.7)),
            (Component::Volume, g2, Rgb::new(0.25, 0.0, 1.5)),
            (Component::Emission, g1, Rgb::new(3.0, 3.0, 3.0)),
        ];
        let (mut split, mut plain, mut bare) = (
            PathRadiance::<Split>::new(),
            PathRadiance::<Whole>::new(),
            Rgb::ZERO,
        );
        for (c, g, v) in values {
            split.add(c, g, v);
            plain.add(c, g, v);
            bare += v;
        }
        let (mut gathered_split, mut gathered_plain) =
            (Gathered::<Split>::new(), Gathered::<Whole>::new());
        for (_, g, v) in values {
            gathered_split.add(g, v);
            gathered_plain.add(g, v);
        }
        let scale = Rgb::new(0.5, 2.0, 0.25);
        let (gathered_split, gathered_plain) =
            (gathered_split.scaled(scale), gathered_plain.scaled(scale));
        let throughput = Rgb::new(0.9, 0.8, 0.7);
        split.add_gathered(Component::Indirect, throughput, &gathered_split);
        plain.add_gathered(Component::Indirect, throughput, &gathered_plain);
        bare += throughput * (bare * scale);
        assert_eq!(split.total(), bare);
        assert_eq!(plain.total(), bare);
        assert_eq!(plain.components(), None);
        assert_eq!(plain.groups(), None);
        let close = |sum: Rgb| (sum - bare).abs().max_element() <= 1e-6 * bare.max_element();
        let parts = split.components().expect("kept");
        assert!(close(parts.iter().sum()));
        let groups = split.groups().expect("kept");
        assert!(close(groups.iter().sum()));
        assert_eq!(
            groups[3..],
            [Rgb::ZERO; crate::light_groups::MAX_LIGHT_GROUPS - 3]
        );
        let g2_alone = Rgb::new(0.25, 0.0, 1.5) * (Rgb::ONE + throughput * scale);
        assert!((groups[g2.index()] - g2_alone).abs().max_element() <= 1e-6);
    }
}
