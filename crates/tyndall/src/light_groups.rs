//! Light groups: named sets of emitters whose light a render keeps apart,
//! as the AOV `light_groups` (Cycles' light groups; pbrt-v4 and Mitsuba
//! have no equivalent). Every contribution an integrator adds comes from
//! one emitter — a light sampled by next event estimation, an area light
//! or the environment hit by a path, a light subpath's light — and goes
//! to that emitter's group; light from emitters in no named group (and
//! from emitting media, emissive surfaces that are not lights, and a
//! constant background) goes to the group [`LightGroup::OTHER`]. The
//! groups therefore partition the radiance: their images sum to the
//! beauty to f32 rounding, and each is the expectation of a render with
//! only its own emitters switched on (docs/physics.md §6.3).

use crate::color::Rgb;
use crate::film::Image;
use glam::DVec3;

/// Most groups a render keeps, [`LightGroup::OTHER`] included: the
/// per-sample split is a fixed array this long.
pub const MAX_LIGHT_GROUPS: usize = 16;

/// The name of [`LightGroup::OTHER`], reserved: no named group may take it.
pub const OTHER_NAME: &str = "other";

/// Longest light group name, in bytes.
pub const MAX_NAME_BYTES: usize = 64;

/// Whether `name` can name a light group: 1 to [`MAX_NAME_BYTES`] ASCII
/// letters, digits, `_` and `-` (it names EXR layers and part-file
/// header words; Blender's light group names are the same set).
pub fn is_group_name(name: &str) -> bool {
    let allowed = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    !name.is_empty() && name.len() <= MAX_NAME_BYTES && name.chars().all(allowed)
}

/// One light group, by its index in [`LightGroups::names`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct LightGroup(u8);

impl LightGroup {
    /// Light from emitters in no named group.
    pub const OTHER: LightGroup = LightGroup(0);

    /// Its index in per-group arrays.
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// The light groups of a scene: their names (index 0 is
/// [`OTHER_NAME`], then the named groups in the order of the first light
/// of each, lights numbered as the scene numbers them: emissive shapes
/// first) and each light's group.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightGroups {
    names: Vec<String>,
    of_light: Vec<LightGroup>,
}

impl LightGroups {
    /// The groups of `count` lights, light `i` in the group named
    /// `names[i]` (`None`: [`LightGroup::OTHER`]). At most
    /// [`MAX_LIGHT_GROUPS`] − 1 distinct names (the description's
    /// validation enforces it; further names fall into OTHER here).
    pub fn new<'a>(names: impl IntoIterator<Item = Option<&'a str>>) -> Self {
        let mut groups = LightGroups {
            names: vec![OTHER_NAME.to_owned()],
            of_light: Vec::new(),
        };
        for name in names {
            let group = match name {
                None => LightGroup::OTHER,
                Some(name) => match groups.names.iter().position(|n| n == name) {
                    Some(i) => LightGroup(i as u8),
                    None if groups.names.len() < MAX_LIGHT_GROUPS => {
                        groups.names.push(name.to_owned());
                        LightGroup((groups.names.len() - 1) as u8)
                    }
                    None => LightGroup::OTHER,
                },
            };
            groups.of_light.push(group);
        }
        groups
    }

    /// The groups' names, by [`LightGroup::index`].
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// How many groups there are, [`LightGroup::OTHER`] included.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Always false: [`LightGroup::OTHER`] is always there.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The group of light number `light` (OTHER for an index out of range,
    /// so that a caller that does not keep groups compiles the lookup away).
    #[inline]
    pub fn of(&self, light: usize) -> LightGroup {
        self.of_light.get(light).copied().unwrap_or_default()
    }
}

/// One camera sample's radiance by light group, indexed by
/// [`LightGroup::index`] (the unused tail is zero).
pub type GroupRadiance = [Rgb; MAX_LIGHT_GROUPS];

/// The per-pixel sums of each group's radiance over a part's samples,
/// with the groups' names (by [`LightGroup::index`]): one value per group
/// per pixel, pixel-major.
#[derive(Clone, Debug, PartialEq)]
pub struct LightGroupSums {
    names: Vec<String>,
    sums: Vec<DVec3>,
}

impl LightGroupSums {
    /// No samples yet, for `pixels` pixels and the groups `names`.
    pub fn new(pixels: usize, names: &[String]) -> Self {
        Self {
            names: names.to_vec(),
            sums: vec![DVec3::ZERO; pixels * names.len()],
        }
    }

    /// Sums read back from storage: one per group of `names` per pixel,
    /// pixel-major. `None` if `sums` is not a whole number of pixels or
    /// there are not `1..=MAX_LIGHT_GROUPS` names.
    pub fn from_sums(names: Vec<String>, sums: Vec<DVec3>) -> Option<Self> {
        ((1..=MAX_LIGHT_GROUPS).contains(&names.len()) && sums.len().is_multiple_of(names.len()))
            .then_some(Self { names, sums })
    }

    /// The groups' names, by [`LightGroup::index`].
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// How many groups each pixel holds.
    pub fn groups(&self) -> usize {
        self.names.len()
    }

    /// Every sum: pixel-major, `groups` per pixel.
    pub fn sums(&self) -> &[DVec3] {
        &self.sums
    }

    /// Every sum, mutably: pixel-major, `groups` per pixel.
    pub fn sums_mut(&mut self) -> &mut [DVec3] {
        &mut self.sums
    }

    /// Adds `next`'s sums (the same pixels and groups) to these.
    pub fn append(&mut self, next: &LightGroupSums) {
        for (a, b) in self.sums.iter_mut().zip(&next.sums) {
            *a += *b;
        }
    }

    /// The mean image of each group over `samples` samples per pixel
    /// (`width`×`height` pixels), by [`LightGroup::index`].
    pub fn resolve(&self, width: u32, height: u32, samples: u32) -> Vec<Image> {
        let n = f64::from(samples.max(1));
        let groups = self.names.len();
        (0..groups)
            .map(|g| {
                let pixels: Vec<Rgb> = self
                    .sums
                    .chunks_exact(groups)
                    .map(|p| (p[g] / n).as_vec3())
                    .collect();
                Image::from_pixels(width, height, pixels)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_numbered_in_first_order_after_other() {
        let groups = LightGroups::new([Some("key"), None, Some("fill"), Some("key")]);
        assert_eq!(groups.names(), ["other", "key", "fill"]);
        let of: Vec<usize> = (0..5).map(|i| groups.of(i).index()).collect();
        assert_eq!(of, [1, 0, 2, 1, 0]);
    }

    #[test]
    fn sums_resolve_to_means_per_group() {
        let mut sums = LightGroupSums::new(2, &["other".into(), "key".into()]);
        for (k, pixel) in sums.sums_mut().chunks_exact_mut(2).enumerate() {
            pixel[0] = DVec3::splat(k as f64);
            pixel[1] = DVec3::splat(4.0);
        }
        let images = sums.resolve(2, 1, 2);
        assert_eq!(images[0].pixels()[1], Rgb::splat(0.5));
        assert_eq!(images[1].pixels()[0], Rgb::splat(2.0));
        let three = vec!["a".to_owned(), "b".into(), "c".into()];
        assert!(LightGroupSums::from_sums(three, vec![DVec3::ZERO; 4]).is_none());
    }
}
