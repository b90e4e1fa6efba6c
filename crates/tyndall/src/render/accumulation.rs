//! The per-pixel sums of a part of a render — a tile, a sample range, a
//! checkpoint — and the share of each pass's light paths a band of rows
//! traces.

use crate::aov::{ComponentSum, Components};
use crate::color::Rgb;
use crate::exact_sum::ExactRgb;
use crate::film::Image;
use crate::guides::{GuideSum, Guides};
use crate::light_groups::LightGroupSums;
use crate::region::{PixelRect, RenderRegion};
use glam::DVec3;

/// The unnormalised per-pixel sums of a part of a render: what a tile, a
/// sample range or a checkpoint holds. [`Accumulation::resolve`] turns it
/// into an image.
#[derive(Clone, Debug, PartialEq)]
pub struct Accumulation {
    /// Width of the full image, in pixels.
    pub width: u32,
    /// Height of the full image, in pixels.
    pub height: u32,
    /// The pixels held, and the sample indices summed so far.
    pub region: RenderRegion,
    /// Per pixel of `region.rect` (row-major), the sum of the camera-path
    /// radiance estimates of samples `region.samples` (non-finite
    /// estimates count as zero and are reported in [`RenderStats`]).
    pub camera: Vec<DVec3>,
    /// Per pixel of the *full* image (row-major), the exact sum of the
    /// light-path splats (radiance times the number of paths) of this
    /// part's share of each pass's light paths (see the module docs), for
    /// renders that trace them (`volpath` with caustics); `None` otherwise.
    pub light: Option<Vec<ExactRgb>>,
    /// Per pixel of `region.rect` (row-major), the sums of the
    /// first-surface guides of samples `region.samples`, for renders that
    /// compute them ([`RenderSettings::guides`]); `None` otherwise.
    ///
    /// [`RenderSettings::guides`]: crate::settings::RenderSettings::guides
    pub guides: Option<Vec<GuideSum>>,
    /// Per pixel of `region.rect` (row-major), the sums of the radiance's
    /// components of samples `region.samples`, for renders that keep them
    /// ([`RenderSettings::components`]); `None` otherwise. They add up to
    /// `camera` to rounding.
    ///
    /// [`RenderSettings::components`]: crate::settings::RenderSettings::components
    pub components: Option<Vec<ComponentSum>>,
    /// Per pixel of `region.rect`, the sums of each light group's
    /// radiance of samples `region.samples`, for renders that keep them
    /// ([`RenderSettings::light_groups`]); `None` otherwise. They add up
    /// to `camera` to rounding.
    ///
    /// [`RenderSettings::light_groups`]: crate::settings::RenderSettings::light_groups
    pub light_groups: Option<LightGroupSums>,
}

impl Accumulation {
    /// No samples yet of `rect`, starting at sample index `first_sample`.
    /// With `kept.guides`, `kept.components` and `kept.light_groups`,
    /// their sums are kept too.
    pub fn new(
        (width, height): (u32, u32),
        rect: PixelRect,
        first_sample: u32,
        light: bool,
        kept: Kept,
    ) -> Self {
        Self {
            width,
            height,
            region: RenderRegion {
                rect,
                samples: first_sample..first_sample,
            },
            camera: vec![DVec3::ZERO; rect.area()],
            light: light.then(|| vec![ExactRgb::ZERO; width as usize * height as usize]),
            guides: kept.guides.then(|| vec![GuideSum::default(); rect.area()]),
            components: kept
                .components
                .then(|| vec![ComponentSum::default(); rect.area()]),
            light_groups: (!kept.light_groups.is_empty())
                .then(|| LightGroupSums::new(rect.area(), &kept.light_groups)),
        }
    }

    /// Samples per pixel summed.
    pub fn passes(&self) -> u32 {
        self.region.samples.len() as u32
    }

    /// This part's light paths per pass: one per pixel of its rows.
    pub fn light_paths_per_pass(&self) -> u64 {
        let share = light_share(self.width, self.region.rect);
        share.end - share.start
    }

    /// The image of the rectangle: each pixel the mean of its camera
    /// samples plus its light splats over the light paths this part traced
    /// (for a tile, an estimate from its share of the paths; for the whole
    /// image, the render); black before the first pass.
    pub fn resolve(&self) -> Image {
        let n = self.passes();
        let rect = self.region.rect;
        if n == 0 {
            return Image::from_pixels(rect.width(), rect.height(), vec![Rgb::ZERO; rect.area()]);
        }
        let light_scale = 1.0 / (self.light_paths_per_pass() as f64 * n as f64);
        let width = rect.width() as usize;
        let pixels = self
            .camera
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let mut p = (*c / n as f64).as_vec3();
                if let Some(light) = &self.light {
                    let (x, y) = (rect.x0 as usize + i % width, rect.y0 as usize + i / width);
                    let full = y * self.width as usize + x;
                    p += (light[full].to_dvec3() * light_scale).as_vec3();
                }
                p
            })
            .collect();
        Image::from_pixels(rect.width(), rect.height(), pixels)
    }

    /// The guide images of the rectangle (the means of its samples), if
    /// this part holds their sums.
    pub fn resolve_guides(&self) -> Option<Guides> {
        let rect = self.region.rect;
        let sums = self.guides.as_ref()?;
        Some(Guides::resolve(
            rect.width(),
            rect.height(),
            sums,
            self.passes(),
        ))
    }

    /// The component images of the rectangle (the means of its samples),
    /// if this part holds their sums.
    pub fn resolve_components(&self) -> Option<Components> {
        let rect = self.region.rect;
        let sums = self.components.as_ref()?;
        Some(Components::resolve(
            rect.width(),
            rect.height(),
            sums,
            self.passes(),
        ))
    }

    /// The light groups' images of the rectangle (the means of its
    /// samples, by [`crate::light_groups::LightGroup::index`]), if this
    /// part holds their sums.
    pub fn resolve_light_groups(&self) -> Option<Vec<Image>> {
        let rect = self.region.rect;
        let sums = self.light_groups.as_ref()?;
        Some(sums.resolve(rect.width(), rect.height(), self.passes()))
    }

    /// What this part keeps beside the radiance.
    pub fn kept(&self) -> Kept {
        Kept {
            guides: self.guides.is_some(),
            components: self.components.is_some(),
            light_groups: self
                .light_groups
                .as_ref()
                .map_or_else(Vec::new, |g| g.names().to_vec()),
        }
    }

    /// Adds the sums of `next`, the same pixels for the sample indices
    /// that follow this one's.
    pub fn append(&mut self, next: &Accumulation) -> Result<(), String> {
        if (self.width, self.height) != (next.width, next.height)
            || self.region.rect != next.region.rect
            || self.light.is_some() != next.light.is_some()
            || self.kept() != next.kept()
        {
            return Err("the parts hold different images or pixels".into());
        }
        if next.region.samples.start != self.region.samples.end {
            return Err(format!(
                "samples {:?} do not follow samples {:?}",
                next.region.samples, self.region.samples
            ));
        }
        for (a, b) in self.camera.iter_mut().zip(&next.camera) {
            *a += *b;
        }
        if let (Some(a), Some(b)) = (&mut self.light, &next.light) {
            for (a, b) in a.iter_mut().zip(b) {
                a.add_exact(b);
            }
        }
        if let (Some(a), Some(b)) = (&mut self.guides, &next.guides) {
            for (a, b) in a.iter_mut().zip(b) {
                a.append(b);
            }
        }
        if let (Some(a), Some(b)) = (&mut self.components, &next.components) {
            for (a, b) in a.iter_mut().zip(b) {
                for (a, b) in a.iter_mut().zip(b) {
                    *a += *b;
                }
            }
        }
        if let (Some(a), Some(b)) = (&mut self.light_groups, &next.light_groups) {
            a.append(b);
        }
        self.region.samples.end = next.region.samples.end;
        Ok(())
    }
}

/// What a part keeps beside the radiance: the first-surface guides, the
/// radiance's components, and its light groups (their names; none: not
/// kept).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Kept {
    pub guides: bool,
    pub components: bool,
    pub light_groups: Vec<String>,
}

impl Kept {
    /// What a render of `scene` with `settings` keeps.
    pub fn by(settings: &crate::settings::RenderSettings, scene: &crate::Scene) -> Kept {
        Kept {
            guides: settings.guides,
            components: settings.components,
            light_groups: if settings.light_groups {
                scene.light_groups().names().to_vec()
            } else {
                Vec::new()
            },
        }
    }
}

/// The in-pass indices of the light paths that a band of whole rows
/// (`rect`, in an image `width` wide) traces: one per pixel of its rows,
/// `y0·W .. y1·W`. Bands that partition the image partition the paths.
pub fn light_share(width: u32, rect: PixelRect) -> std::ops::Range<u64> {
    rect.y0 as u64 * width as u64..rect.y1 as u64 * width as u64
}
