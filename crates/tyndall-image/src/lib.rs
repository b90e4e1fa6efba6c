//! Image files for Tyndall: the file formats the core leaves out.
//!
//! The core crate renders into a [`tyndall::Image`], plain linear-RGB
//! data. This crate writes it as PNG (display-referred, sRGB, exposure) or
//! OpenEXR (scene-referred linear radiance) and reads OpenEXR back
//! ([`mod@format`], [`output`]); stores render parts (tiles, sample ranges,
//! checkpoints) as OpenEXR files that keep their sums exact ([`parts`]);
//! and measures an image against a reference ([`metrics`], [`mod@compare`]).

pub mod compare;
pub mod format;
pub mod metrics;
pub mod output;
pub mod parts;

pub use compare::{Comparison, compare, compare_files};
pub use format::{AovLayer, EXR_ENCODING, ImageError, ImageFormat, read_exr};
pub use output::{OutputFile, write_image};
