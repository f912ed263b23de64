//! What a [`crate::Simulation`] asks of the physics that steps it: bodies for hands and an
//! object, the hands' joint state, their drive for the next step, and what touched. Two engines
//! answer: [`crate::reduced::world::ReducedWorld`] (the default: the hand in reduced coordinates
//! on the project's own dynamics, with a contact solver of its own) and
//! [`crate::rapier::world::RapierWorld`] (rapier's impulse joints). The simulation keeps everything else: the
//! controllers, their state machines, the recording and the checks.

use prehensile_control::JointSpring;
use prehensile_core::math::{Transform, Vec3};
use prehensile_core::{HandModel, ObjectModel};

use crate::error::{Divergence, SimError};
use crate::world::contacts::Contacts;
use crate::world::holding_wrench::FrameMotion;

/// What drives one hand over the next step.
pub(crate) struct HandDrive<'a> {
    /// The joint angles the springs were computed at (read by [`PhysicsEngine::joint_state`]).
    pub q: &'a [f64],
    /// The controller's τP + τA as one implicit spring per degree of freedom.
    pub springs: &'a [JointSpring],
    /// A ball joint's cross torques (explicit), zero elsewhere.
    pub coupling: &'a [f64],
    /// How the palm moves now (world), whether or not it is compensated.
    pub palm: FrameMotion,
    /// Whether τG holds the hand against gravity.
    pub compensate_gravity: bool,
    /// Whether τARM carries the hand along with the palm.
    pub compensate_arm: bool,
    /// The hand's root placement at the end of the step (the arm is prescribed).
    pub next_root: Transform,
}

/// A physics engine holding hands and at most one object.
pub(crate) trait PhysicsEngine: Send {
    /// Adds `hand` with its root at `root` and joint angles `start`.
    fn add_hand(
        &mut self,
        hand: &HandModel,
        root: &Transform,
        start: &[f64],
    ) -> Result<(), SimError>;
    /// Adds the object at `pose` (held in place while `fixed`); returns its mass, kg.
    fn add_object(
        &mut self,
        object: &ObjectModel,
        pose: &Transform,
        fixed: bool,
    ) -> Result<f64, SimError>;
    /// Lets a fixed object go.
    fn let_go_object(&mut self);
    /// The object's pose, if there is one.
    fn object_pose(&self) -> Option<Transform>;
    /// Hand `i`'s palm (root bone) frame now.
    fn palm(&self, i: usize) -> Transform;
    /// Hand `i`'s joint angles and rates now.
    fn joint_state(&self, i: usize, q: &mut [f64], qd: &mut [f64]);
    /// Sets what drives hand `i` over the next step.
    fn drive(&mut self, i: usize, drive: &HandDrive) -> Result<(), SimError>;
    /// Advances the world by one step of the settings' length.
    fn step(&mut self) -> Result<(), SimError>;
    /// Contacts of hand `i` with everything outside it in the last step.
    fn contacts(&self, i: usize) -> Contacts;
    /// The deepest penetration of hand `i` into anything outside it in the last step, metres.
    fn penetration(&self, i: usize) -> f64;
    /// What ran away or came apart, if anything did: which hand and bone, or the object.
    fn diverged(&self) -> Option<Divergence>;
    /// Hand `i`'s bone frames now, into `out` (one per bone).
    fn bone_frames(&self, i: usize, out: &mut Vec<Transform>);
}

/// True when a body's place is not finite or it moves faster than anything a hand does
/// (2000 rad/s, 50 m/s).
pub(crate) fn runaway(position_finite: bool, linear: &Vec3, angular: &Vec3) -> bool {
    !(position_finite && angular.norm() < 2000.0 && linear.norm() < 50.0)
}

/// What diverged when bone `k` of hand `i` ran away: the bone and its joint.
pub(crate) fn bone_ran_away(hand: &HandModel, i: usize, k: usize) -> Divergence {
    let bone = &hand.bones()[k];
    Divergence::Bone {
        hand: i,
        bone: bone.name.clone(),
        joint: hand
            .dof_names()
            .get(bone.first_dof)
            .map_or("fixed", |s| s.as_str())
            .to_string(),
    }
}
