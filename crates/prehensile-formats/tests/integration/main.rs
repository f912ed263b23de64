//! The crate's integration tests, in one binary: one test binary per file would link the
//! whole dependency tree once per file (32 binaries in the workspace took most of a
//! newcomer's `cargo test --release` build time).

mod bvh_round_trip;
mod collision_meshes;
mod fuzz_corpus;
mod glb_export;
mod hand_errors;
mod hand_gltf;
mod hand_mjcf;
mod hand_urdf;
mod mesh_files;
mod parsers_never_panic;
