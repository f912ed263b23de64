//! # prehensile-formats
//!
//! Reading and writing for Prehensile: meshes (OBJ, STL ascii and binary, PLY ascii and binary)
//! and hands (TOML, URDF, MJCF, glTF skins), plus the built-in hands. Builds core types; knows nothing of
//! physics engines. Every error names the file, the line or element, and the reason.
#![deny(missing_docs)]

pub mod builtin;
mod bvh;
mod collision_mesh;
mod error;
mod file_access;
#[doc(hidden)]
mod glb;
mod gltf_accessors;
mod hand_gltf;
mod hand_import;
mod hand_mjcf;
mod hand_toml;
mod hand_urdf;
mod mesh_gltf;
mod mesh_obj;
mod mesh_ply;
mod mesh_stl;
mod meshes;
pub mod output;
pub mod sources;
mod units;

pub use builtin::{builtin_hand, builtin_object, BUILTIN_HANDS, BUILTIN_OBJECTS};
pub use bvh::{euler_zxy, parse_bvh, write_bvh, BvhJoint, BvhMotion};
pub use error::{FormatCause, FormatError};
pub use file_access::{confined, read_input, read_input_text, MAX_MESH_BYTES, MAX_TEXT_BYTES};
pub use glb::{glb_container, grasp_glb, inverse_bind_matrices, simulation_glb};
pub use hand_gltf::{load_hand_gltf, load_hand_gltf_skinned, parse_hand_gltf_skinned, SkinnedMesh};
pub use hand_import::Sidecar;
pub use hand_mjcf::{load_hand_mjcf, parse_hand_mjcf, parse_hand_mjcf_files, parse_hand_mjcf_with};
pub use hand_toml::{load_hand, parse_hand, parse_hand_toml};
pub use hand_urdf::{load_hand_urdf, parse_hand_urdf, parse_hand_urdf_files, parse_hand_urdf_with};
pub use mesh_obj::parse_obj;
pub use mesh_ply::parse_ply;
pub use mesh_stl::parse_stl;
pub use meshes::{load_object, load_object_repaired, parse_mesh, read_mesh, write_obj, LoadNote};
pub use output::{write_atomically, write_file, OutputError, Outputs};
pub use units::Units;
