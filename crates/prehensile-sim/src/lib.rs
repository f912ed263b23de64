//! # prehensile-sim
//!
//! Physically simulated hands: the grasp controller of `prehensile-control` driving hands built
//! from Prehensile hand models, with objects as dynamic rigid bodies, a prescribed arm
//! trajectory, friction and gravity; and the scenarios of Pollard & Zordan's paper with their
//! metrics. Two engines step them ([`Engine`]): a rapier3d world (one body per bone, impulse
//! joints), and the hand in reduced coordinates on the project's own dynamics with a contact
//! solver of its own. The only crate of the workspace that depends on rapier.
//!
//! Layers, bottom up (a module uses only those below it): [`SimError`]; `world` (settings,
//! the engine interface, contacts, the arm); the two engines, `reduced` and `rapier`, each in
//! its own folder; [`Simulation`], which steps either; and the [`scenarios`] on top.
#![deny(missing_docs)]

mod error;
mod rapier;
mod reduced;
pub mod scenarios;
mod simulation;
mod world;

pub use error::{Divergence, SimError};
pub use rapier::articulated_hand::{
    check_hand, hand_groups, ArticulatedHand, INTERMEDIATE_MASS_FRACTION,
};
pub use rapier::object_body::{object_shape, ObjectBody, ObjectShape, OBJECT_GROUP};
pub use simulation::{DistanceTo, HandSetup, Simulation, StateChange};
pub use world::arm_trajectory::{ArmTrajectory, Shake, Waypoint};
pub use world::contacts::Contacts;
pub use world::holding_wrench::{holding_wrench, FrameMotion};
pub use world::settings::{Engine, RapierSettings, ReducedSettings, Settings};
