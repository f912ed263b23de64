//! What both engines share, below them: the world's settings (with each engine's own), the
//! engine interface a [`crate::Simulation`] steps, the contact report, the prescribed arm and
//! the wrench that holds a hand on it, and an object's mass properties.

pub mod arm_trajectory;
pub mod contacts;
pub(crate) mod convert;
pub(crate) mod engine;
pub mod holding_wrench;
pub(crate) mod object_mass;
pub mod settings;
