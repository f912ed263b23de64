//! # prehensile-sim
//!
//! Physically simulated hands: the grasp controller of `prehensile-control` driving hands built
//! from Prehensile hand models, with objects as dynamic rigid bodies, a prescribed arm
//! trajectory, friction and gravity; and the scenarios of Pollard & Zordan's paper with their
//! metrics. Two engines step them ([`Engine`]): a rapier3d world (one body per bone, impulse
//! joints), and the hand in reduced coordinates on the project's own dynamics with a contact
//! solver of its own. The only crate of the workspace that depends on rapier.
#![warn(missing_docs)]

mod arm_trajectory;
mod articulated_hand;
mod convert;
mod holding_wrench;
mod object_body;
mod physics_engine;
mod projected_gauss_seidel;
mod rapier_world;
mod reduced_hand;
mod reduced_world;
pub mod scenarios;
mod simulation;

pub use arm_trajectory::{ArmTrajectory, Shake, Waypoint};
pub use articulated_hand::{check_hand, hand_groups, ArticulatedHand, INTERMEDIATE_MASS_FRACTION};
pub use holding_wrench::{holding_wrench, FrameMotion};
pub use object_body::{object_shape, ObjectBody, ObjectShape, OBJECT_GROUP};
pub use physics_engine::Engine;
pub use simulation::{Contacts, DistanceTo, HandSetup, Settings, Simulation, StateChange};

/// Why a simulation cannot run or stopped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// The hand cannot be simulated.
    #[error("{0}")]
    Hand(String),
    /// The object cannot be simulated.
    #[error("{0}")]
    Object(String),
    /// A setting or input is out of range.
    #[error("{0}")]
    Settings(String),
    /// The grasp search found no valid grasp of the object.
    #[error("{0}")]
    NoGrasp(String),
    /// The grasp search for the scenario could not start.
    #[error(transparent)]
    Search(#[from] prehensile_core::search::SearchError),
    /// The simulation blew up; stopped before anything non-finite was written.
    #[error("the simulation diverged at t = {time:.4} s: {what}")]
    Diverged {
        /// Seconds.
        time: f64,
        /// Which hand, bone and joint, or the object.
        what: String,
    },
}
