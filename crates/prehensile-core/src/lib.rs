//! # prehensile-core
//!
//! Hand and object models, capsule collision, kinematics, finger closing, stability and the
//! real-time grasp pose search of Paolo Caputo's thesis *Real-Time Grasp Pose Generation for
//! Virtual Hand* (Politecnico di Milano, 2015). No file I/O, no physics engine, no printing:
//! formats live in `prehensile-formats`, the simulation in `prehensile-sim`, the CLI in
//! `prehensile-cli`.
//!
//! Conventions: SI units; hand frame with z from the wrist along the fingers, x across the
//! knuckles and **y the palm normal pointing out of the palm** (the side fingers close toward).
//!
//! Layers, bottom up (a module uses only those below it): [`math`], [`random`], [`parameter`],
//! [`geometry`]; [`mesh`] and [`shapes`]; [`hand`] (its model, kinematics and movements);
//! [`collision`]; [`object`]; [`stability`]; [`workspace`]; [`finger_closing`]; [`search`];
//! [`animation`].
//!
//! A whole request, as the CLI makes it:
//!
//! ```
//! use prehensile_core::search::{find_grasp, GraspOptions};
//! use prehensile_formats::sources::{hand_from_spec, object_from_spec};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let hand = hand_from_spec("human")?;
//! let (object, _repairs) = object_from_spec("mug", 1.0, None)?;
//! let options = GraspOptions { seed: 2, threads: Some(1), ..GraspOptions::default() };
//! let request = options.request(&hand, &object)?;
//! let result = find_grasp(&hand, &object, &request, &mut ())?;
//! assert!(result.valid);
//! # Ok(())
//! # }
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
