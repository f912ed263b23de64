//! Keyframes of a grasp for export: the hand approaches along the hook's −y in the movement's
//! start pose, then closes each bone from the start to the fraction it reached.

use crate::hand::HandModel;
use crate::math::{Rotation, Transform};
use crate::movement::GraspMovement;
use crate::search::translate_to_free::hand_root;

/// One keyframe: a time, the root bone's world placement and every bone's joint rotation.
#[derive(Debug, Clone, PartialEq)]
pub struct Keyframe {
    /// Seconds from the start.
    pub time: f64,
    /// Where the hand's root is (the placement its rest transform is relative to).
    pub root: Transform,
    /// Joint rotation of every bone.
    pub rotations: Vec<Rotation>,
}

/// Approach from `approach` metres further back over one second, then close over one second to
/// the per-bone `fractions` of the movement; `steps` keyframes per phase.
pub fn approach_and_close(
    hand: &HandModel,
    movement: &GraspMovement,
    hook: &Transform,
    offset: f64,
    fractions: &[f64],
    approach: f64,
    steps: usize,
) -> Vec<Keyframe> {
    let steps = steps.max(1);
    let n = hand.bones().len();
    let mut frames = Vec::with_capacity(2 * steps + 1);
    for k in 0..=2 * steps {
        let (back, closing) = if k <= steps {
            (approach * (1.0 - k as f64 / steps as f64), 0.0)
        } else {
            (0.0, (k - steps) as f64 / steps as f64)
        };
        frames.push(Keyframe {
            time: k as f64 / steps as f64,
            root: hand_root(hook, movement, offset + back),
            rotations: (0..n)
                .map(|b| movement.rotation_at(b, closing * fractions[b]))
                .collect(),
        });
    }
    frames
}
