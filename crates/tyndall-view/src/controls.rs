//! The live controls: what each key and slider changes in the scene
//! description, within the ranges the loader accepts ([`LiveScene::set`]
//! keeps them, for keys and sliders alike), and a one-line summary of the
//! current values for the window title.
//!
//! | key | control |
//! |---|---|
//! | `1` / `2` | fog density σt ÷ / × 1.25 (adds fog of σt 0.05 if there is none) |
//! | `3` / `4` | fog albedo − / + 0.05 |
//! | `5` / `6` | HG asymmetry g − / + 0.05 (in [−0.95, 0.95]) |
//! | `7` / `8` | march step ÷ / × 1.25 |
//! | `9` / `0` | exposure − / + 0.25 stops |
//! | `Tab` | select the next light |
//! | `[` / `]` | selected light's intensity ÷ / × 1.25 |
//! | `-` / `=` | selected spot's cone cutoff − / + 1° (1° or its inner cone + 0.5°, to 89.5°) |
//! | arrows | selected spot or sun: direction yaw (←/→) and pitch (↑/↓) by 3° |
//! | `G` | glass model: filter ↔ blend |
//! | `I` | in-scattering: the march ↔ unbiased single scattering (interleaved equiangular samples) |

use glam::{Quat, Vec2, Vec3};
use tyndall::Rgb;
use tyndall::description::{LightDesc, Sourced};
use tyndall::glass::GlassModel;
use tyndall::lights::SpotProfile;
use tyndall::limits;
use tyndall::media::Fog;
use tyndall::phase::PhaseFunction;
use tyndall::{IntegratorKind, SceneDesc};

/// A change to the scene that restarts accumulation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Control {
    /// Multiply fog density by the factor.
    Density(f32),
    /// Add to the fog albedo (grey).
    Albedo(f32),
    /// Add to the HG asymmetry g.
    Asymmetry(f32),
    /// Multiply the march step by the factor.
    Step(f32),
    /// Add stops of exposure (display only: no restart needed).
    Exposure(f32),
    /// Select the next light.
    NextLight,
    /// Multiply the selected light's intensity (irradiance for a sun).
    Intensity(f32),
    /// Widen the selected spot's cone by degrees.
    Cutoff(f32),
    /// Turn the selected spot or sun: yaw and pitch in degrees.
    Turn { yaw: f32, pitch: f32 },
    /// Switch the glass model between filter and blend.
    GlassModel,
    /// Switch the in-scattering estimator between the march and `single`.
    Estimator,
}

impl Control {
    /// Whether the change alters the rendered radiance (and so restarts
    /// accumulation); exposure and the light selection do not.
    pub fn changes_radiance(self) -> bool {
        !matches!(self, Control::Exposure(_) | Control::NextLight)
    }
}

/// An absolute value of one control: what a slider sets, and what a key's
/// relative [`Control`] step becomes before it is applied.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Setting {
    /// Fog extinction coefficient σt (1/scene unit); adds fog if none.
    Density(f32),
    /// Fog single-scattering albedo per channel.
    Albedo(Rgb),
    /// HG asymmetry g.
    Asymmetry(f32),
    /// March step length (scene units).
    Step(f32),
    /// Exposure in stops (display only).
    Exposure(f32),
    /// A light's radiant intensity (W/sr; irradiance W/m² for a sun).
    Intensity {
        light: usize,
        emission: Rgb,
    },
    /// A spot's cone cutoff half-angle in degrees.
    Cutoff {
        light: usize,
        degrees: f32,
    },
    /// A spot's axis or the direction a sun's light travels (normalised
    /// here).
    Direction {
        light: usize,
        direction: Vec3,
    },
    GlassModel(GlassModel),
    /// The in-scattering estimator: `March` or `Single` (the GPU's two;
    /// `single` takes the scene's `volume_samples` per light).
    Estimator(IntegratorKind),
}

impl Setting {
    /// Whether the change alters the rendered radiance (and so restarts
    /// accumulation); exposure does not.
    pub fn changes_radiance(self) -> bool {
        !matches!(self, Setting::Exposure(_))
    }
}

/// Range of the fog density σt the controls keep to.
pub const MIN_FOG_DENSITY: f32 = 1e-4;
pub const MAX_FOG_DENSITY: f32 = 1e3;
/// Range of the march step the controls keep to.
pub const MIN_STEP: f32 = 1e-3;
pub const MAX_STEP: f32 = 10.0;
/// |g| the controls keep to (HG is degenerate at ±1).
pub const MAX_ASYMMETRY: f32 = 0.95;
/// |exposure| in stops the controls keep to.
pub const MAX_EXPOSURE_STOPS: f32 = 20.0;

/// The cutoffs (degrees) a spot of `profile` may take: at least 1° (and
/// 0.5° past a smooth profile's inner cone, which must stay inside); at
/// most 89.5°, not 90°: cos(90°) rounds below 0 in f32, which reads back
/// as just over the loader's 90°.
pub fn cutoff_range(profile: &SpotProfile) -> (f32, f32) {
    let min = match profile {
        SpotProfile::Smooth { cos_inner } => cos_inner.clamp(-1.0, 1.0).acos().to_degrees() + 0.5,
        _ => 1.0,
    };
    (min.min(89.5), 89.5)
}

/// A light's emission: intensity (W/sr), a sun's irradiance (W/m²) or
/// an environment's radiance scale.
pub fn emission(light: &LightDesc) -> Rgb {
    match light {
        LightDesc::Point(l) => l.intensity,
        LightDesc::Spot(l) => l.intensity,
        LightDesc::Directional(l) => l.irradiance,
        LightDesc::Environment(l) => l.scale,
    }
}

/// A spot's axis or a sun's direction of travel.
pub fn direction(light: &LightDesc) -> Result<Vec3, String> {
    match light {
        LightDesc::Spot(l) => Ok(l.direction),
        LightDesc::Directional(l) => Ok(l.direction),
        LightDesc::Point(_) => Err("a point light has no direction".into()),
        LightDesc::Environment(_) => Err("an environment has no direction".into()),
    }
}

/// Fog density given to a scene without fog when density is raised.
pub const NEW_FOG_DENSITY: f32 = 0.05;
/// Degrees the arrows turn a light by.
pub const TURN_DEGREES: f32 = 3.0;

/// The scene being viewed and which light the light controls act on.
pub struct LiveScene {
    pub desc: SceneDesc,
    pub selected_light: usize,
}

impl LiveScene {
    /// The view of `desc`, rendered with `march` at first (the GPU's
    /// integrator that also accepts the paper's albedos above 1; `I`
    /// switches to `single`).
    pub fn new(mut desc: SceneDesc) -> Self {
        desc.settings.integrator = IntegratorKind::March;
        Self {
            desc,
            selected_light: 0,
        }
    }

    /// Applies `control` (a key's relative step) as the absolute
    /// [`Setting`] it leads to, through [`LiveScene::set`]; `Err` says why
    /// it did nothing (no fog, no light, not a spot, a limit reached).
    pub fn apply(&mut self, control: Control) -> Result<(), String> {
        let light = self.selected_light;
        let setting = match control {
            Control::Density(f) => match &self.desc.fog {
                Some(fog) => Setting::Density(fog.value.sigma_t * f),
                None => Setting::Density(NEW_FOG_DENSITY),
            },
            Control::Albedo(d) => Setting::Albedo(self.fog()?.albedo + Rgb::splat(d)),
            Control::Asymmetry(d) => Setting::Asymmetry(asymmetry(&self.fog()?.phase) + d),
            Control::Step(f) => Setting::Step(self.desc.settings.step * f),
            Control::Exposure(d) => Setting::Exposure(self.desc.settings.exposure + d),
            Control::NextLight => {
                if self.desc.lights.is_empty() {
                    return Err("the scene has no point, spot or directional light".into());
                }
                self.selected_light = (self.selected_light + 1) % self.desc.lights.len();
                return Ok(());
            }
            Control::Intensity(f) => Setting::Intensity {
                light,
                emission: emission(self.light(light)?) * f,
            },
            Control::Cutoff(d) => match self.light(light)? {
                LightDesc::Spot(l) => Setting::Cutoff {
                    light,
                    degrees: l.cos_cutoff.clamp(-1.0, 1.0).acos().to_degrees() + d,
                },
                _ => return Err("the selected light is not a spot".into()),
            },
            Control::Turn { yaw, pitch } => Setting::Direction {
                light,
                direction: turn(direction(self.light(light)?)?, yaw, pitch),
            },
            Control::GlassModel => Setting::GlassModel(match self.desc.glass.model {
                GlassModel::Filter => GlassModel::Blend,
                GlassModel::Blend => GlassModel::Filter,
            }),
            Control::Estimator => Setting::Estimator(match self.desc.settings.integrator {
                IntegratorKind::Single => IntegratorKind::March,
                _ => IntegratorKind::Single,
            }),
        };
        self.set(setting)
    }

    /// Sets one value, kept within the ranges the loader and the
    /// renderer accept (the one place those clamps are applied, for keys
    /// and sliders alike); `Err` says why it did nothing.
    pub fn set(&mut self, setting: Setting) -> Result<(), String> {
        let desc = &mut self.desc;
        match setting {
            Setting::Density(sigma_t) => {
                let sigma_t = sigma_t.clamp(MIN_FOG_DENSITY, MAX_FOG_DENSITY);
                match &mut desc.fog {
                    Some(fog) => fog.value.sigma_t = sigma_t,
                    None => {
                        desc.fog = Some(Sourced::code(Fog {
                            sigma_t,
                            albedo: Rgb::splat(1.0),
                            phase: PhaseFunction::Isotropic,
                            bounds: None,
                        }))
                    }
                }
            }
            Setting::Albedo(albedo) => {
                // The paper's albedos above 1 only under the march.
                let max = match desc.settings.integrator {
                    IntegratorKind::March => limits::MAX_FOG_ALBEDO,
                    _ => 1.0,
                };
                self.fog_mut()?.albedo = albedo.clamp(Rgb::ZERO, Rgb::splat(max));
            }
            Setting::Asymmetry(g) => {
                let g = g.clamp(-MAX_ASYMMETRY, MAX_ASYMMETRY);
                // Snap accumulated key steps back onto 0 exactly.
                let g = if g.abs() < 1e-4 { 0.0 } else { g };
                self.fog_mut()?.phase = PhaseFunction::from_asymmetry(g);
            }
            Setting::Step(step) => desc.settings.step = step.clamp(MIN_STEP, MAX_STEP),
            Setting::Exposure(stops) => {
                desc.settings.exposure = stops.clamp(-MAX_EXPOSURE_STOPS, MAX_EXPOSURE_STOPS)
            }
            Setting::Intensity { light, emission } => {
                if !(emission.is_finite() && emission.max_element() <= limits::MAX_EMISSION) {
                    return Err("the light is at the largest emission the renderer takes".into());
                }
                let emission = emission.max(Rgb::ZERO);
                match self.light_mut(light)? {
                    LightDesc::Point(l) => l.intensity = emission,
                    LightDesc::Spot(l) => l.intensity = emission,
                    LightDesc::Directional(l) => l.irradiance = emission,
                    LightDesc::Environment(l) => l.scale = emission,
                }
            }
            Setting::Cutoff { light, degrees } => match self.light_mut(light)? {
                LightDesc::Spot(l) => {
                    let (min, max) = cutoff_range(&l.profile);
                    l.cos_cutoff = degrees.clamp(min, max).to_radians().cos();
                }
                _ => return Err("the light is not a spot".into()),
            },
            Setting::Direction { light, direction } => {
                if !(direction.is_finite() && direction.length_squared() > 1e-12) {
                    return Err("a light's direction must be a nonzero vector".into());
                }
                match self.light_mut(light)? {
                    LightDesc::Spot(l) => l.direction = direction.normalize(),
                    LightDesc::Directional(l) => l.direction = direction.normalize(),
                    LightDesc::Point(_) => return Err("a point light has no direction".into()),
                    LightDesc::Environment(_) => {
                        return Err("an environment has no direction".into());
                    }
                }
            }
            Setting::GlassModel(model) => desc.glass.model = model,
            Setting::Estimator(kind) => match kind {
                IntegratorKind::March => desc.settings.integrator = kind,
                IntegratorKind::Single => {
                    if desc
                        .fog
                        .as_ref()
                        .is_some_and(|f| f.value.albedo.max_element() > 1.0)
                    {
                        return Err("single scattering takes only a physical fog albedo (at most 1); the march renders the paper's".into());
                    }
                    desc.settings.integrator = kind;
                }
                IntegratorKind::Volpath => {
                    return Err("the GPU view renders the march or single scattering".into());
                }
            },
        }
        Ok(())
    }

    fn fog(&self) -> Result<&Fog, String> {
        self.desc
            .fog
            .as_ref()
            .map(|f| &f.value)
            .ok_or_else(|| "no fog (raise the density first)".to_string())
    }

    fn fog_mut(&mut self) -> Result<&mut Fog, String> {
        self.desc
            .fog
            .as_mut()
            .map(|f| &mut f.value)
            .ok_or_else(|| "no fog (raise the density first)".to_string())
    }

    fn light(&self, index: usize) -> Result<&LightDesc, String> {
        self.desc
            .lights
            .get(index)
            .map(|l| &l.value)
            .ok_or_else(|| "the scene has no point, spot or directional light".to_string())
    }

    fn light_mut(&mut self, index: usize) -> Result<&mut LightDesc, String> {
        self.desc
            .lights
            .get_mut(index)
            .map(|l| &mut l.value)
            .ok_or_else(|| "the scene has no point, spot or directional light".to_string())
    }

    /// The current values, for the window title and the log.
    pub fn summary(&self) -> String {
        let d = &self.desc;
        let fog = match &d.fog {
            Some(f) => format!(
                "σt {:.3} albedo {:.2} g {:.2}",
                f.value.sigma_t,
                f.value.albedo.max_element(),
                asymmetry(&f.value.phase)
            ),
            None => "no fog".into(),
        };
        let light = match d.lights.get(self.selected_light).map(|l| &l.value) {
            None => "no light".into(),
            Some(l) => {
                let n = format!("light {}/{}", self.selected_light + 1, d.lights.len());
                match l {
                    LightDesc::Point(p) => format!("{n} point I {:.3}", p.intensity.max_element()),
                    LightDesc::Spot(s) => format!(
                        "{n} spot I {:.3} cutoff {:.1}° dir {}",
                        s.intensity.max_element(),
                        s.cos_cutoff.clamp(-1.0, 1.0).acos().to_degrees(),
                        short(s.direction)
                    ),
                    LightDesc::Directional(s) => format!(
                        "{n} sun E {:.3} dir {}",
                        s.irradiance.max_element(),
                        short(s.direction)
                    ),
                    LightDesc::Environment(e) => format!(
                        "{n} environment L {:.3}{}",
                        e.scale.max_element(),
                        if e.map.is_some() { " × map" } else { "" }
                    ),
                }
            }
        };
        let glass = match d.glass.model {
            GlassModel::Filter => "filter",
            GlassModel::Blend => "blend",
        };
        let estimator = match d.settings.integrator {
            IntegratorKind::Single => format!("single {}/light", d.settings.volume_samples),
            _ => format!("march step {:.4}", d.settings.step),
        };
        format!(
            "{fog} {estimator} | {light} | glass {glass} | exposure {:+.2}",
            d.settings.exposure
        )
    }
}

/// The HG asymmetry of a phase function (0 for isotropic).
pub fn asymmetry(phase: &PhaseFunction) -> f32 {
    match phase {
        PhaseFunction::Isotropic => 0.0,
        PhaseFunction::HenyeyGreenstein { g } => *g,
    }
}

/// The azimuth (degrees about the y axis from +z towards +x, in
/// [−180°, 180°]) and elevation (degrees above the horizontal plane) of a
/// unit `direction`: the angles of the panel's direction sliders.
pub fn direction_angles(direction: Vec3) -> (f32, f32) {
    let d = direction.normalize();
    (
        d.x.atan2(d.z).to_degrees(),
        // atan2, not asin: well conditioned near the poles too.
        d.y.atan2(Vec2::new(d.x, d.z).length()).to_degrees(),
    )
}

/// The unit direction of `azimuth` and `elevation` (degrees), the inverse
/// of [`direction_angles`].
pub fn direction_from_angles(azimuth: f32, elevation: f32) -> Vec3 {
    let (a, e) = (azimuth.to_radians(), elevation.to_radians());
    Vec3::new(e.cos() * a.sin(), e.sin(), e.cos() * a.cos())
}

/// `direction` turned by `yaw` degrees about the world's y axis and
/// `pitch` degrees about its horizontal normal, kept off the vertical.
fn turn(direction: Vec3, yaw: f32, pitch: f32) -> Vec3 {
    let d = Quat::from_rotation_y(yaw.to_radians()) * direction.normalize();
    let side = d.cross(Vec3::Y);
    if side.length_squared() < 1e-8 {
        // Straight up or down: pitch about x instead.
        return (Quat::from_rotation_x(pitch.to_radians()) * d).normalize();
    }
    let turned = Quat::from_axis_angle(side.normalize(), pitch.to_radians()) * d;
    turned.normalize()
}

fn short(v: Vec3) -> String {
    format!("({:.2}, {:.2}, {:.2})", v.x, v.y, v.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EVERY_CONTROL: [Control; 15] = [
        Control::Density(1.25),
        Control::Density(0.8),
        Control::Albedo(0.05),
        Control::Albedo(-0.05),
        Control::Asymmetry(0.05),
        Control::Asymmetry(-0.05),
        Control::Step(1.25),
        Control::Step(0.8),
        Control::Intensity(1.25),
        Control::Intensity(0.8),
        Control::Cutoff(1.0),
        Control::Cutoff(-1.0),
        Control::Turn {
            yaw: 3.0,
            pitch: 3.0,
        },
        Control::GlassModel,
        Control::Estimator,
    ];

    /// Held down for 500 presses, every control keeps the scene one the
    /// renderer accepts (validation and the limits found by fuzzing).
    #[test]
    fn held_controls_keep_the_scene_valid() {
        for control in EVERY_CONTROL {
            for light in 0..2 {
                let mut live = LiveScene::new(tyndall_load::demo::load().expect("demo"));
                live.selected_light = light;
                for _ in 0..500 {
                    let _ = live.apply(control);
                }
                if let Err(e) = crate::accumulator::build_scene(&live.desc) {
                    panic!("{control:?} on light {light}: {e:#}");
                }
            }
        }
    }

    #[test]
    fn one_press_changes_what_it_says() {
        let demo = tyndall_load::demo::load().expect("demo");
        let fog = |live: &LiveScene| live.desc.fog.as_ref().map(|f| f.value).expect("fog");
        let mut live = LiveScene::new(demo.clone());
        live.apply(Control::Density(1.25)).expect("density");
        assert!(
            (fog(&live).sigma_t - fog(&LiveScene::new(demo.clone())).sigma_t * 1.25).abs() < 1e-6
        );
        live.apply(Control::Step(0.8)).expect("step");
        assert!((live.desc.settings.step - demo.settings.step * 0.8).abs() < 1e-7);
        let before = live.desc.glass.model;
        live.apply(Control::GlassModel).expect("glass");
        assert_ne!(live.desc.glass.model, before);
        live.apply(Control::NextLight).expect("next light");
        assert_eq!(live.selected_light, 1 % demo.lights.len());
        assert!(!Control::Exposure(0.25).changes_radiance());
        assert!(Control::Cutoff(1.0).changes_radiance());
    }

    /// `I` switches the GPU view between the march and `single`, and the
    /// GPU renders what it says; `single` refuses the paper's albedos and
    /// keeps the fog physical while it is on.
    #[test]
    fn the_estimator_switch_sets_what_the_gpu_renders() {
        use tyndall_gpu::{InScattering, MarchSettings};
        let mut live = LiveScene::new(tyndall_load::demo::load().expect("demo"));
        let gpu = |live: &LiveScene| MarchSettings::from(&live.desc.settings).in_scattering;
        assert_eq!(gpu(&live), InScattering::March);
        live.apply(Control::Estimator).expect("to single");
        assert_eq!(
            gpu(&live),
            InScattering::Single {
                volume_samples: live.desc.settings.volume_samples
            }
        );
        live.set(Setting::Albedo(Rgb::splat(5.0))).expect("albedo");
        assert_eq!(
            live.desc.fog.as_ref().map(|f| f.value.albedo),
            Some(Rgb::ONE)
        );
        live.apply(Control::Estimator).expect("back to the march");
        assert_eq!(gpu(&live), InScattering::March);
        live.set(Setting::Albedo(Rgb::splat(5.0))).expect("albedo");
        assert!(
            live.apply(Control::Estimator).is_err(),
            "albedo 5 under single"
        );
        assert_eq!(gpu(&live), InScattering::March);
    }

    #[test]
    fn direction_angles_round_trip() {
        for d in [
            Vec3::new(0.82, -0.58, 0.02),
            Vec3::new(-0.3, 0.2, -0.9),
            Vec3::new(0.0, -1.0, 0.001),
        ] {
            let d = d.normalize();
            let (a, e) = direction_angles(d);
            let back = direction_from_angles(a, e);
            // A handful of f32 operations (atan2, sin, cos, products),
            // each good to about 1e-7: 1e-5 leaves 100× room, and an
            // ill-conditioned formula (asin of y near the pole: 2e-5 for
            // the last case) fails it.
            assert!((back - d).length() < 1e-5, "{d} → ({a}, {e}) → {back}");
        }
    }

    #[test]
    fn turning_keeps_unit_length_and_moves() {
        let d = Vec3::new(0.0, -1.0, 0.2).normalize();
        let t = turn(d, TURN_DEGREES, 0.0);
        assert!((t.length() - 1.0).abs() < 1e-5);
        let angle = t.dot(d).clamp(-1.0, 1.0).acos().to_degrees();
        assert!(angle > 0.1 && angle < TURN_DEGREES + 0.01, "{angle}");
        let p = turn(d, 0.0, TURN_DEGREES);
        let angle = p.dot(d).clamp(-1.0, 1.0).acos().to_degrees();
        assert!((angle - TURN_DEGREES).abs() < 0.01, "{angle}");
    }
}
