//! Keyframes of a grasp for export: the hand approaches along the hook's −y in the movement's
//! start pose, then closes each bone from the start to the fraction it reached.

use crate::hand::movement::GraspMovement;
use crate::hand::HandModel;
use crate::math::{Point3, Rotation, Transform};
use crate::search::translate_to_free::hand_root;
use crate::search::{GraspResult, SearchError};

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

/// The approach and closing of a search result ([`approach_and_close`] from 10 cm back, each
/// half over one second at 12 frames a second), for `hand`, the hand that found it.
pub fn result_keyframes(
    hand: &HandModel,
    result: &GraspResult,
) -> Result<Vec<Keyframe>, SearchError> {
    let movement = hand
        .movement(&result.movement)
        .ok_or_else(|| SearchError::UnknownMovement {
            hand: hand.name().to_string(),
            movement: result.movement.clone(),
            known: hand
                .movements()
                .iter()
                .map(|m| m.name().to_string())
                .collect(),
            auto_allowed: false,
        })?;
    let [x, y, z, w] = result.hook_rotation_xyzw;
    let hook = Transform::from_parts(
        Point3::from(result.hook).coords.into(),
        Rotation::from_quaternion(nalgebra::Quaternion::new(w, x, y, z)),
    );
    let fractions: Vec<f64> = result.bones.iter().map(|b| b.fraction).collect();
    Ok(approach_and_close(
        hand,
        movement,
        &hook,
        result.offset,
        &fractions,
        0.1,
        12,
    ))
}
