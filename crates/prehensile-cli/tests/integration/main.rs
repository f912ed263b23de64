//! The crate's integration tests, in one binary: one test binary per file would link the
//! whole dependency tree once per file (32 binaries in the workspace took most of a
//! newcomer's `cargo test --release` build time).

mod batch;
mod cli;
mod hostile_inputs;
mod view;
