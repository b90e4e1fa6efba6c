//! The rules the code keeps (docs/architecture.md): no module of the core
//! imports a module that imports it, no source file is over 800 lines, and
//! the core depends on no file-format crate.

mod common;

use common::repo;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Longest source file allowed, in lines.
const MAX_LINES: usize = 800;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("read dir").flatten() {
        let path = entry.path();
        if path.is_dir() {
            if path.file_name().is_some_and(|n| n != "target") {
                rust_files(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "rs") {
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
    for module in graph.keys() {
        let mut path = vec![module.clone()];
        let cycle = cycle_from(&graph, module, module, &mut path, &mut BTreeSet::new());
        assert!(
            cycle.is_none(),
            "import cycle: {}",
            cycle.unwrap().join(" → ")
        );
    }
    // The settings are a leaf the loaders may use.
    assert!(graph["settings"].is_empty(), "{:?}", graph["settings"]);
}

#[test]
fn no_source_file_is_over_800_lines() {
    let mut files = Vec::new();
    rust_files(&repo().join("crates"), &mut files);
    assert!(files.len() > 50);
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
