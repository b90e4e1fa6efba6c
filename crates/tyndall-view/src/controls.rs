//! The live controls: what each key changes in the scene description,
//! within the ranges the loader accepts, and a one-line summary of the
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

use glam::{Quat, Vec3};
use tyndall::Rgb;
use tyndall::SceneDesc;
use tyndall::description::{LightDesc, Sourced};
use tyndall::glass::GlassModel;
use tyndall::lights::SpotProfile;
use tyndall::limits;
use tyndall::media::Fog;
use tyndall::phase::PhaseFunction;

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
}

impl Control {
    /// Whether the change alters the rendered radiance (and so restarts
    /// accumulation); exposure and the light selection do not.
    pub fn changes_radiance(self) -> bool {
        !matches!(self, Control::Exposure(_) | Control::NextLight)
    }
}

/// Fog density given to a scene without fog when density is raised.
const NEW_FOG_DENSITY: f32 = 0.05;
/// Degrees the arrows turn a light by.
pub const TURN_DEGREES: f32 = 3.0;

/// The scene being viewed and which light the light controls act on.
pub struct LiveScene {
    pub desc: SceneDesc,
    pub selected_light: usize,
}

impl LiveScene {
    /// The view of `desc`, rendered with `march` (the GPU's integrator,
    /// which also accepts the paper's albedos above 1).
    pub fn new(mut desc: SceneDesc) -> Self {
        desc.settings.integrator = tyndall::IntegratorKind::March;
        Self {
            desc,
            selected_light: 0,
        }
    }

    /// Applies `control`; `Err` says why it did nothing (no fog, no light,
    /// not a spot, a limit reached).
    pub fn apply(&mut self, control: Control) -> Result<(), String> {
        let desc = &mut self.desc;
        match control {
            Control::Density(f) => match &mut desc.fog {
                Some(fog) => fog.value.sigma_t = (fog.value.sigma_t * f).clamp(1e-4, 1e3),
                None => {
                    desc.fog = Some(Sourced::code(Fog {
                        sigma_t: NEW_FOG_DENSITY,
                        albedo: Rgb::splat(1.0),
                        phase: PhaseFunction::Isotropic,
                        bounds: None,
                    }))
                }
            },
            Control::Albedo(d) => {
                let fog = desc
                    .fog
                    .as_mut()
                    .ok_or("no fog (raise the density first)")?;
                fog.value.albedo = (fog.value.albedo + Rgb::splat(d))
                    .clamp(Rgb::ZERO, Rgb::splat(limits::MAX_FOG_ALBEDO));
            }
            Control::Asymmetry(d) => {
                let fog = desc
                    .fog
                    .as_mut()
                    .ok_or("no fog (raise the density first)")?;
                let g = (asymmetry(&fog.value.phase) + d).clamp(-0.95, 0.95);
                // Snap the accumulated key steps back onto 0 exactly.
                let g = if g.abs() < 1e-4 { 0.0 } else { g };
                fog.value.phase = PhaseFunction::from_asymmetry(g);
            }
            Control::Step(f) => desc.settings.step = (desc.settings.step * f).clamp(1e-3, 10.0),
            Control::Exposure(d) => desc.settings.exposure += d,
            Control::NextLight => {
                if desc.lights.is_empty() {
                    return Err("the scene has no point, spot or directional light".into());
                }
                self.selected_light = (self.selected_light + 1) % desc.lights.len();
            }
            Control::Intensity(f) => {
                let emission = match self.light_mut()? {
                    LightDesc::Point(l) => &mut l.intensity,
                    LightDesc::Spot(l) => &mut l.intensity,
                    LightDesc::Directional(l) => &mut l.irradiance,
                };
                let scaled = *emission * f;
                if scaled.max_element() > limits::MAX_EMISSION {
                    return Err("the light is at the largest emission the renderer takes".into());
                }
                *emission = scaled;
            }
            Control::Cutoff(d) => match self.light_mut()? {
                LightDesc::Spot(l) => {
                    let degrees = l.cos_cutoff.clamp(-1.0, 1.0).acos().to_degrees();
                    // At least 1° (and 0.5° past a smooth profile's inner
                    // cone, which must stay inside); at most 89.5°, not 90°:
                    // cos(90°) rounds below 0 in f32, which reads back as
                    // just over the loader's 90°.
                    let min = match l.profile {
                        SpotProfile::Smooth { cos_inner } => {
                            cos_inner.clamp(-1.0, 1.0).acos().to_degrees() + 0.5
                        }
                        _ => 1.0,
                    };
                    let new = (degrees + d).clamp(min.min(89.5), 89.5);
                    l.cos_cutoff = new.to_radians().cos();
                }
                _ => return Err("the selected light is not a spot".into()),
            },
            Control::Turn { yaw, pitch } => {
                let direction = match self.light_mut()? {
                    LightDesc::Spot(l) => &mut l.direction,
                    LightDesc::Directional(l) => &mut l.direction,
                    LightDesc::Point(_) => {
                        return Err("a point light has no direction".into());
                    }
                };
                *direction = turn(*direction, yaw, pitch);
            }
            Control::GlassModel => {
                desc.glass.model = match desc.glass.model {
                    GlassModel::Filter => GlassModel::Blend,
                    GlassModel::Blend => GlassModel::Filter,
                }
            }
        }
        Ok(())
    }

    fn light_mut(&mut self) -> Result<&mut LightDesc, String> {
        self.desc
            .lights
            .get_mut(self.selected_light)
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
                }
            }
        };
        let glass = match d.glass.model {
            GlassModel::Filter => "filter",
            GlassModel::Blend => "blend",
        };
        format!(
            "{fog} step {:.4} | {light} | glass {glass} | exposure {:+.2}",
            d.settings.step, d.settings.exposure
        )
    }
}

/// The HG asymmetry of a phase function (0 for isotropic).
fn asymmetry(phase: &PhaseFunction) -> f32 {
    match phase {
        PhaseFunction::Isotropic => 0.0,
        PhaseFunction::HenyeyGreenstein { g } => *g,
    }
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

    const EVERY_CONTROL: [Control; 14] = [
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
