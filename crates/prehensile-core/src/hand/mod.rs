//! The hand model (§4): an immutable tree of bones stored parents-first, their joints with limits,
//! coupling rules, one capsule per bone segment, fingers as chains from the root, and grasp
//! movements.

mod build;
pub mod capsule_inertia;
pub mod closing_facts;
pub mod convex_capsules;
mod description;
pub mod kinematics;
mod model;
pub mod movement;
mod movement_building;
pub mod movement_derivation;

pub use build::{BonePart, HandError, HandParts};
pub use description::{
    BoneDescription, CouplingDescription, HandDescription, JointDescription, MovementDescription,
};
pub use model::{Axis, Bone, BoneCapsule, Coupling, Finger, HandModel, Inertial, Joint};
pub use movement::{GraspMovement, Via};
