//! Per-thread mutable buffers for the hot loops, sized once from a hand model (the model/workspace
//! split of MuJoCo's mjModel/mjData).

use crate::collision::{Capsule, CollisionCounters};
use crate::hand::HandModel;
use crate::math::{Rotation, Transform};
use crate::stability::{Contact, GraspWrenchSpace};

/// Scratch space for kinematics, collision and finger closing. Make one per thread.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// Joint rotation of every bone.
    pub rotations: Vec<Rotation>,
    /// World transform of every bone.
    pub world: Vec<Transform>,
    /// Interpolation fraction each bone has reached.
    pub fraction: Vec<f64>,
    /// Whether each bone has stopped.
    pub stopped: Vec<bool>,
    /// Whether each bone stopped because it touched the object.
    pub touching: Vec<bool>,
    /// Interpolation index each bone reached (0..=N).
    pub reached: Vec<u32>,
    /// World capsules of the current pose, one per hand capsule.
    pub capsules: Vec<Capsule>,
    /// World capsules at the touching end of a contact refinement's bracket (finger closing's
    /// scratch).
    pub capsules_touching: Vec<Capsule>,
    /// Each bone's world transform when finger closing last found it free, if it has in this
    /// closing: a bone posed there again is free without a query (the same pose gets the same
    /// answer).
    pub free_pose: Vec<Option<Transform>>,
    /// Each bone's world transform when finger closing last found it touching, if it has in
    /// this closing: a bone posed there again touches without a query.
    pub touching_pose: Vec<Option<Transform>>,
    /// Collision query counts.
    pub counters: CollisionCounters,
    /// Contacts of the last stability evaluation.
    pub contacts: Vec<Contact>,
    /// Buffers of the grasp wrench space.
    pub wrench_space: GraspWrenchSpace,
}

impl Workspace {
    /// Buffers sized for `hand`.
    pub fn new(hand: &HandModel) -> Self {
        let n = hand.bones().len();
        let zero = Capsule {
            a: Default::default(),
            b: Default::default(),
            radius: 0.0,
        };
        Self {
            rotations: vec![Rotation::identity(); n],
            world: vec![Transform::identity(); n],
            fraction: vec![0.0; n],
            stopped: vec![false; n],
            touching: vec![false; n],
            reached: vec![0; n],
            capsules: vec![zero; hand.capsules().len()],
            capsules_touching: vec![zero; hand.capsules().len()],
            free_pose: vec![None; n],
            touching_pose: vec![None; n],
            counters: CollisionCounters::default(),
            contacts: Vec::with_capacity(3 * hand.capsules().len()),
            wrench_space: GraspWrenchSpace::new(),
        }
    }
}
