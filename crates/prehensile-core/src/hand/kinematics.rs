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
    for i in 0..hand.bones().len() {
        place_bone(hand, root, rotations, i, world);
    }
}

/// [`forward_kinematics`] of `bones` alone (in index order, each bone's parent among them or
/// none), for a caller that reads no other bone: the same transforms for them.
pub fn forward_kinematics_of(
    hand: &HandModel,
    root: &Transform,
    rotations: &[Rotation],
    bones: &[usize],
    world: &mut [Transform],
) {
    for &i in bones {
        place_bone(hand, root, rotations, i, world);
    }
}

/// Places bone `i` in `world` from its parent's transform (or `root`) and its rotation.
#[inline(always)]
fn place_bone(
    hand: &HandModel,
    root: &Transform,
    rotations: &[Rotation],
    i: usize,
    world: &mut [Transform],
) {
    let bone = &hand.bones()[i];
    let local = bone.rest * Transform::from_parts(Default::default(), rotations[i]);
    world[i] = match bone.parent {
        Some(p) => world[p] * local,
        None => root * local,
    };
}
