//! The crate's integration tests, in one binary: one test binary per file would link the
//! whole dependency tree once per file (32 binaries in the workspace took most of a
//! newcomer's `cargo test --release` build time).

#[path = "../common/mod.rs"]
mod common;

mod collision_oracle;
mod fast_equals_exact;
mod finger_closing;
mod grasp_search;
mod stability_oracle;
mod winding_oracle;
