//! # prehensile-core
//!
//! Hand and object models, capsule collision, kinematics and finger closing for real-time grasp
//! pose search (Paolo Caputo, "Real-Time Grasp Pose Generation for Virtual Hand", Politecnico di
//! Milano, 2015). No file I/O, no
//! physics engine, no printing: formats live in `prehensile-formats`, the CLI in `prehensile-cli`.
//!
//! Conventions: SI units; hand frame with z from the wrist along the fingers, x across the
//! knuckles and **y the palm normal pointing out of the palm** (the side fingers close toward).
//!
//! ```
//! use prehensile_core::{shapes, ObjectModel};
//! let mesh = shapes::builtin_object("sphere").unwrap();
//! let object = ObjectModel::new("sphere", mesh, None).unwrap();
//! assert!(object.volume() > 0.0);
//! ```
#![deny(missing_docs)]

pub mod animation;
pub mod collision;
mod edge_groups;
pub mod finger_closing;
pub mod geometry;
pub mod hand;
pub mod math;
pub mod mesh;
pub mod object;
pub mod parameter;
pub mod random;
pub mod search;
pub mod shapes;
pub mod stability;
pub mod workspace;

pub use collision::{Capsule, CollisionCounters};
pub use finger_closing::{close_fingers, ClosingOutcome, ClosingParams};
pub use hand::GraspMovement;
pub use hand::{HandDescription, HandError, HandModel};
pub use mesh::{DroppedTriangles, MeshDefect, MeshError, MeshReport, TriangleMesh};
pub use object::{ObjectError, ObjectModel};
pub use workspace::Workspace;
