//! Hand positioning (§5.2, §6.5.1, Alg. 3): the hand hangs from a hook frame by its movement's
//! grasp center and moves only by rotating the hook and by backing the grasp center away from the
//! object along the hook's y axis until no capsule touches the object.

use crate::collision::Capsule;
use crate::hand::kinematics::forward_kinematics;
use crate::hand::movement::GraspMovement;
use crate::hand::HandModel;
use crate::math::{Transform, Vec3};
use crate::object::ObjectModel;
use crate::workspace::Workspace;

/// Placement of the hand's root for a hook frame, the movement's grasp center and a back-off
/// distance `offset` (metres along the hook's −y: the palm faces the hook's +y side).
#[inline]
pub fn hand_root(hook: &Transform, movement: &GraspMovement, offset: f64) -> Transform {
    let back = Transform::translation(0.0, -offset, 0.0);
    let center = Transform::translation_from(-movement.grasp_center().coords);
    hook * back * center
}

trait TranslationFrom {
    fn translation_from(v: Vec3) -> Self;
}

impl TranslationFrom for Transform {
    fn translation_from(v: Vec3) -> Self {
        Transform::translation(v.x, v.y, v.z)
    }
}

/// Does any capsule of the hand, in the movement's start pose at `root`, touch the object?
/// `likely` is the capsule asked first, and becomes the one found touching: the same answer in
/// any order, but TranslateToFree's next placement is most often blocked by the capsule that
/// blocked the last, and a touching capsule ends the test.
pub fn start_pose_touches(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &GraspMovement,
    root: &Transform,
    likely: &mut usize,
    ws: &mut Workspace,
) -> bool {
    ws.counters.placements += 1;
    ws.rotations.copy_from_slice(movement.start_rotations());
    forward_kinematics(hand, root, &ws.rotations, &mut ws.world);
    let capsules = hand.capsules();
    let first = (*likely).min(capsules.len().saturating_sub(1));
    let order = std::iter::once(first).chain((0..capsules.len()).filter(|&k| k != first));
    for k in order.take(capsules.len()) {
        let c = &capsules[k];
        let w = ws.world[c.bone];
        let capsule = Capsule {
            a: w * c.a,
            b: w * c.b,
            radius: c.radius,
        };
        if object.capsule_touches(&capsule, &mut ws.counters) {
            *likely = k;
            return true;
        }
    }
    false
}

/// How TranslateToFree advances.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum TranslateMode {
    /// The thesis's Alg. 3: fixed steps of `step` metres until free.
    Steps {
        /// Step length, metres.
        step: f64,
    },
    /// Steps of `coarse` metres until free, then bisection back toward the object until the free
    /// and the touching offsets are less than `precision` apart. Finds the first free offset to
    /// within `precision`, unless a free gap thinner than `coarse` is stepped over.
    Bisection {
        /// Coarse step, metres.
        coarse: f64,
        /// Final precision, metres.
        precision: f64,
    },
    /// As `Bisection`, but each jump is at least a lower bound of the distance still to go:
    /// moving the hand by δ changes every capsule's clearance by at most δ, so a touching capsule
    /// whose clearance is at most `u` (bounded by the distance grid) needs δ ≥ radius − u. Deep
    /// contacts are left in one jump instead of many coarse steps.
    DistanceBound {
        /// Smallest jump, metres.
        coarse: f64,
        /// Final precision, metres.
        precision: f64,
    },
}

impl Default for TranslateMode {
    fn default() -> Self {
        TranslateMode::DistanceBound {
            coarse: 0.004,
            precision: 0.00025,
        }
    }
}

/// Alg. 3: back the hand off until its start pose is free; returns the offset, or `None` if it is
/// still touching after `max_offset` metres, or still touching at `give_up_at` metres or more
/// (every offset it could then return is larger; `f64::INFINITY` never gives up early).
#[allow(clippy::too_many_arguments)]
pub fn translate_to_free(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &GraspMovement,
    hook: &Transform,
    mode: TranslateMode,
    max_offset: f64,
    give_up_at: f64,
    ws: &mut Workspace,
) -> Option<f64> {
    // The capsule that blocked the last placement, asked first at the next; kept within this
    // call, so that an evaluation's queries do not depend on the evaluations before it.
    let mut likely = 0;
    let mut touches = |offset: f64, ws: &mut Workspace| {
        let root = hand_root(hook, movement, offset);
        start_pose_touches(hand, object, movement, &root, &mut likely, ws)
    };
    let mut offset = 0.0;
    let mut last_touching = None;
    while touches(offset, ws) {
        // The answer lies beyond the last touching offset.
        if offset >= give_up_at {
            return None;
        }
        let jump = match mode {
            TranslateMode::Steps { step } => step,
            TranslateMode::Bisection { coarse, .. } => coarse,
            TranslateMode::DistanceBound { coarse, .. } => {
                distance_still_to_go(hand, object, ws, coarse)
            }
        };
        last_touching = Some(offset);
        offset += jump;
        if offset > max_offset {
            return None;
        }
    }
    let precision = match mode {
        TranslateMode::Steps { .. } => return Some(offset),
        TranslateMode::Bisection { precision, .. }
        | TranslateMode::DistanceBound { precision, .. } => precision,
    };
    if let Some(mut lo) = last_touching {
        let mut hi = offset;
        while hi - lo > precision {
            let mid = 0.5 * (lo + hi);
            if touches(mid, ws) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        offset = hi;
    }
    Some(offset)
}

/// A lower bound on how far the hand, posed in `ws`, must still move to be free: the largest
/// `radius − clearance upper bound` over its capsules, or `at_least` if that is larger.
fn distance_still_to_go(
    hand: &HandModel,
    object: &ObjectModel,
    ws: &Workspace,
    at_least: f64,
) -> f64 {
    let collider = object.collider();
    hand.capsules().iter().fold(at_least, |most, c| {
        let w = ws.world[c.bone];
        // Only a clearance below `radius − most` can raise the bound.
        let clearance =
            collider.segment_clearance_upper_bound(&(w * c.a), &(w * c.b), c.radius - most);
        most.max(c.radius - clearance)
    })
}
