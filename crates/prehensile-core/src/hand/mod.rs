//! The hand model (§4): an immutable tree of bones stored parents-first, their joints with limits,
//! coupling rules, one capsule per bone segment, fingers as chains from the root, and grasp
//! movements.
//!
//! Layers, bottom up: the description and the parts a hand is given as, its error and checks;
//! the movement's data and the model; kinematics; the facts closing asks for; building
//! movements and deriving them for imported hands; capsules and inertia from geometry; and the
//! assembly of a model from parts or a description on top.

mod assembly;
pub mod capsule_inertia;
pub mod closing_facts;
pub mod convex_capsules;
mod description;
mod error;
mod from_description;
pub mod kinematics;
mod limits;
mod model;
pub mod movement;
mod movement_building;
pub mod movement_derivation;
mod parts;
mod validation;

pub use description::{
    BoneDescription, CouplingDescription, HandDescription, JointDescription, MovementDescription,
};
pub use error::{HandError, MovementProblem};
pub use limits::{MAX_BONES, MAX_HAND_EXTENT, MIN_BONE_LENGTH};
pub use model::{Axis, Bone, BoneCapsule, Coupling, Finger, HandModel, Inertial, Joint};
pub use movement::{GraspMovement, Via};
pub use parts::{BonePart, HandParts};
