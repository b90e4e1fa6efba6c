//! What the fuzzer feeds its inputs to: each loader on bytes in memory,
//! and tiny renders of the scenes they accept.

use std::path::Path;
use tyndall::settings::VisibilityMode;
use tyndall::{IntegratorKind, RenderSettings, Scene, SceneDesc};
use tyndall_load::legacy::{self, LegacyOptions};
use tyndall_load::mesh::{self, MeshTransform};
use tyndall_load::{SourceText, gltf, native, tgrid, vdb};

/// One reader, or renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The TOML scene parser ([`native::parse`]).
    Native,
    /// The paper's .obj scene parser ([`legacy::parse`]).
    Legacy,
    /// The `.tgrid` reader ([`tgrid::from_bytes`]).
    Grid,
    /// The .obj mesh reader ([`mesh::parse_obj_mesh`]).
    Mesh,
    /// glTF JSON ([`gltf::load_bytes`]; relative URIs resolve in
    /// `scenes/blender`, so buffers and images are read too).
    Gltf,
    /// The binary glTF container, the same loader.
    Glb,
    /// The OpenVDB reader ([`vdb::read_grid_from_bytes`]): the grid list, then
    /// every grid read as a density and as a vector grid.
    Vdb,
    /// Scenes the native, legacy or glTF loader accepted, rendered at 8×8
    /// pixels, 1 spp, with each integrator whose settings validate.
    Render,
}

/// What running one input did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Outcome {
    /// The reader accepted the input.
    pub accepted: bool,
    pub renders: u64,
    /// Samples the renders dropped as NaN or infinite.
    pub dropped: u64,
}

impl Outcome {
    fn parsed(accepted: bool) -> Self {
        Self {
            accepted,
            ..Self::default()
        }
    }
}

impl Target {
    pub const ALL: [Target; 8] = [
        Target::Native,
        Target::Legacy,
        Target::Grid,
        Target::Mesh,
        Target::Gltf,
        Target::Glb,
        Target::Vdb,
        Target::Render,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Target::Native => "native",
            Target::Legacy => "legacy",
            Target::Grid => "grid",
            Target::Mesh => "mesh",
            Target::Gltf => "gltf",
            Target::Glb => "glb",
            Target::Vdb => "vdb",
            Target::Render => "render",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Index in [`Target::ALL`], for counters.
    pub fn index(self) -> usize {
        Self::ALL.iter().position(|t| *t == self).unwrap_or(0)
    }

    /// Whether a seed file suits the target best (every file seeds every
    /// target some of the time).
    pub fn suits(self, path: &Path) -> bool {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        match self {
            Target::Native => ext == "toml",
            Target::Render => matches!(ext, "toml" | "obj" | "gltf" | "glb"),
            Target::Legacy | Target::Mesh => ext == "obj",
            Target::Grid => ext == "tgrid",
            Target::Gltf => ext == "gltf",
            Target::Glb => ext == "glb",
            Target::Vdb => ext == "vdb",
        }
    }

    /// Runs `input` through the target. `scenes` is the seed folder,
    /// where relative mesh, grid and buffer references resolve.
    pub fn run(self, input: &[u8], scenes: &Path) -> Outcome {
        match self {
            Target::Native | Target::Legacy => {
                let legacy = self == Target::Legacy;
                Outcome::parsed(parse_scene(scenes, input, Some(legacy)).is_some())
            }
            Target::Grid => Outcome::parsed(tgrid::from_bytes(input).is_ok()),
            Target::Mesh => {
                let transform = MeshTransform {
                    translate: glam::Vec3::ZERO,
                    scale: glam::Vec3::ONE,
                    rotate_deg: glam::Vec3::ZERO,
                };
                Outcome::parsed(mesh::parse_obj_mesh(input, &transform).is_ok())
            }
            Target::Gltf | Target::Glb => Outcome::parsed(load_gltf(scenes, input).is_some()),
            Target::Vdb => Outcome::parsed(read_vdb(input)),
            Target::Render => match parse_scene(scenes, input, None) {
                Some(desc) => {
                    let (renders, dropped) = render_tiny(&desc);
                    Outcome {
                        accepted: true,
                        renders,
                        dropped,
                    }
                }
                None => Outcome::default(),
            },
        }
    }
}

/// Parses a scene as legacy .obj (`Some(true)`), native TOML
/// (`Some(false)`) or whichever the bytes look like (`None`: glTF by its
/// JSON or GLB start, legacy by `v` statements without TOML tables). The
/// scene's path sits in `scenes/` so relative files resolve.
fn parse_scene(scenes: &Path, bytes: &[u8], legacy_format: Option<bool>) -> Option<SceneDesc> {
    let legacy_format = match legacy_format {
        Some(legacy) => legacy,
        None if looks_gltf(bytes) => return load_gltf(scenes, bytes),
        None => bytes.contains(&b'v') && !bytes.contains(&b'['),
    };
    let text = String::from_utf8_lossy(bytes).into_owned();
    if legacy_format {
        let source = SourceText::new(scenes.join("fuzz.obj"), text);
        legacy::parse(&source, LegacyOptions::default()).ok()
    } else {
        let source = SourceText::new(scenes.join("fuzz.toml"), text);
        native::parse(&source).ok()
    }
}

/// A GLB container (its magic) or a JSON document naming a glTF `asset`.
fn looks_gltf(bytes: &[u8]) -> bool {
    bytes.starts_with(b"glTF")
        || (bytes.trim_ascii_start().starts_with(b"{")
            && bytes.windows(7).any(|w| w == b"\"asset\""))
}

fn load_gltf(scenes: &Path, bytes: &[u8]) -> Option<SceneDesc> {
    let base = scenes.join("blender");
    gltf::load_bytes(&base.join("fuzz.gltf"), bytes, Some(&base)).ok()
}

/// Lists the grids of a VDB file and reads each as a density and as a
/// vector grid; accepted if any read succeeds.
fn read_vdb(bytes: &[u8]) -> bool {
    let name = Path::new("fuzz.vdb");
    let Ok(grids) = vdb::list_grids_from_bytes(name, bytes) else {
        return false;
    };
    let mut any = false;
    for i in 0..grids.len() {
        let selector = format!("#{i}");
        any |= vdb::read_grid_from_bytes(name, bytes, &selector).is_ok();
        any |= vdb::read_vector_grid_from_bytes(name, bytes, &selector).is_ok();
    }
    any
}

/// Renders an accepted scene at 8×8, 1 spp with every integrator whose
/// settings validate (shadow maps at most 64² texels). Returns how many
/// renders ran and how many samples were dropped as non-finite.
fn render_tiny(desc: &SceneDesc) -> (u64, u64) {
    let (mut renders, mut dropped) = (0, 0);
    // A loader validates what it returns, so building cannot fail.
    let scene = Scene::build(desc).expect("a loaded scene builds");
    for integrator in IntegratorKind::ALL {
        let mut settings = RenderSettings {
            width: 8,
            height: 8,
            spp: 1,
            threads: Some(1),
            integrator,
            ..desc.settings
        };
        if let VisibilityMode::Maps { resolution } = settings.visibility {
            settings.visibility = VisibilityMode::Maps {
                resolution: resolution.min(64),
            };
        }
        if let Ok(render) = tyndall::render(&scene, &settings, &|_| {}) {
            renders += 1;
            dropped += render.stats.invalid_samples;
        }
    }
    (renders, dropped)
}
