//! The built-in demo scene: a stained-glass window throwing coloured
//! shafts into a dusty room. It is `scenes/stained-glass.toml`, compiled in,
//! so the file in the repository and the demo never drift apart.

use crate::native;
use crate::source::{SceneError, SourceText};
use tyndall::SceneDesc;

/// Text of the demo scene.
pub const DEMO_SCENE: &str = include_str!("../../../scenes/stained-glass.toml");

/// Name shown for the demo in messages.
pub const DEMO_NAME: &str = "<built-in demo: scenes/stained-glass.toml>";

/// Loads the demo scene. It has no relative paths.
pub fn load() -> Result<SceneDesc, SceneError> {
    native::parse(&SourceText::new(DEMO_NAME, DEMO_SCENE))
}
