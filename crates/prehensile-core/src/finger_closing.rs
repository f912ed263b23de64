//! Finger closing (§5.4, §6.4, Alg. 1–2): advance every bone through N interpolations of a grasp
//! movement; a bone that touches the object stops together with all its predecessors in its
//! finger. Beyond the thesis, each stopping bone is refined by bisection between its last free
//! and its first touching fraction, so the final pose touches within a tolerance instead of
//! penetrating by up to a whole interpolation step.

use crate::collision::Capsule;
use crate::hand::HandModel;
use crate::math::Transform;
use crate::movement::GraspMovement;
use crate::object::ObjectModel;
use crate::workspace::Workspace;

/// Most bisection steps of the contact refinement.
const MAX_REFINE_STEPS: u32 = 40;

/// Parameters of finger closing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosingParams {
    /// Number of interpolations N between start and end pose (the thesis uses 10–20).
    pub interpolations: u32,
    /// Refine stopping bones until they touch within this many metres; `None` keeps the thesis's
    /// behaviour (a bone stays at the interpolation where it first collided).
    pub contact_tolerance: Option<f64>,
}

impl Default for ClosingParams {
    fn default() -> Self {
        Self {
            interpolations: 20,
            contact_tolerance: Some(0.0005),
        }
    }
}

/// Summary of one finger closing; per-bone results stay in the [`Workspace`]
/// (`reached`, `fraction`, `touching`, `world`, `capsules`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ClosingOutcome {
    /// Bones that stopped because they touched the object.
    pub touching_bones: u32,
    /// Some bone already touched the object at the start pose.
    pub started_in_collision: bool,
}

/// Closes the hand's fingers along `movement` with the root bone placed at `root`.
/// Allocates nothing.
pub fn close_fingers(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &GraspMovement,
    root: &Transform,
    params: &ClosingParams,
    ws: &mut Workspace,
) -> ClosingOutcome {
    let bones = hand.bones();
    let n = params.interpolations.max(1);
    let mut outcome = ClosingOutcome::default();
    for b in 0..bones.len() {
        ws.rotations[b] = movement.rotation_at(b, 0.0);
        ws.fraction[b] = 0.0;
        ws.reached[b] = 0;
        ws.stopped[b] = b == 0;
        ws.touching[b] = false;
    }
    crate::kinematics::forward_kinematics(hand, root, &ws.rotations, &mut ws.world);
    let mut moving = bones.len() - 1;
    for i in 1..=n {
        if moving == 0 {
            break;
        }
        let f = i as f64 / n as f64;
        for b in 1..bones.len() {
            if ws.stopped[b] {
                continue;
            }
            let previous = ws.fraction[b];
            set_fraction(hand, movement, b, f, ws);
            ws.reached[b] = i;
            if !bone_touches(hand, object, b, ws) {
                continue;
            }
            if let Some(tolerance) = params.contact_tolerance {
                set_fraction(hand, movement, b, previous, ws);
                if bone_touches(hand, object, b, ws) {
                    outcome.started_in_collision = true;
                } else {
                    refine_contact(hand, object, movement, b, previous, f, tolerance, ws);
                }
            }
            ws.touching[b] = true;
            outcome.touching_bones += 1;
            let mut at = Some(b);
            while let Some(k) = at {
                if !ws.stopped[k] {
                    ws.stopped[k] = true;
                    moving -= 1;
                }
                at = hand.chain_predecessor(k);
            }
        }
    }
    for b in 1..bones.len() {
        if !ws.stopped[b] {
            ws.reached[b] = n;
        }
    }
    update_world_capsules(hand, ws);
    outcome
}

/// Moves bone `b` to fraction `f` of the movement and updates its world transform from its
/// parent's (descendants are updated when the loop reaches them).
#[inline]
fn set_fraction(hand: &HandModel, movement: &GraspMovement, b: usize, f: f64, ws: &mut Workspace) {
    let bone = &hand.bones()[b];
    ws.fraction[b] = f;
    ws.rotations[b] = movement.rotation_at(b, f);
    let local = bone.rest * Transform::from_parts(Default::default(), ws.rotations[b]);
    ws.world[b] = match bone.parent {
        Some(p) => ws.world[p] * local,
        None => local,
    };
}

/// Does any capsule of bone `b` touch the object in the current pose?
#[inline]
fn bone_touches(hand: &HandModel, object: &ObjectModel, b: usize, ws: &mut Workspace) -> bool {
    let world = ws.world[b];
    hand.bone_capsules(b).iter().any(|c| {
        let capsule = Capsule {
            a: world * c.a,
            b: world * c.b,
            radius: c.radius,
        };
        object.capsule_touches(&capsule, &mut ws.counters)
    })
}

/// Bisects bone `b` between a free fraction `lo` and a touching fraction `hi` until its capsules
/// move less than `tolerance` between the two, and leaves it at the free end.
#[allow(clippy::too_many_arguments)]
fn refine_contact(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &GraspMovement,
    b: usize,
    mut lo: f64,
    mut hi: f64,
    tolerance: f64,
    ws: &mut Workspace,
) {
    for _ in 0..MAX_REFINE_STEPS {
        if capsule_travel(hand, movement, b, lo, hi, ws) <= tolerance {
            break;
        }
        let mid = 0.5 * (lo + hi);
        set_fraction(hand, movement, b, mid, ws);
        if bone_touches(hand, object, b, ws) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    set_fraction(hand, movement, b, lo, ws);
}

/// Largest distance any capsule end of bone `b` moves between fractions `lo` and `hi` (a bound on
/// every point of the capsule, since the motion is a rotation about the joint).
fn capsule_travel(
    hand: &HandModel,
    movement: &GraspMovement,
    b: usize,
    lo: f64,
    hi: f64,
    ws: &Workspace,
) -> f64 {
    let bone = &hand.bones()[b];
    let parent = bone.parent.map_or(Transform::identity(), |p| ws.world[p]);
    let at = |f: f64| {
        parent * bone.rest * Transform::from_parts(Default::default(), movement.rotation_at(b, f))
    };
    let (w0, w1) = (at(lo), at(hi));
    hand.bone_capsules(b)
        .iter()
        .map(|c| {
            ((w0 * c.a) - (w1 * c.a))
                .norm()
                .max(((w0 * c.b) - (w1 * c.b)).norm())
        })
        .fold(0.0, f64::max)
}

/// Writes every capsule's world position into `ws.capsules`.
pub fn update_world_capsules(hand: &HandModel, ws: &mut Workspace) {
    for (slot, c) in ws.capsules.iter_mut().zip(hand.capsules()) {
        let w = ws.world[c.bone];
        *slot = Capsule {
            a: w * c.a,
            b: w * c.b,
            radius: c.radius,
        };
    }
}
