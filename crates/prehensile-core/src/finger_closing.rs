//! Finger closing (§5.4, §6.4, Alg. 1–2): advance every bone through N interpolations of a grasp
//! movement; a bone that touches the object stops together with all its predecessors in its
//! finger. Beyond the thesis, each stopping bone is refined by bisection between its last free
//! and its first touching fraction, so the final pose touches within a tolerance instead of
//! penetrating by up to a whole interpolation step.

use std::ops::Range;

use crate::collision::Capsule;
use crate::hand::movement::GraspMovement;
use crate::hand::HandModel;
use crate::math::Transform;
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
    close_fingers_while(hand, object, movement, root, params, ws, &mut |_, _| true)
        .expect("a closing never told to stop finishes")
}

/// [`close_fingers`], asking `go_on(finger, ws)` each time a finger has closed when the fingers
/// close one after another ([`crate::hand::closing_facts::fingers_close_apart`]), and stopping with `None` (the workspace
/// holding a partial pose) as soon as it answers no: a search stops a pose whose fingers
/// closed so far already rule it out. Hands whose fingers must close together are closed
/// whole and never asked. Allocates nothing.
pub fn close_fingers_while(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &GraspMovement,
    root: &Transform,
    params: &ClosingParams,
    ws: &mut Workspace,
    go_on: &mut dyn FnMut(usize, &Workspace) -> bool,
) -> Option<ClosingOutcome> {
    let bones = hand.bones();
    let mut outcome = ClosingOutcome::default();
    ws.free_pose.fill(None);
    ws.touching_pose.fill(None);
    for b in 0..bones.len() {
        ws.rotations[b] = movement.rotation_at(b, 0.0);
        ws.fraction[b] = 0.0;
        ws.reached[b] = 0;
        ws.stopped[b] = b == 0;
        ws.touching[b] = false;
    }
    crate::hand::kinematics::forward_kinematics(hand, root, &ws.rotations, &mut ws.world);
    if hand.fingers_close_apart() {
        for (f, finger) in hand.fingers().iter().enumerate() {
            let bones = finger.bones.iter().copied();
            close_together(hand, object, movement, params, bones, &mut outcome, ws);
            if !go_on(f, ws) {
                return None;
            }
        }
    } else {
        close_together(
            hand,
            object,
            movement,
            params,
            1..bones.len(),
            &mut outcome,
            ws,
        );
    }
    outcome.touching_bones = ws.touching.iter().filter(|&&t| t).count() as u32;
    update_world_capsules(hand, ws);
    Some(outcome)
}

/// Alg. 1 over `group` (bones in index order, parents first): every bone of it advances through
/// the interpolations, and one that touches stops with its still-moving predecessors. Bones
/// that never stop end at the last interpolation.
fn close_together(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &GraspMovement,
    params: &ClosingParams,
    group: impl Iterator<Item = usize> + Clone,
    outcome: &mut ClosingOutcome,
    ws: &mut Workspace,
) {
    let bones = hand.bones();
    let n = params.interpolations.max(1);
    let mut moving = group.clone().filter(|&b| !ws.stopped[b]).count();
    for i in 1..=n {
        if moving == 0 {
            break;
        }
        let f = i as f64 / n as f64;
        for b in group.clone() {
            if ws.stopped[b] {
                continue;
            }
            let previous = ws.fraction[b];
            set_fraction(hand, movement, b, f, ws);
            ws.reached[b] = i;
            if !bone_touches(hand, object, b, ws) {
                continue;
            }
            // The bone and its still-moving predecessors (consecutive indices, parents first)
            // advanced together this step and stop together now.
            let mut top = b;
            while let Some(p) = hand.chain_predecessor(top) {
                if ws.stopped[p] {
                    break;
                }
                top = p;
            }
            let chain = top..b + 1;
            let finger_end = chain.start
                + bones[chain.start..]
                    .iter()
                    .take_while(|x| x.finger == bones[b].finger)
                    .count();
            if let Some(tolerance) = params.contact_tolerance {
                // Bracket the contact between the previous fraction (free: the last step checked
                // it, and a refinement earlier in this step kept this bone's pose free) and `f`.
                set_group(hand, movement, chain.clone(), previous, finger_end, ws);
                if !group_touches(hand, object, chain.start..finger_end, ws) {
                    refine_contact(
                        hand,
                        object,
                        movement,
                        chain.clone(),
                        finger_end,
                        [previous, f],
                        tolerance,
                        ws,
                    );
                } else {
                    outcome.started_in_collision = true;
                    ws.touching[b] = true;
                }
            } else {
                ws.touching[b] = true;
            }
            for k in chain {
                ws.stopped[k] = true;
                moving -= 1;
            }
            moving -= stop_coupled_followers(hand, object, movement, params.contact_tolerance, ws);
        }
    }
    for b in group {
        if !ws.stopped[b] {
            ws.reached[b] = n;
        }
    }
}

/// Beyond the thesis: the file's mechanical joint couplings (MJCF fixed tendons, URDF mimic
/// joints; [`crate::hand::Coupling::rigid`]) hold at every interpolation. A movement's poses obey them exactly ([`HandModel::constrain`]) and bones
/// interpolate their angles linearly, so bones at one fraction agree; a bone whose coupling leader
/// has stopped therefore stops at the leader's fraction. A follower still behind it is brought up
/// to it, and if that touches the object, leader and follower (a chain) find the contact
/// together. Returns how many bones it stopped. Allocates nothing.
fn stop_coupled_followers(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &GraspMovement,
    tolerance: Option<f64>,
    ws: &mut Workspace,
) -> usize {
    let mut stopped = 0;
    // Repeat for chains of couplings (a follower that leads another).
    loop {
        let mut changed = false;
        for c in hand.couplings().iter().filter(|c| c.rigid) {
            let (leader, follower) = (hand.bone_of_dof(c.leader), hand.bone_of_dof(c.follower));
            if !ws.stopped[leader] || ws.stopped[follower] {
                continue;
            }
            ws.stopped[follower] = true;
            stopped += 1;
            changed = true;
            let (at_leader, at_follower) = (ws.fraction[leader], ws.fraction[follower]);
            let finger = hand.bones()[follower].finger;
            let finger_end = follower
                + hand.bones()[follower..]
                    .iter()
                    .take_while(|x| x.finger == finger)
                    .count();
            set_group(
                hand,
                movement,
                follower..follower + 1,
                at_leader,
                finger_end,
                ws,
            );
            ws.reached[follower] = ws.reached[leader];
            if at_follower >= at_leader
                || !crate::hand::closing_facts::leads_its_chain(hand, leader, follower)
                || !group_touches(hand, object, follower..finger_end, ws)
            {
                continue;
            }
            let chain = leader..follower + 1;
            match tolerance {
                Some(t) => refine_contact(
                    hand,
                    object,
                    movement,
                    chain,
                    finger_end,
                    [at_follower, at_leader],
                    t,
                    ws,
                ),
                None => {
                    set_group(hand, movement, chain, at_follower, finger_end, ws);
                    ws.touching[follower] = true;
                }
            }
        }
        if !changed {
            return stopped;
        }
    }
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

/// Moves the bones in `group` (a chain, parents first) to fraction `f`, and the rest of the
/// finger (`group.end..finger_end`) along with them at their own fractions.
fn set_group(
    hand: &HandModel,
    movement: &GraspMovement,
    group: Range<usize>,
    f: f64,
    finger_end: usize,
    ws: &mut Workspace,
) {
    for k in group.clone() {
        set_fraction(hand, movement, k, f, ws);
    }
    for k in group.end..finger_end {
        set_fraction(hand, movement, k, ws.fraction[k], ws);
    }
}

/// Does any capsule of bone `b` touch the object in the current pose? The last pose the bone
/// was found free in, and the last it was found touching in, in this closing, are answered
/// without a query: closing asks again at the previous fraction before each contact
/// refinement, and at the bracket's touching end after it.
#[inline]
fn bone_touches(hand: &HandModel, object: &ObjectModel, b: usize, ws: &mut Workspace) -> bool {
    let world = ws.world[b];
    if ws.free_pose[b] == Some(world) {
        return false;
    }
    if ws.touching_pose[b] == Some(world) {
        return true;
    }
    let touches = hand.bone_capsules(b).iter().any(|c| {
        let capsule = Capsule {
            a: world * c.a,
            b: world * c.b,
            radius: c.radius,
        };
        object.capsule_touches(&capsule, &mut ws.counters)
    });
    if touches {
        ws.touching_pose[b] = Some(world);
    } else {
        ws.free_pose[b] = Some(world);
    }
    touches
}

/// Does any bone of `group` touch the object?
fn group_touches(
    hand: &HandModel,
    object: &ObjectModel,
    group: Range<usize>,
    ws: &mut Workspace,
) -> bool {
    group.into_iter().any(|k| bone_touches(hand, object, k, ws))
}

/// Bisects the chain `group` between a free fraction and a touching one (`bracket`) until no
/// capsule of the finger from the group down moves more than `tolerance` between the two, and
/// leaves it at the free end. Motions are rotations about joints, so capsule ends bound every
/// point; the finger below the group is carried along and must stay free too.
#[allow(clippy::too_many_arguments)]
fn refine_contact(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &GraspMovement,
    group: Range<usize>,
    finger_end: usize,
    bracket: [f64; 2],
    tolerance: f64,
    ws: &mut Workspace,
) {
    let [mut lo, mut hi] = bracket;
    // The bone found touching at `hi` last; the group's last bone (the one that stopped it)
    // to begin with.
    let mut blocking = group.end - 1;
    let first = hand.capsule_range(group.start).start;
    let last = hand.capsule_range(finger_end - 1).end;
    // The capsule ends at `lo` in `ws.capsules` and at `hi` in `ws.capsules_touching`: each
    // bisection poses the finger once, at its midpoint, and keeps the ends for the bracket's end
    // the midpoint replaces.
    set_group(hand, movement, group.clone(), lo, finger_end, ws);
    write_capsule_ends(hand, &ws.world, first..last, &mut ws.capsules);
    set_group(hand, movement, group.clone(), hi, finger_end, ws);
    write_capsule_ends(hand, &ws.world, first..last, &mut ws.capsules_touching);
    for _ in 0..MAX_REFINE_STEPS {
        let travel = (first..last)
            .map(|k| {
                let (free, touching) = (&ws.capsules[k], &ws.capsules_touching[k]);
                (touching.a - free.a)
                    .norm()
                    .max((touching.b - free.b).norm())
            })
            .fold(0.0, f64::max);
        if travel <= tolerance {
            break;
        }
        let mid = 0.5 * (lo + hi);
        if hi - lo <= f64::EPSILON {
            break;
        }
        set_group(hand, movement, group.clone(), mid, finger_end, ws);
        // The same answer in any order; the bone that touched at `hi` first, as it most often
        // touches at `mid` too and a touching bone ends the test.
        let order =
            std::iter::once(blocking).chain((group.start..finger_end).filter(|&k| k != blocking));
        match order
            .into_iter()
            .find(|&k| bone_touches(hand, object, k, ws))
        {
            Some(k) => {
                hi = mid;
                blocking = k;
                write_capsule_ends(hand, &ws.world, first..last, &mut ws.capsules_touching);
            }
            None => {
                lo = mid;
                write_capsule_ends(hand, &ws.world, first..last, &mut ws.capsules);
            }
        }
    }
    // The bones touching at the touching end are the contacts, within `tolerance` at `lo`.
    set_group(hand, movement, group.clone(), hi, finger_end, ws);
    for k in group.start..finger_end {
        if bone_touches(hand, object, k, ws) {
            ws.touching[k] = true;
        }
    }
    set_group(hand, movement, group, lo, finger_end, ws);
}

/// Writes every capsule's world position into `ws.capsules`.
pub fn update_world_capsules(hand: &HandModel, ws: &mut Workspace) {
    write_capsule_ends(hand, &ws.world, 0..hand.capsules().len(), &mut ws.capsules);
}

/// Writes the world positions of the hand's capsules `range`, bones posed at `world`, into the
/// same slots of `slots`.
fn write_capsule_ends(
    hand: &HandModel,
    world: &[Transform],
    range: Range<usize>,
    slots: &mut [Capsule],
) {
    for (slot, c) in slots[range.clone()].iter_mut().zip(&hand.capsules()[range]) {
        let w = world[c.bone];
        *slot = Capsule {
            a: w * c.a,
            b: w * c.b,
            radius: c.radius,
        };
    }
}
