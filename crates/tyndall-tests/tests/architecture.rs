//! The rules the code keeps (docs/architecture.md): no module of the core
//! imports a module that imports it (top-level modules through `crate::`
//! paths; modules at every depth through `crate::` and `super::` paths),
//! no source file (Rust or WGSL) is over 800 lines, and the core depends
//! on no file-format crate.

mod common;

use common::repo;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Longest source file allowed, in lines.
const MAX_LINES: usize = 800;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    files_ending(dir, &["rs"], out);
}

/// The files under `dir` (outside `target/`) whose extension is one of
/// `extensions`.
fn files_ending(dir: &Path, extensions: &[&str], out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("read dir").flatten() {
        let path = entry.path();
        if path.is_dir() {
            if path.file_name().is_some_and(|n| n != "target") {
                files_ending(&path, extensions, out);
            }
        } else if path
            .extension()
            .is_some_and(|e| extensions.iter().any(|x| e == *x))
        {
            out.push(path);
        }
    }
}

/// The code of a file without comments and without its test module.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap_or("");
    text.lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The top-level modules of the core each top-level module names as
/// `crate::module`.
fn core_module_graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = repo().join("crates/tyndall/src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for file in files {
        let rel = file.strip_prefix(&src).expect("inside src");
        let first = rel.components().next().expect("a component");
        let top = first
            .as_os_str()
            .to_str()
            .expect("utf-8")
            .trim_end_matches(".rs")
            .to_string();
        if top == "lib" {
            continue;
        }
        let text = code(&std::fs::read_to_string(&file).expect("read"));
        let deps = graph.entry(top.clone()).or_default();
        for (at, _) in text.match_indices("crate::") {
            let name: String = text[at + 7..]
                .chars()
                .take_while(|c| c.is_ascii_lowercase() || *c == '_')
                .collect();
            if !name.is_empty() && name != top {
                deps.insert(name);
            }
        }
    }
    graph
}

/// Fails naming the first import cycle of `graph`, if any.
fn assert_no_cycle(graph: &BTreeMap<String, BTreeSet<String>>) {
    for module in graph.keys() {
        let mut path = vec![module.clone()];
        let cycle = cycle_from(graph, module, module, &mut path, &mut BTreeSet::new());
        assert!(
            cycle.is_none(),
            "import cycle: {}",
            cycle.unwrap().join(" → ")
        );
    }
}

/// A cycle through `start`, if any, as the path of modules.
fn cycle_from(
    graph: &BTreeMap<String, BTreeSet<String>>,
    start: &str,
    at: &str,
    path: &mut Vec<String>,
    seen: &mut BTreeSet<String>,
) -> Option<Vec<String>> {
    for next in graph.get(at).into_iter().flatten() {
        if next == start {
            let mut cycle = path.clone();
            cycle.push(start.to_string());
            return Some(cycle);
        }
        if seen.insert(next.clone()) {
            path.push(next.clone());
            if let Some(c) = cycle_from(graph, start, next, path, seen) {
                return Some(c);
            }
            path.pop();
        }
    }
    None
}

#[test]
fn core_modules_import_no_cycle() {
    let graph = core_module_graph();
    assert!(graph.len() > 15, "found only {:?}", graph.keys());
    assert!(
        graph["render"].contains("integrators"),
        "{:?}",
        graph["render"]
    );
    assert_no_cycle(&graph);
    // The settings are a leaf the loaders may use.
    assert!(graph["settings"].is_empty(), "{:?}", graph["settings"]);
}

/// Every module of the core by path (`integrators::volpath::mis`; the
/// crate root is left out), with its file.
fn core_modules() -> BTreeMap<String, PathBuf> {
    let src = repo().join("crates/tyndall/src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut modules = BTreeMap::new();
    for file in files {
        let rel = file.strip_prefix(&src).expect("inside src");
        let mut parts: Vec<String> = rel
            .components()
            .map(|c| c.as_os_str().to_str().expect("utf-8").to_string())
            .collect();
        let last = parts.pop().expect("a file");
        let stem = last.trim_end_matches(".rs");
        if stem != "mod" {
            parts.push(stem.to_string());
        }
        if parts.is_empty() || parts == ["lib"] {
            continue;
        }
        modules.insert(parts.join("::"), file);
    }
    modules
}

/// The module a path names: the longest prefix of `segments` that is a
/// module, else `base` itself (the path names one of its items).
fn module_named(
    modules: &BTreeMap<String, PathBuf>,
    base: &[String],
    segments: &[String],
) -> String {
    let mut best = base.join("::");
    let mut path = base.to_vec();
    for segment in segments {
        path.push(segment.clone());
        let name = path.join("::");
        if modules.contains_key(&name) {
            best = name;
        } else {
            break;
        }
    }
    best
}

/// The paths of a `use` tree after a `crate::` or `super::` prefix: one
/// list of segments per leaf of `a::{b, c::d}`, stopping at `self`, `*`
/// and renames.
fn use_paths(text: &str) -> Vec<Vec<String>> {
    fn word(text: &str) -> (&str, &str) {
        let end = text
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(text.len());
        text.split_at(end)
    }
    fn tree(text: &str, prefix: &[String], out: &mut Vec<Vec<String>>) -> usize {
        let mut i = 0;
        let mut path = prefix.to_vec();
        loop {
            let rest = text[i..].trim_start();
            i = text.len() - rest.len();
            if let Some(group) = rest.strip_prefix('{') {
                let mut consumed = 1;
                let mut inner = group;
                loop {
                    let n = tree(inner, &path, out);
                    consumed += n;
                    inner = &inner[n..];
                    let after = inner.trim_start();
                    consumed += inner.len() - after.len();
                    if let Some(next) = after.strip_prefix(',') {
                        consumed += 1;
                        inner = next;
                        if inner.trim_start().starts_with('}') {
                            let t = inner.trim_start();
                            consumed += inner.len() - t.len() + 1;
                            break;
                        }
                    } else {
                        consumed += usize::from(after.starts_with('}'));
                        break;
                    }
                }
                return i + consumed;
            }
            let (name, after) = word(rest);
            if name.is_empty() || name == "self" {
                out.push(path);
                return i + name.len();
            }
            path.push(name.to_string());
            i += name.len();
            if let Some(next) = after.strip_prefix("::") {
                i += 2;
                if next.starts_with('*') {
                    out.push(path);
                    return i + 1;
                }
            } else {
                out.push(path);
                return i;
            }
        }
    }
    let mut out = Vec::new();
    tree(text, &[], &mut out);
    out
}

/// Which modules of the core each module imports, at every depth, by
/// `crate::` paths and by `super::` paths (resolved against the module's
/// parent); a path to an item counts as its module. A module's use of
/// its ancestors (`super::Item` of the module that declares it) is not
/// an edge: a parent declares and re-exports its children, so that would
/// make every such use a cycle; only imports between modules that do not
/// contain each other count.
fn core_submodule_graph() -> BTreeMap<String, BTreeSet<String>> {
    let modules = core_modules();
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (module, file) in &modules {
        let text = code(&std::fs::read_to_string(file).expect("read"));
        let own: Vec<String> = module.split("::").map(String::from).collect();
        let deps = graph.entry(module.clone()).or_default();
        let mut at = 0;
        while let Some(found) = text[at..].find(['c', 's']) {
            let start = at + found;
            at = start + 1;
            let before = text[..start].chars().next_back();
            if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            let rest = &text[start..];
            let (base, tail) = if let Some(tail) = rest.strip_prefix("crate::") {
                (Vec::new(), tail)
            } else if rest.starts_with("super::") {
                // `super` is the module's parent (for `a/mod.rs`, module
                // `a`, too).
                let mut base = own.clone();
                let mut tail = rest;
                while let Some(t) = tail.strip_prefix("super::") {
                    base.pop();
                    tail = t;
                }
                (base, tail)
            } else {
                continue;
            };
            for segments in use_paths(tail) {
                let target = module_named(&modules, &base, &segments);
                if !target.is_empty()
                    && &target != module
                    && !module.starts_with(&format!("{target}::"))
                {
                    deps.insert(target);
                }
            }
        }
    }
    graph
}

/// Import cycles between modules of the core that are known and owned by
/// another change: each with the issue that removes it.
const KNOWN_CYCLES: &[(&str, &str)] = &[];

#[test]
fn core_submodules_import_no_cycle() {
    let mut graph = core_submodule_graph();
    assert!(
        graph
            .get("integrators::march")
            .is_some_and(|d| d.contains("integrators::lighting")),
        "super:: imports not followed: {:?}",
        graph.get("integrators::march")
    );
    // The known cycles are there, each as an edge the other way too:
    // allowed by dropping one of its edges.
    for (a, b) in KNOWN_CYCLES {
        let there = graph.get(*a).is_some_and(|d| d.contains(*b))
            && graph.get(*b).is_some_and(|d| d.contains(*a));
        assert!(
            there,
            "the known cycle {a} ↔ {b} is gone: remove it from KNOWN_CYCLES"
        );
        graph.get_mut(*a).expect("present").remove(*b);
    }
    assert_no_cycle(&graph);
}

#[test]
fn no_source_file_is_over_800_lines() {
    let mut files = Vec::new();
    files_ending(&repo().join("crates"), &["rs", "wgsl"], &mut files);
    assert!(files.len() > 50);
    assert!(
        files
            .iter()
            .any(|f| f.extension().is_some_and(|e| e == "wgsl")),
        "no WGSL file found"
    );
    let long: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let lines = std::fs::read_to_string(f).expect("read").lines().count();
            (lines > MAX_LINES).then(|| format!("{} ({lines} lines)", f.display()))
        })
        .collect();
    assert!(long.is_empty(), "over {MAX_LINES} lines: {long:?}");
}

/// The GPU renderer (issue 14) is a crate of its own: the core builds and
/// renders without wgpu.
#[test]
fn the_core_does_not_depend_on_the_gpu_crate() {
    let manifest = std::fs::read_to_string(repo().join("crates/tyndall/Cargo.toml")).expect("read");
    for name in ["wgpu", "tyndall-gpu", "naga"] {
        assert!(
            !manifest.lines().any(|l| l.trim_start().starts_with(name)),
            "crates/tyndall depends on {name}"
        );
    }
}

#[test]
fn the_core_has_no_file_format_dependency() {
    let manifest = std::fs::read_to_string(repo().join("crates/tyndall/Cargo.toml")).expect("read");
    for name in [
        "toml",
        "tobj",
        "image",
        "exr",
        "serde",
        "gltf",
        "serde_json",
        "miniz_oxide",
    ] {
        let listed = manifest.lines().any(|l| {
            l.trim_start().starts_with(&format!("{name}."))
                || l.trim_start().starts_with(&format!("{name} ="))
        });
        assert!(!listed, "crates/tyndall depends on {name}");
    }
}
