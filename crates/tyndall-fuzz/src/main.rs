//! `tyndall-fuzz`: a mutation fuzzer for Tyndall's loaders, on stable
//! Rust and without dependencies beyond the library.
//!
//! Seeds are every file under `scenes/`. Each iteration picks a target,
//! a seed, and mutates it (bit flips, byte and range edits, splices with
//! other seeds, numbers replaced by hostile values such as `1e38`, `NaN`
//! or `2147483648`). Targets:
//!
//! * `native`: the TOML scene parser ([`native::parse`]);
//! * `legacy`: the paper's .obj scene parser ([`legacy::parse`]);
//! * `grid`: the `.tgrid` reader ([`tgrid::from_bytes`]);
//! * `mesh`: the .obj mesh reader ([`mesh::parse_obj_mesh`]);
//! * `render`: scenes the native or legacy parser accepted, rendered at
//!   8×8 pixels, 1 spp, with each integrator whose settings validate.
//!
//! A panic, or an input that takes longer than `--limit` seconds (a
//! watchdog thread), is saved under `--findings` and counted; the run
//! exits non-zero if it found anything. The same `--seed` gives the same
//! inputs.
//!
//! ```text
//! cargo run --release -p tyndall-fuzz -- --seconds 60 --seed 1
//! ```

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};
use tyndall::settings::VisibilityMode;
use tyndall::{IntegratorKind, RenderSettings, Scene, SceneDesc};
use tyndall_load::legacy::{self, LegacyOptions};
use tyndall_load::mesh::{self, MeshTransform};
use tyndall_load::{SourceText, native, tgrid};

/// With every target running, one input in this many is a render.
const RENDER_SHARE: usize = 16;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    Native,
    Legacy,
    Grid,
    Mesh,
    Render,
}

impl Target {
    const ALL: [Target; 5] = [
        Target::Native,
        Target::Legacy,
        Target::Grid,
        Target::Mesh,
        Target::Render,
    ];

    fn name(self) -> &'static str {
        match self {
            Target::Native => "native",
            Target::Legacy => "legacy",
            Target::Grid => "grid",
            Target::Mesh => "mesh",
            Target::Render => "render",
        }
    }
}

/// Parses a scene as native TOML or legacy .obj (by `legacy`); the path
/// sits in `scenes/` so relative mesh and grid files resolve.
fn parse_scene(scenes: &Path, bytes: &[u8], legacy_format: bool) -> Option<SceneDesc> {
    let text = String::from_utf8_lossy(bytes).into_owned();
    if legacy_format {
        let source = SourceText::new(scenes.join("fuzz.obj"), text);
        legacy::parse(&source, LegacyOptions::default()).ok()
    } else {
        let source = SourceText::new(scenes.join("fuzz.toml"), text);
        native::parse(&source).ok()
    }
}

/// Renders an accepted scene at 8×8, 1 spp with every integrator whose
/// settings validate (shadow maps at most 64² texels). Returns how many
/// renders ran and how many samples were dropped as non-finite.
fn render_tiny(desc: &SceneDesc) -> (u64, u64) {
    let (mut renders, mut dropped) = (0, 0);
    // A loader validates what it returns, so building cannot fail.
    let scene = Scene::build(desc).expect("a loaded scene builds");
    for integrator in [
        IntegratorKind::March,
        IntegratorKind::Single,
        IntegratorKind::Volpath,
    ] {
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

/// CPU seconds this process has used (user + system, from
/// `/proc/self/stat`, in ticks of 1/100 s), or `None` where that is not
/// available. The watchdog measures inputs in CPU time: a niced fuzzer
/// on a busy machine can wait for the CPU far longer than it computes.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are
    // the 14th and 15th fields of the line.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// What the watchdog knows about the input being run.
struct Current {
    started: Instant,
    started_cpu: Option<f64>,
    target: &'static str,
    input: Vec<u8>,
}

struct Args {
    seconds: f64,
    seed: u64,
    limit: f64,
    targets: Vec<Target>,
    scenes: PathBuf,
    findings: PathBuf,
}

fn parse_args() -> Result<Args, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut args = Args {
        seconds: 60.0,
        seed: 1,
        limit: 10.0,
        targets: Target::ALL.to_vec(),
        scenes: root.join("scenes"),
        findings: root.join("target/fuzz-findings"),
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{flag} needs a value"));
        match flag.as_str() {
            "--seconds" => args.seconds = value()?.parse().map_err(|e| format!("{e}"))?,
            "--seed" => args.seed = value()?.parse().map_err(|e| format!("{e}"))?,
            "--limit" => args.limit = value()?.parse().map_err(|e| format!("{e}"))?,
            "--scenes" => args.scenes = PathBuf::from(value()?),
            "--findings" => args.findings = PathBuf::from(value()?),
            "--targets" => {
                let names = value()?;
                args.targets = names
                    .split(',')
                    .map(|n| {
                        Target::ALL
                            .into_iter()
                            .find(|t| t.name() == n)
                            .ok_or_else(|| format!("unknown target `{n}`"))
                    })
                    .collect::<Result<_, _>>()?;
            }
            "--help" | "-h" => {
                return Err("usage: tyndall-fuzz [--seconds N] [--seed S] [--limit SECONDS] [--targets native,legacy,grid,mesh,render] [--scenes DIR] [--findings DIR]".into());
            }
            other => return Err(format!("unknown flag `{other}`")),
        }
    }
    Ok(args)
}

fn seed_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
    paths.sort();
    for path in paths {
        if path.is_dir() {
            seed_files(&path, out);
        } else {
            out.push(path);
        }
    }
}

fn save(findings: &Path, kind: &str, target: &str, n: u64, input: &[u8]) {
    let _ = std::fs::create_dir_all(findings);
    let path = findings.join(format!("{kind}-{target}-{n}.bin"));
    let _ = std::fs::write(&path, input);
    eprintln!(
        "{kind} in target {target}: input saved to {}",
        path.display()
    );
}

fn main() -> std::process::ExitCode {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            return std::process::ExitCode::from(2);
        }
    };
    let mut paths = Vec::new();
    seed_files(&args.scenes, &mut paths);
    let seeds: Vec<(PathBuf, Vec<u8>)> = paths
        .into_iter()
        .filter_map(|p| std::fs::read(&p).ok().map(|b| (p, b)))
        .collect();
    if seeds.is_empty() {
        eprintln!("no seed files under {}", args.scenes.display());
        return std::process::ExitCode::from(2);
    }
    let seed_bytes: Vec<Vec<u8>> = seeds.iter().map(|(_, b)| b.clone()).collect();
    // Seeds by the targets they suit best; every file seeds every target
    // some of the time.
    let suits = |t: Target, p: &Path| {
        let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
        match t {
            Target::Native => ext == "toml",
            Target::Render => ext == "toml" || ext == "obj",
            Target::Legacy | Target::Mesh => ext == "obj",
            Target::Grid => ext == "tgrid",
        }
    };

    // Panics are caught and counted; keep their messages short.
    std::panic::set_hook(Box::new(|info| {
        eprintln!("panic: {info}");
    }));
    let current = std::sync::Arc::new(Mutex::new(Current {
        started: Instant::now(),
        started_cpu: None,
        target: "",
        input: Vec::new(),
    }));
    let limit = Duration::from_secs_f64(args.limit);
    {
        let current = current.clone();
        let findings = args.findings.clone();
        std::thread::spawn(move || {
            loop {
                std::thread::sleep(Duration::from_millis(250));
                let c = current.lock().unwrap_or_else(|e| e.into_inner());
                // CPU time where known; wall time (ten times the limit)
                // as a backstop.
                let cpu = match (cpu_seconds(), c.started_cpu) {
                    (Some(now), Some(then)) => now - then > limit.as_secs_f64(),
                    _ => false,
                };
                let wall = c.started.elapsed() > limit * 10;
                if !c.target.is_empty() && (cpu || wall) {
                    save(&findings, "slow", c.target, 0, &c.input);
                    eprintln!(
                        "an input of target {} ran longer than {:?} of CPU time: stopping",
                        c.target, limit
                    );
                    std::process::exit(3);
                }
            }
        });
    }

    let mut rng = Rng(args.seed);
    let deadline = Instant::now() + Duration::from_secs_f64(args.seconds);
    let tried: [AtomicU64; 5] = Default::default();
    let accepted: [AtomicU64; 5] = Default::default();
    let (mut panics, mut renders, mut dropped) = (0u64, 0u64, 0u64);
    let mut iteration = 0u64;
    while Instant::now() < deadline {
        iteration += 1;
        // A render costs about a thousand parses: renders get one pick in
        // RENDER_SHARE when other targets run too, so parses keep their
        // pace.
        let parse_targets: Vec<Target> = args
            .targets
            .iter()
            .copied()
            .filter(|t| *t != Target::Render)
            .collect();
        let render_too = parse_targets.len() < args.targets.len();
        let target = if parse_targets.is_empty() || (render_too && rng.below(RENDER_SHARE) == 0) {
            Target::Render
        } else {
            parse_targets[rng.below(parse_targets.len())]
        };
        let suited: Vec<&Vec<u8>> = seeds
            .iter()
            .filter(|(p, _)| suits(target, p))
            .map(|(_, b)| b)
            .collect();
        let mut input = if suited.is_empty() || rng.below(8) == 0 {
            seed_bytes[rng.below(seed_bytes.len())].clone()
        } else {
            suited[rng.below(suited.len())].clone()
        };
        mutate(&mut rng, &mut input, &seed_bytes);
        {
            let mut c = current.lock().unwrap_or_else(|e| e.into_inner());
            c.started = Instant::now();
            c.started_cpu = cpu_seconds();
            c.target = target.name();
            c.input.clone_from(&input);
        }
        let scenes = &args.scenes;
        let outcome = catch_unwind(AssertUnwindSafe(|| match target {
            Target::Native => (parse_scene(scenes, &input, false).is_some(), 0, 0),
            Target::Legacy => (parse_scene(scenes, &input, true).is_some(), 0, 0),
            Target::Grid => (tgrid::from_bytes(&input).is_ok(), 0, 0),
            Target::Mesh => {
                let transform = MeshTransform {
                    translate: glam::Vec3::ZERO,
                    scale: glam::Vec3::ONE,
                    rotate_deg: glam::Vec3::ZERO,
                };
                (mesh::parse_obj_mesh(&input, &transform).is_ok(), 0, 0)
            }
            Target::Render => {
                // A mutated TOML or legacy scene.
                match parse_scene(scenes, &input, looks_legacy(&input)) {
                    Some(desc) => {
                        let (r, d) = render_tiny(&desc);
                        (true, r, d)
                    }
                    None => (false, 0, 0),
                }
            }
        }));
        let index = Target::ALL.iter().position(|t| *t == target).unwrap_or(0);
        tried[index].fetch_add(1, Ordering::Relaxed);
        match outcome {
            Ok((ok, r, d)) => {
                if ok {
                    accepted[index].fetch_add(1, Ordering::Relaxed);
                }
                renders += r;
                dropped += d;
                if d > 0 {
                    // Not a failure (the render reports them), but worth
                    // a look: save the scene.
                    save(
                        &args.findings,
                        "nonfinite",
                        target.name(),
                        iteration,
                        &input,
                    );
                }
            }
            Err(_) => {
                panics += 1;
                save(&args.findings, "panic", target.name(), iteration, &input);
            }
        }
        current.lock().unwrap_or_else(|e| e.into_inner()).target = "";
    }
    println!("tyndall-fuzz: seed {}, {:.0} s", args.seed, args.seconds);
    for (i, t) in Target::ALL.iter().enumerate() {
        println!(
            "  {:7} {:>10} inputs, {:>8} accepted",
            t.name(),
            tried[i].load(Ordering::Relaxed),
            accepted[i].load(Ordering::Relaxed)
        );
    }
    println!("  renders at 8×8, 1 spp: {renders}; non-finite samples dropped: {dropped}");
    println!("  panics: {panics}");
    if panics > 0 {
        std::process::ExitCode::FAILURE
    } else {
        std::process::ExitCode::SUCCESS
    }
}

/// Legacy scenes have `v` statements and no TOML tables.
fn looks_legacy(input: &[u8]) -> bool {
    input.contains(&b'v') && !input.contains(&b'[')
}
