//! The key table: which key does what (see [`crate::controls`] for the
//! scene controls and the crate docs for the whole table).

use crate::controls::{Control, TURN_DEGREES};
use crate::orbit::Fly;
use winit::keyboard::{Key, NamedKey};

/// What a key press asks for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Action {
    Control(Control),
    Fly(Fly),
    /// Save a PNG of the current view (`P`).
    SavePng,
    /// Switch between the GPU view and the progressive CPU render (`R`).
    ToggleCpu,
    /// Show or hide the control panel (`H`).
    TogglePanel,
    Quit,
}

/// The action of a key, if it has one.
pub fn action(key: &Key) -> Option<Action> {
    use Action::{Control as C, Fly as F};
    let fly = |forward, right, up| Some(F(Fly { forward, right, up }));
    match key {
        Key::Named(named) => match named {
            NamedKey::Tab => Some(C(Control::NextLight)),
            NamedKey::ArrowLeft => Some(C(Control::Turn {
                yaw: TURN_DEGREES,
                pitch: 0.0,
            })),
            NamedKey::ArrowRight => Some(C(Control::Turn {
                yaw: -TURN_DEGREES,
                pitch: 0.0,
            })),
            NamedKey::ArrowUp => Some(C(Control::Turn {
                yaw: 0.0,
                pitch: TURN_DEGREES,
            })),
            NamedKey::ArrowDown => Some(C(Control::Turn {
                yaw: 0.0,
                pitch: -TURN_DEGREES,
            })),
            NamedKey::Escape => Some(Action::Quit),
            _ => None,
        },
        Key::Character(c) => match c.to_lowercase().as_str() {
            "w" => fly(1.0, 0.0, 0.0),
            "s" => fly(-1.0, 0.0, 0.0),
            "a" => fly(0.0, -1.0, 0.0),
            "d" => fly(0.0, 1.0, 0.0),
            "q" => fly(0.0, 0.0, -1.0),
            "e" => fly(0.0, 0.0, 1.0),
            "1" => Some(C(Control::Density(1.0 / 1.25))),
            "2" => Some(C(Control::Density(1.25))),
            "3" => Some(C(Control::Albedo(-0.05))),
            "4" => Some(C(Control::Albedo(0.05))),
            "5" => Some(C(Control::Asymmetry(-0.05))),
            "6" => Some(C(Control::Asymmetry(0.05))),
            "7" => Some(C(Control::Step(1.0 / 1.25))),
            "8" => Some(C(Control::Step(1.25))),
            "9" => Some(C(Control::Exposure(-0.25))),
            "0" => Some(C(Control::Exposure(0.25))),
            "[" => Some(C(Control::Intensity(1.0 / 1.25))),
            "]" => Some(C(Control::Intensity(1.25))),
            "-" => Some(C(Control::Cutoff(-1.0))),
            "=" | "+" => Some(C(Control::Cutoff(1.0))),
            "g" => Some(C(Control::GlassModel)),
            "i" => Some(C(Control::Estimator)),
            "p" => Some(Action::SavePng),
            "r" => Some(Action::ToggleCpu),
            "h" => Some(Action::TogglePanel),
            _ => None,
        },
        _ => None,
    }
}

/// The key table as `--help` and the README print it.
pub const KEY_TABLE: &str = "\
mouse drag   orbit around the camera's look_at      wheel    zoom
W/S A/D Q/E  fly forward/back, left/right, down/up
1 / 2        fog density ÷ / × 1.25 (a scene without fog gets σt 0.05)
3 / 4        fog albedo − / + 0.05
5 / 6        HG asymmetry g − / + 0.05
7 / 8        march step ÷ / × 1.25
9 / 0        exposure − / + 0.25 stops
Tab          select the next light
[ / ]        selected light's intensity ÷ / × 1.25
- / =        selected spot's cone cutoff − / + 1°
arrows       turn the selected spot or sun (← → yaw, ↑ ↓ pitch, 3°)
G            glass model: filter ↔ blend
I            in-scattering: the march ↔ single (interleaved equiangular samples)
P            save a PNG of the current view (tyndall-view-NNNN.png)
R            progressive CPU render of the same view on / off
H            control panel (sliders for all of the above, fps) hide / show
Esc          quit";
