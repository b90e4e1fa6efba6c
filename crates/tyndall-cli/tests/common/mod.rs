//! Helpers shared by the CLI's integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `tyndall` binary with `args` and waits for it.
pub fn tyndall(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tyndall"))
        .args(args)
        .output()
        .expect("run tyndall")
}

/// The repository's root directory.
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// This test binary's scratch directory (one per test file and process).
pub fn temp_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "tyndall-cli-{}-{}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// A fresh path in the scratch directory (any old file removed).
pub fn temp(name: &str) -> PathBuf {
    let path = temp_dir().join(name);
    let _ = std::fs::remove_file(&path);
    path
}

/// The process's standard error as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}
