//! # prehensile-control
//!
//! Rigid-body dynamics of a hand model, engine-agnostic (state in, torques out): inverse
//! dynamics, the joint-space mass matrix, the outboard inertia of every joint (the `I` of Pollard
//! & Zordan's Eq. 3 and 5) and gravity torques; the controller's torque laws, state machine,
//! blends and grip strength. Setpoint fitting and the simulation are not built yet.
//!
//! Conventions: the base is the hand's root bone, fixed; gravity is given in the root bone's
//! frame; joint vectors follow [`prehensile_core::HandModel::dof_names`].
#![warn(missing_docs)]

mod active_fitting;
mod controller;
mod forward_dynamics;
mod inverse_dynamics;
mod mass_matrix;
mod passive_fitting;

pub use active_fitting::fit_active;
pub use controller::{
    active_torque, passive_torque, Gains, GraspController, GraspState, Setpoints,
};
pub use forward_dynamics::forward_dynamics;
pub use inverse_dynamics::{
    gravity_torques, inverse_dynamics, inverse_dynamics_moving_base, BaseMotion, DynamicsError,
};
pub use mass_matrix::{mass_matrix, outboard_inertia};
pub use passive_fitting::fit_passive;
