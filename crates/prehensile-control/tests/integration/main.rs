//! The crate's integration tests, in one binary: one test binary per file would link the
//! whole dependency tree once per file (32 binaries in the workspace took most of a
//! newcomer's `cargo test --release` build time).

#[path = "../common/mod.rs"]
mod common;

mod ball_joint_dynamics;
mod controller;
mod energy_consistency;
mod mujoco_oracle;
mod pinocchio_oracle;
