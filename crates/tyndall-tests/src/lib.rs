//! Tyndall's integration tests live in `tests/`: they load scenes with
//! `tyndall-load` and render them with `tyndall`, so they sit in a crate
//! of their own and the core crate needs no file formats, even to test.
