//! What `render` and `merge` write once the sums are in: the image,
//! denoised if asked (`--denoise`), with the AOVs asked for (`--aov`) as
//! layers of the OpenEXR file.

use anyhow::{Context, Result, bail};
use clap::Args;
use std::path::Path;
use tyndall::aov::Aov;
use tyndall::guides::Guides;
use tyndall::render::Accumulation;
use tyndall_denoise::{DenoiseGuides, Denoiser};
use tyndall_image::{AovLayer, ImageFormat, OutputFile};

/// The flags that choose what is written beside and instead of the raw
/// image.
#[derive(Args, Clone, Default)]
pub struct Finishing {
    /// Also write these AOVs, comma-separated, as layers of the .exr output:
    /// `albedo` and `normal` of the first non-specular surface (the
    /// denoiser's guides), `depth` (distance along the camera ray) and
    /// `position` of the first surface, the radiance's components
    /// `emission`, `direct`, `indirect` and `volume`, which sum to it, and
    /// `light_groups`, one layer `light_group.<name>` per light group of
    /// the scene, which sum to it too (docs/scene-format.md, "AOVs and
    /// denoising"). They are not denoised.
    #[arg(long, value_parser = parse_aovs)]
    pub aov: Option<AovList>,
    /// Denoise the image with Intel Open Image Denoise, guided by the
    /// first-surface albedo and normal (prefiltered). OIDN is loaded at run
    /// time: `pip install pyoidn` and set TYNDALL_OIDN to its library folder
    /// (an error says how when it is missing). Tiles and sample ranges are
    /// denoised by `tyndall merge --denoise`, after the merge.
    #[arg(long)]
    pub denoise: bool,
}

/// A list of AOVs, as `--aov` takes it.
#[derive(Clone, Debug, Default)]
pub struct AovList(pub Vec<Aov>);

fn parse_aovs(s: &str) -> Result<AovList, String> {
    Aov::parse_list(s).map(AovList)
}

/// The finishing, checked and ready: the AOVs and the loaded denoiser.
pub struct Finisher {
    aovs: Vec<Aov>,
    denoiser: Option<Denoiser>,
}

impl Finishing {
    /// Checks the flags against the output (`--aov` needs an .exr) and
    /// loads the denoiser, so that a render never starts whose image
    /// could not be finished.
    pub fn prepare(&self, output: &Path) -> Result<Finisher> {
        let aovs = self.aov.clone().unwrap_or_default().0;
        if !aovs.is_empty() && ImageFormat::from_path(output)? != ImageFormat::Exr {
            bail!(
                "{}: --aov writes the AOVs as OpenEXR layers, so the output must be an .exr file",
                output.display()
            );
        }
        let denoiser = if self.denoise {
            Some(Denoiser::find().context("--denoise")?)
        } else {
            None
        };
        Ok(Finisher { aovs, denoiser })
    }
}

impl Finisher {
    /// Whether the render must keep the first-surface guides.
    pub fn needs_guides(&self) -> bool {
        self.aovs.iter().any(|a| a.is_guide()) || self.denoiser.is_some()
    }

    /// Whether the render must keep the radiance's components.
    pub fn needs_components(&self) -> bool {
        self.aovs.iter().any(|a| a.is_component())
    }

    /// Whether the render must keep the light groups' radiance.
    pub fn needs_light_groups(&self) -> bool {
        self.aovs.contains(&Aov::LightGroups)
    }

    /// Whether anything but the raw image is written.
    pub fn finishes(&self) -> bool {
        !self.aovs.is_empty() || self.denoiser.is_some()
    }

    /// Resolves `accumulation`, denoises it if asked, and writes it with
    /// its AOVs to `output` (`exposure` for PNG).
    pub fn write(
        &self,
        output: OutputFile,
        accumulation: &Accumulation,
        exposure: f32,
    ) -> Result<()> {
        let image = accumulation.resolve();
        let guides = accumulation.resolve_guides();
        let components = accumulation.resolve_components();
        let group_images = accumulation.resolve_light_groups();
        let group_layers: Vec<String> = accumulation
            .light_groups
            .iter()
            .flat_map(|g| g.names())
            .map(|name| Aov::light_group_layer(name))
            .collect();
        let needed = |what: &str| -> Result<&Guides> {
            guides.as_ref().with_context(|| {
                format!("{what} needs the first-surface guides, which these sums do not hold")
            })
        };
        let image = match &self.denoiser {
            Some(denoiser) => {
                let g = needed("--denoise")?;
                let guides = DenoiseGuides {
                    albedo: &g.albedo,
                    normal: &g.normal,
                    prefilter: true,
                };
                denoiser
                    .denoise(&image, Some(guides))
                    .with_context(|| format!("--denoise ({})", denoiser.path().display()))?
            }
            None => image,
        };
        let mut layers: Vec<AovLayer> = Vec::with_capacity(self.aovs.len());
        for &aov in &self.aovs {
            let image = match aov {
                Aov::Component(c) => components.as_ref().map(|k| k.get(c)).with_context(|| {
                    format!("--aov {}: these sums do not hold the radiance's components (parts of renders with light paths do not)", aov.name())
                })?,
                Aov::LightGroups => {
                    let images = group_images.as_ref().with_context(|| {
                        "--aov light_groups: these sums do not hold the light groups' radiance (parts of scenes without named light groups, and of renders with light paths, do not)"
                    })?;
                    for (name, image) in group_layers.iter().zip(images) {
                        layers.push(AovLayer::radiance(name, image));
                    }
                    continue;
                }
                guide => needed("--aov")?.get(guide).expect("a guide"),
            };
            layers.push(AovLayer::new(aov, image));
        }
        output
            .finish_with_aovs(&image, &layers, exposure)
            .context("the image was not written")
    }
}
