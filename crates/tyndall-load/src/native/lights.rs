//! `[[lights]]` tables: point, spot, directional, quad and environment
//! lights, their
//! colour temperature, and the measured (IES) profiles of point and spot
//! lights (docs/scene-format.md, "Measured profiles").

use super::Loader;
use super::tables::*;
use crate::photometry::candela_to_watts_per_sr;
use crate::source::SceneError;
use glam::Vec3;
use serde_spanned::Spanned;
use std::f32::consts::PI;
use std::ops::Range;
use std::sync::Arc;
use tyndall::color::{Rgb, blackbody};
use tyndall::description::{LightDesc, SceneDesc};
use tyndall::lights::gobo::Gobo;
use tyndall::lights::photometric::Luminaire;
use tyndall::lights::{DirectionalLight, EnvironmentLight, PointLight, SpotLight, SpotProfile};
use tyndall::texture::Wrap;

impl Loader<'_> {
    pub(super) fn light(
        &self,
        desc: &Spanned<LightTable>,
        scene: &mut SceneDesc,
    ) -> Result<(), SceneError> {
        let span = desc.span();
        let origin = self.origin(&span);
        match desc.get_ref() {
            LightTable::Point(PointTable {
                position,
                intensity,
                power,
                direction,
                temperature_k,
                ies,
                ies_rotate_deg,
                light_group: _,
            }) => {
                let nadir = match direction {
                    Some(d) => self.direction(&span, "direction", *d)?,
                    None => -Vec3::Y,
                };
                let measured = self.luminaire(&span, ies, *ies_rotate_deg, nadir)?;
                if measured.is_none() && direction.is_some() {
                    return Err(self.err(
                        &span,
                        "direction",
                        "a point light's `direction` is the nadir of an `ies` profile, and there is none",
                    ));
                }
                let mean = measured.as_ref().map_or(1.0, |(l, _)| l.profile.mean());
                let intensity = match (intensity, power, &measured) {
                    (Some(i), None, _) => self.emission(&span, "intensity", *i)?,
                    // The peak intensity of the power the profile spreads.
                    (None, Some(p), _) => self.emission(&span, "power", *p)? / (4.0 * PI * mean),
                    (None, None, Some((_, candela))) => {
                        Rgb::splat(candela_to_watts_per_sr(*candela))
                    }
                    _ => {
                        return Err(self.err(
                            &span,
                            "position",
                            "a point light needs exactly one of `intensity` (W/sr) or `power` (W) \
                             (or neither, with an `ies` profile: then the file's candela)",
                        ));
                    }
                };
                let tint = self.temperature(&span, *temperature_k)?;
                scene.add_light(
                    LightDesc::Point(PointLight {
                        position: Vec3::from_array(*position),
                        intensity: intensity * tint,
                        luminaire: measured.map(|(l, _)| l),
                    }),
                    origin,
                );
            }
            LightTable::Spot(SpotTable {
                position,
                direction,
                look_at,
                cutoff_deg,
                profile,
                inner_deg,
                intensity,
                temperature_k,
                ies,
                ies_rotate_deg,
                gobo,
                gobo_rotate_deg,
                light_group: _,
            }) => {
                let position = self.vec3(&span, "position", *position)?;
                let direction = match (direction, look_at) {
                    (Some(d), None) => self.direction(&span, "direction", *d)?,
                    (None, Some(t)) => {
                        let t = self.vec3(&span, "look_at", *t)?;
                        if t == position {
                            return Err(self.err(
                                &span,
                                "look_at",
                                "`look_at` must differ from `position`",
                            ));
                        }
                        // Scaled before normalising: a `look_at` 1e-45 away
                        // would otherwise normalise to NaN.
                        self.direction(&span, "look_at", (t - position).to_array())?
                    }
                    _ => {
                        return Err(self.err(
                            &span,
                            "position",
                            "a spot light needs exactly one of `direction` or `look_at`",
                        ));
                    }
                };
                let cutoff = self.number(
                    &span,
                    "cutoff_deg",
                    *cutoff_deg,
                    (f32::MIN_POSITIVE, 90.0),
                    "a half-angle in (0°, 90°]",
                )?;
                let cos_cutoff = cutoff.to_radians().cos();
                let profile = match (profile.as_deref().unwrap_or("linear"), inner_deg) {
                    ("linear", None) => SpotProfile::Linear,
                    ("hard", None) => SpotProfile::Hard,
                    ("smooth", Some(inner)) => {
                        let inner = self.number(&span, "inner_deg", *inner, (0.0, cutoff), "an angle in [0°, cutoff_deg)")?;
                        if inner >= cutoff {
                            return Err(self.err(&span, "inner_deg", format!("`inner_deg` must be below `cutoff_deg` ({cutoff}), got {inner}")));
                        }
                        SpotProfile::Smooth { cos_inner: inner.to_radians().cos() }
                    }
                    ("smooth", None) => return Err(self.err(&span, "profile", "the `smooth` profile needs `inner_deg`, the angle where the fall-off starts")),
                    ("linear" | "hard", Some(_)) => return Err(self.err(&span, "inner_deg", "`inner_deg` applies only to the `smooth` profile")),
                    (other, _) => return Err(self.err(&span, "profile", format!("unknown spot profile `{other}`: expected `linear`, `smooth` or `hard`"))),
                };
                let measured = self.luminaire(&span, ies, *ies_rotate_deg, direction)?;
                let intensity = match (intensity, &measured) {
                    (Some(i), _) => Rgb::from_array(i.0),
                    (None, Some((_, candela))) => Rgb::splat(candela_to_watts_per_sr(*candela)),
                    (None, None) => {
                        return Err(self.err(
                            &span,
                            "position",
                            "a spot light needs `intensity` (W/sr on its axis), \
                             unless an `ies` profile gives the file's candela",
                        ));
                    }
                };
                let tint = self.temperature(&span, *temperature_k)?;
                let gobo = self.gobo(&span, gobo, *gobo_rotate_deg, direction, cutoff)?;
                scene.add_light(
                    LightDesc::Spot(SpotLight {
                        gobo,
                        position,
                        direction,
                        cos_cutoff,
                        profile,
                        intensity: intensity * tint,
                        luminaire: measured.map(|(l, _)| l),
                    }),
                    origin,
                );
            }
            LightTable::Directional(DirectionalTable {
                direction,
                irradiance,
                temperature_k,
                light_group: _,
            }) => {
                let tint = self.temperature(&span, *temperature_k)?;
                scene.add_light(
                    LightDesc::Directional(DirectionalLight {
                        direction: self.direction(&span, "direction", *direction)?,
                        irradiance: Rgb::from_array(irradiance.0) * tint,
                    }),
                    origin,
                );
            }
            LightTable::Quad(QuadLightTable {
                corners,
                radiance,
                two_sided,
                temperature_k,
                light_group: _,
            }) => {
                let quad = self.quad(&span, corners, false)?;
                let radiance =
                    Rgb::from_array(radiance.0) * self.temperature(&span, *temperature_k)?;
                scene.add_quad_light(quad, radiance, *two_sided, origin);
            }
            LightTable::Environment(EnvironmentTable {
                radiance,
                map,
                map_rotate_deg,
                temperature_k,
                light_group: _,
            }) => {
                let tint = self.temperature(&span, *temperature_k)?;
                let scale = match radiance {
                    Some(r) => Some(self.emission(&span, "radiance", *r)? * tint),
                    None => None,
                };
                let light = match (self.turned_file(&span, "map", map, *map_rotate_deg)?, scale) {
                    (Some((path, rotate)), scale) => {
                        let map = crate::images::load_environment_map(&path).map_err(|e| {
                            self.err(&span, "map", format!("the environment's `map`: {e}"))
                        })?;
                        EnvironmentLight::mapped(Arc::new(map), scale.unwrap_or(tint), rotate)
                    }
                    (None, Some(scale)) => EnvironmentLight::uniform(scale),
                    (None, None) => {
                        return Err(self.err(
                            &span,
                            "type",
                            "an environment light needs `radiance` (W/(m²·sr), the same from \
                             every direction) or a `map` (an OpenEXR or Radiance HDR file)",
                        ));
                    }
                };
                scene.add_light(LightDesc::Environment(light), origin);
            }
        }
        Ok(())
    }

    /// The colour of a light of colour temperature `kelvin` (none: white):
    /// the blackbody's colour at luminance 1 (as for blackbody media,
    /// docs/physics.md §2.5), channels below 0 clipped (below about
    /// 1900 K the blackbody is bluer than Rec. 709's gamut allows).
    fn temperature(&self, span: &Range<usize>, kelvin: Option<f32>) -> Result<Rgb, SceneError> {
        let Some(kelvin) = kelvin else {
            return Ok(Rgb::ONE);
        };
        let kelvin = self.number(
            span,
            "temperature_k",
            kelvin,
            (800.0, 100_000.0),
            "a temperature from 800 K to 100000 K",
        )?;
        Ok(blackbody::unit_luminance_rgb(f64::from(kelvin)).max(Rgb::ZERO))
    }

    /// The file a pattern key (`gobo`, `ies`, `map`) names, relative to the scene,
    /// with the turn its `{key}_rotate_deg` gives it (default 0°); `None`
    /// without the key, where the turn alone is an error.
    fn turned_file(
        &self,
        span: &Range<usize>,
        key: &str,
        file: &Option<String>,
        rotate_deg: Option<f32>,
    ) -> Result<Option<(std::path::PathBuf, f32)>, SceneError> {
        let turn = format!("{key}_rotate_deg");
        let Some(file) = file else {
            if rotate_deg.is_some() {
                return Err(self.err(
                    span,
                    &turn,
                    format!("`{turn}` turns what `{key}` names, and there is no `{key}`"),
                ));
            }
            return Ok(None);
        };
        let rotate = self.number(
            span,
            &turn,
            rotate_deg.unwrap_or(0.0),
            (-360.0, 360.0),
            "an angle in [−360°, 360°]",
        )?;
        Ok(Some((self.relative(file), rotate)))
    }

    /// The gobo a spot's `gobo` key names (an image file), projected along
    /// `axis` into the cone of `cutoff_deg` and turned by
    /// `gobo_rotate_deg`; `None` without the key.
    fn gobo(
        &self,
        span: &Range<usize>,
        file: &Option<String>,
        rotate_deg: Option<f32>,
        axis: Vec3,
        cutoff_deg: f32,
    ) -> Result<Option<Gobo>, SceneError> {
        let Some((path, rotate)) = self.turned_file(span, "gobo", file, rotate_deg)? else {
            return Ok(None);
        };
        let image = self
            .gobo_images
            .get_or_read(&path, |path| {
                crate::images::load_texture(path, [Wrap::Clamp; 2]).map(Arc::new)
            })
            .map_err(|e| self.err(span, "gobo", e))?;
        Gobo::new(image, axis, cutoff_deg, rotate)
            .map(Some)
            .map_err(|e| self.err(span, "cutoff_deg", e))
    }

    /// The measured profile an `ies` key names, placed with its nadir
    /// along `nadir` and its 0° plane turned by `ies_rotate_deg`, with the
    /// file's peak candela; `None` without the key.
    fn luminaire(
        &self,
        span: &Range<usize>,
        ies: &Option<String>,
        rotate_deg: Option<f32>,
        nadir: Vec3,
    ) -> Result<Option<(Luminaire, f32)>, SceneError> {
        let Some((path, rotate)) = self.turned_file(span, "ies", ies, rotate_deg)? else {
            return Ok(None);
        };
        let measured = self
            .ies_files
            .get_or_read(&path, crate::ies::load)
            .map_err(|e| self.err(span, "ies", e))?;
        Ok(Some((
            Luminaire::new(measured.profile, nadir, rotate),
            measured.peak_candela,
        )))
    }
}
