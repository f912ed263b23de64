//! Forward kinematics: one flat loop over bones stored parents-first.

use crate::hand::HandModel;
use crate::math::{Rotation, Transform};

/// Writes the world transform of every bone into `world`, given each bone's joint rotation and
/// the root's placement. `world` and `rotations` have one entry per bone. Allocates nothing.
#[inline]
pub fn forward_kinematics(
    hand: &HandModel,
    root: &Transform,
    rotations: &[Rotation],
    world: &mut [Transform],
) {
    for (i, bone) in hand.bones().iter().enumerate() {
        let local = bone.rest * Transform::from_parts(Default::default(), rotations[i]);
        world[i] = match bone.parent {
            Some(p) => world[p] * local,
            None => root * local,
        };
    }
}
