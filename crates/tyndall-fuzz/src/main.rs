//! `tyndall-fuzz`: a mutation fuzzer for Tyndall's loaders, on stable
//! Rust and without dependencies beyond the library.
//!
//! First it replays the regression corpus (`crates/tyndall-fuzz/corpus/`,
//! one folder per target): every input that once crashed, hung or
//! exhausted memory, each of which must now be refused or read within
//! the time limit. Then it fuzzes: seeds are every file under `scenes/`
//! and the corpus; each iteration picks a target, a seed, and mutates it
//! (bit flips, byte and range edits, splices with other seeds, numbers
//! replaced by hostile values such as `1e38`, `NaN` or `2147483648`,
//! hostile little-endian words). The targets ([`targets::Target`]):
//! `native`, `legacy`, `grid`, `mesh`, `gltf`, `glb`, `vdb` (each loader
//! on bytes in memory) and `render` (8×8, 1 spp renders of accepted
//! scenes with each integrator).
//!
//! A panic, or an input that takes longer than `--limit` seconds of CPU
//! time (a watchdog thread), is saved under `--findings` and counted; the
//! run exits non-zero if it found anything. An allocation the reader
//! should have refused aborts the process, which fails the run too. The
//! same `--seed` gives the same inputs.
//!
//! ```text
//! cargo run --release -p tyndall-fuzz -- --seconds 60 --seed 1
//! ```

mod mutate;
mod targets;

use mutate::{Rng, mutate};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use targets::{Outcome, Target};

/// With every target running, one input in this many is a render.
const RENDER_SHARE: usize = 16;

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

/// The input being run, shared with the watchdog thread, which ends the
/// process (saving the input) when one runs past the limit.
#[derive(Clone)]
struct Watchdog(Arc<Mutex<Current>>);

impl Watchdog {
    fn start(limit: Duration, findings: PathBuf) -> Self {
        let current = Arc::new(Mutex::new(Current {
            started: Instant::now(),
            started_cpu: None,
            target: "",
            input: Vec::new(),
        }));
        let watched = current.clone();
        std::thread::spawn(move || {
            loop {
                std::thread::sleep(Duration::from_millis(250));
                let c = watched.lock().unwrap_or_else(|e| e.into_inner());
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
        Self(current)
    }

    /// Runs `input` through `target` under the watchdog; `Err` for a
    /// panic.
    fn run(&self, target: Target, input: &[u8], scenes: &Path) -> Result<Outcome, ()> {
        {
            let mut c = self.0.lock().unwrap_or_else(|e| e.into_inner());
            c.started = Instant::now();
            c.started_cpu = cpu_seconds();
            c.target = target.name();
            c.input.clear();
            c.input.extend_from_slice(input);
        }
        let outcome = catch_unwind(AssertUnwindSafe(|| target.run(input, scenes))).map_err(|_| ());
        self.0.lock().unwrap_or_else(|e| e.into_inner()).target = "";
        outcome
    }
}

struct Args {
    seconds: f64,
    seed: u64,
    limit: f64,
    targets: Vec<Target>,
    scenes: PathBuf,
    corpus: PathBuf,
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
        corpus: Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus"),
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
            "--corpus" => args.corpus = PathBuf::from(value()?),
            "--findings" => args.findings = PathBuf::from(value()?),
            "--targets" => {
                args.targets = value()?
                    .split(',')
                    .map(|n| Target::from_name(n).ok_or_else(|| format!("unknown target `{n}`")))
                    .collect::<Result<_, _>>()?;
            }
            "--help" | "-h" => {
                let names: Vec<&str> = Target::ALL.iter().map(|t| t.name()).collect();
                return Err(format!(
                    "usage: tyndall-fuzz [--seconds N] [--seed S] [--limit SECONDS] [--targets {}] [--scenes DIR] [--corpus DIR] [--findings DIR]",
                    names.join(",")
                ));
            }
            other => return Err(format!("unknown flag `{other}`")),
        }
    }
    Ok(args)
}

fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.flatten().map(|e| e.path()).collect();
    paths.sort();
    for path in paths {
        if path.is_dir() {
            files_under(&path, out);
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

/// Replays the regression corpus: `corpus/<target>/*` through each
/// target (a folder naming no target is an error, so no reproducer is
/// silently skipped). Returns the number of inputs and of panics.
fn replay_corpus(args: &Args, watchdog: &Watchdog) -> Result<(usize, u64), String> {
    let Ok(entries) = std::fs::read_dir(&args.corpus) else {
        return Ok((0, 0));
    };
    let mut folders: Vec<PathBuf> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.is_dir())
        .collect();
    folders.sort();
    let (mut count, mut panics) = (0, 0);
    for folder in folders {
        let name = folder.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let target = Target::from_name(name)
            .ok_or_else(|| format!("{}: the corpus folder names no target", folder.display()))?;
        let mut files = Vec::new();
        files_under(&folder, &mut files);
        for file in files {
            let input = std::fs::read(&file).map_err(|e| format!("{}: {e}", file.display()))?;
            count += 1;
            if watchdog.run(target, &input, &args.scenes).is_err() {
                panics += 1;
                eprintln!("corpus input {} panicked", file.display());
            }
        }
    }
    Ok((count, panics))
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
    files_under(&args.scenes, &mut paths);
    files_under(&args.corpus, &mut paths);
    let seeds: Vec<(PathBuf, Vec<u8>)> = paths
        .into_iter()
        .filter(|p| p.extension().is_none_or(|e| e != "py" && e != "md"))
        .filter_map(|p| std::fs::read(&p).ok().map(|b| (p, b)))
        .collect();
    if seeds.is_empty() {
        eprintln!("no seed files under {}", args.scenes.display());
        return std::process::ExitCode::from(2);
    }
    let seed_bytes: Vec<Vec<u8>> = seeds.iter().map(|(_, b)| b.clone()).collect();

    // Panics are caught and counted; keep their messages short.
    std::panic::set_hook(Box::new(|info| {
        eprintln!("panic: {info}");
    }));
    let watchdog = Watchdog::start(Duration::from_secs_f64(args.limit), args.findings.clone());
    let (replayed, mut panics) = match replay_corpus(&args, &watchdog) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{e}");
            return std::process::ExitCode::from(2);
        }
    };

    let mut rng = Rng(args.seed);
    let deadline = Instant::now() + Duration::from_secs_f64(args.seconds);
    let tried: [AtomicU64; Target::ALL.len()] = Default::default();
    let accepted: [AtomicU64; Target::ALL.len()] = Default::default();
    let (mut renders, mut dropped) = (0u64, 0u64);
    let mut iteration = 0u64;
    // A render costs about a thousand parses: renders get one pick in
    // RENDER_SHARE when other targets run too, so parses keep their pace.
    let parse_targets: Vec<Target> = args
        .targets
        .iter()
        .copied()
        .filter(|t| *t != Target::Render)
        .collect();
    let render_too = parse_targets.len() < args.targets.len();
    while Instant::now() < deadline {
        iteration += 1;
        let target = if parse_targets.is_empty() || (render_too && rng.below(RENDER_SHARE) == 0) {
            Target::Render
        } else {
            parse_targets[rng.below(parse_targets.len())]
        };
        let suited: Vec<&Vec<u8>> = seeds
            .iter()
            .filter(|(p, _)| target.suits(p))
            .map(|(_, b)| b)
            .collect();
        let mut input = if suited.is_empty() || rng.below(8) == 0 {
            seed_bytes[rng.below(seed_bytes.len())].clone()
        } else {
            suited[rng.below(suited.len())].clone()
        };
        mutate(&mut rng, &mut input, &seed_bytes);
        let index = target.index();
        tried[index].fetch_add(1, Ordering::Relaxed);
        match watchdog.run(target, &input, &args.scenes) {
            Ok(outcome) => {
                if outcome.accepted {
                    accepted[index].fetch_add(1, Ordering::Relaxed);
                }
                renders += outcome.renders;
                dropped += outcome.dropped;
                if outcome.dropped > 0 {
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
            Err(()) => {
                panics += 1;
                save(&args.findings, "panic", target.name(), iteration, &input);
            }
        }
    }
    println!("tyndall-fuzz: seed {}, {:.0} s", args.seed, args.seconds);
    println!("  regression corpus: {replayed} inputs replayed");
    for t in Target::ALL {
        println!(
            "  {:7} {:>10} inputs, {:>8} accepted",
            t.name(),
            tried[t.index()].load(Ordering::Relaxed),
            accepted[t.index()].load(Ordering::Relaxed)
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
