//! # prehensile-control
//!
//! Rigid-body dynamics of a hand model, engine-agnostic (state in, torques out): inverse
//! dynamics, the joint-space mass matrix, the outboard inertia of every joint (the `I` of Pollard
//! & Zordan's Eq. 3 and 5) and gravity torques; the controller's torque laws, state machine,
//! blends and grip strength; fitting the controller to an example motion, and its file format.
//! The simulation lives in `prehensile-sim`.
//!
//! Model apart from data, as in Pinocchio and MuJoCo: [`DynamicsModel`] is built once per hand
//! and [`rnea`], [`crba`], [`outboard_inertia_into`] write into its [`DynamicsData`];
//! [`GraspController`] is the controller as fitted or read, and each hand running it keeps its own
//! [`ControllerState`]. Loops allocate nothing (`tests/no_allocation.rs`). The functions taking a
//! `HandModel` ([`inverse_dynamics`], [`mass_matrix`], [`outboard_inertia`], [`gravity_torques`])
//! build a model per call, for one-off use.
//!
//! Conventions: the base is the hand's root bone, fixed; gravity is given in the root bone's
//! frame; joint vectors follow [`prehensile_core::HandModel::dof_names`].
#![deny(missing_docs)]
//!
//! Layers, bottom up (a module uses only those below it): [`DynamicsError`]; `dynamics` (the
//! model and data, inertia, inverse and forward dynamics, the mass matrix); `controller` (the
//! setpoints and the torque laws); `fitting` (example motions, passive and active fitting, the
//! controller file).

mod controller;
mod dynamics;
mod error;
mod fitting;

pub use controller::setpoint::{Blend, PerSetpoint, Setpoint, SETPOINT_NAMES};
pub use controller::torque_laws::{
    active_torque, ball_joint_coupling, joint_springs, passive_torque, ControllerState, Gains,
    GraspController, GraspState, JointSpring, Setpoints,
};
pub use dynamics::body_inertia::OutboardInertia;
pub use dynamics::forward_dynamics::forward_dynamics;
pub use dynamics::inverse_dynamics::{
    bias_torques, gravity_torques, inverse_dynamics, inverse_dynamics_moving_base, rnea, BaseMotion,
};
pub use dynamics::mass_matrix::{crba, mass_matrix};
pub use dynamics::model::{DynamicsData, DynamicsModel};
pub use dynamics::outboard_inertia::{outboard_inertia, outboard_inertia_into};
pub use error::DynamicsError;
pub use fitting::active_fitting::fit_active;
pub use fitting::controller_fitting::{
    fit_controller, ControllerFile, GainsRecord, SetpointRecord, CONTROLLER_SCHEMA,
};
pub use fitting::example_motion::{Motion, MOTION_SCHEMA};
pub use fitting::passive_fitting::fit_passive;
