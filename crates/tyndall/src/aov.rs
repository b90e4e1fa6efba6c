//! The outputs a render can write beside the radiance, arbitrary output
//! variables (AOVs): the first-surface guides (module [`crate::guides`]),
//! the radiance's components ([`Component`]), which sum to it, and its
//! light groups (module [`crate::light_groups`]), which sum to it too.

use crate::color::Rgb;
use crate::film::Image;
use glam::DVec3;

/// A part of a camera sample's radiance, by the path its light took
/// (docs/physics.md §6.2). Every contribution of every integrator goes to
/// exactly one, so the four sum to the radiance (to f32 rounding).
/// "Scattering" here is an event at a diffuse or glossy surface or in a
/// medium; specular events (thin glass, mirrors met by a camera ray, and
/// dielectric interfaces) do not count.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Component {
    /// Light that reaches the camera without scattering: emitters, lamps,
    /// emitting media and the background seen directly (or through
    /// specular events).
    Emission,
    /// Light scattered once, at a surface: direct lighting.
    Direct,
    /// Light whose first scattering from the camera is at a surface and
    /// which scattered more than once: interreflection, and fog light
    /// seen in a surface.
    Indirect,
    /// Light whose first scattering from the camera is in a medium (fog
    /// or a volume), however often it scattered: the in-scattered light.
    Volume,
}

impl Component {
    pub const ALL: [Component; 4] = [
        Component::Emission,
        Component::Direct,
        Component::Indirect,
        Component::Volume,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Component::Emission => "emission",
            Component::Direct => "direct",
            Component::Indirect => "indirect",
            Component::Volume => "volume",
        }
    }

    /// Its position in [`Component::ALL`] and in per-component arrays.
    pub fn index(self) -> usize {
        self as usize
    }

    /// The component of light that scattered `events` times, the first
    /// scattering from the camera being `first` (`None`: it did not
    /// scatter).
    #[inline]
    pub fn of_path(first: Option<Scattering>, events: u32) -> Component {
        match first {
            None => Component::Emission,
            Some(Scattering::Medium) => Component::Volume,
            Some(Scattering::Surface) if events <= 1 => Component::Direct,
            Some(Scattering::Surface) => Component::Indirect,
        }
    }
}

/// Where light scattered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scattering {
    Surface,
    Medium,
}

/// One of the outputs a render can write beside the radiance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Aov {
    /// Reflectance of the first non-specular surface (RGB, 0–1).
    Albedo,
    /// Its world-space shading normal (XYZ, −1–1).
    Normal,
    /// Distance along the camera ray to the first surface (scene units).
    Depth,
    /// World-space point of the first surface (XYZ, scene units).
    Position,
    /// A component of the radiance (RGB, W·sr⁻¹·m⁻²).
    Component(Component),
    /// The radiance of each light group (RGB, W·sr⁻¹·m⁻²): one image
    /// per group, written as layers `light_group.<name>`.
    LightGroups,
}

impl Aov {
    pub const ALL: [Aov; 9] = [
        Aov::Albedo,
        Aov::Normal,
        Aov::Depth,
        Aov::Position,
        Aov::Component(Component::Emission),
        Aov::Component(Component::Direct),
        Aov::Component(Component::Indirect),
        Aov::Component(Component::Volume),
        Aov::LightGroups,
    ];

    /// Its name in flags, files and the Python API.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Albedo => "albedo",
            Aov::Normal => "normal",
            Aov::Depth => "depth",
            Aov::Position => "position",
            Aov::Component(c) => c.name(),
            Aov::LightGroups => "light_groups",
        }
    }

    pub fn from_name(name: &str) -> Option<Aov> {
        Aov::ALL.into_iter().find(|a| a.name() == name)
    }

    /// Whether it is a first-surface guide (kept by
    /// `RenderSettings::guides`) rather than a part of the radiance (a
    /// component, kept by `RenderSettings::components`, or the light
    /// groups, kept by `RenderSettings::light_groups`).
    pub fn is_guide(self) -> bool {
        !matches!(self, Aov::Component(_) | Aov::LightGroups)
    }

    /// Whether it is a radiance component.
    pub fn is_component(self) -> bool {
        matches!(self, Aov::Component(_))
    }

    /// The name of the layer of light group `group`'s image.
    pub fn light_group_layer(group: &str) -> String {
        format!("light_group.{group}")
    }

    /// Parses a comma-separated list of names (`albedo,normal`), each once.
    pub fn parse_list(list: &str) -> Result<Vec<Aov>, String> {
        let mut aovs = Vec::new();
        for name in list.split(',').map(str::trim) {
            let aov = Aov::from_name(name).ok_or_else(|| {
                let known: Vec<_> = Aov::ALL.iter().map(|a| a.name()).collect();
                format!("unknown AOV `{name}` (known: {})", known.join(", "))
            })?;
            if aovs.contains(&aov) {
                return Err(format!("AOV `{name}` is named twice"));
            }
            aovs.push(aov);
        }
        Ok(aovs)
    }
}

/// A pixel's radiance components summed over its samples (f64), indexed
/// by [`Component::index`].
pub type ComponentSum = [DVec3; 4];

/// The component images of a rectangle of pixels, indexed by
/// [`Component::index`]: each pixel the mean of its samples.
#[derive(Clone, Debug, PartialEq)]
pub struct Components(pub [Image; 4]);

impl Components {
    /// The means of `sums` (row-major, `width`×`height`) over `samples`
    /// samples per pixel.
    pub fn resolve(width: u32, height: u32, sums: &[ComponentSum], samples: u32) -> Components {
        let n = f64::from(samples.max(1));
        Components(Component::ALL.map(|c| {
            let pixels: Vec<Rgb> = sums.iter().map(|s| (s[c.index()] / n).as_vec3()).collect();
            Image::from_pixels(width, height, pixels)
        }))
    }

    pub fn get(&self, component: Component) -> &Image {
        &self.0[component.index()]
    }
}
