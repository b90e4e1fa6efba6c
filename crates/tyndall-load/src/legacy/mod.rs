//! The paper's scene format: the course code base's extended .obj
//! (docs/scene-format.md, "The paper's legacy format"), with the paper's `c` (spotlight cutoff) and
//! `alpha` (glass opacity) tokens.
//!
//! Tokens are whitespace-separated and newlines are not significant. A
//! `material` block is open from the `material` token until the next
//! statement that is not one of its fields. Reading a file has three
//! phases, each testable alone:
//!
//! 1. [`statements`]: the tokens read as statements, each value checked;
//! 2. [`cutoffs`]: what each spotlight cutoff `c` means — a `c` that ends
//!    a block's fields may be the material's or a statement for the faces
//!    that follow — and so the cutoff of every face, with warnings where
//!    the reading is ambiguous;
//! 3. [`build`]: the [`SceneDesc`], validated and located in the file.

mod build;
mod cutoffs;
mod statements;

use crate::source::{SceneError, SourceText};
use std::path::Path;
use tyndall::description::SceneDesc;

/// Options for loading legacy files.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LegacyOptions {
    /// Make quads two-sided (the course code's switch); one-sided by default.
    pub two_sided: bool,
}

/// Loads a legacy .obj scene.
pub fn load(path: &Path, options: LegacyOptions) -> Result<SceneDesc, SceneError> {
    parse(&SourceText::read(path)?, options)
}

/// Parses legacy text. Quads are one-sided unless `options.two_sided`.
pub fn parse(source: &SourceText, options: LegacyOptions) -> Result<SceneDesc, SceneError> {
    let statements = statements::read(source)?;
    let cutoffs = cutoffs::disambiguate(&statements, source);
    build::build(statements, cutoffs, source, options)
}
