//! Facts of a hand's fingers that finger closing and the search ask for on every evaluation.
//! They depend on the hand alone, so [`HandModel`] works them out once when it
//! is built and keeps them ([`HandModel::fingers_close_apart`](super::HandModel::fingers_close_apart),
//! [`HandModel::finger_floor_radius`](super::HandModel::finger_floor_radius)).

use crate::hand::{Finger, HandModel};

/// Can the fingers close one after another, each through every interpolation, instead of all
/// of them step by step (Alg. 1), with the same outcome? Yes when every bone but the root
/// belongs to a finger (its bones in index order, parents first) and hangs from the root or
/// from its own finger, and every rigid coupling stays within a finger: a bone's poses then
/// depend on its own finger's alone, and the order the fingers are taken in changes nothing.
pub fn fingers_close_apart(hand: &HandModel) -> bool {
    let bones = hand.bones();
    let finger_of = |b: usize| bones[b].finger;
    let hang_from_their_finger = bones.iter().skip(1).all(|bone| {
        bone.finger.is_some()
            && bone
                .parent
                .is_some_and(|p| p == 0 || finger_of(p) == bone.finger)
    });
    let fingers_in_order = hand.fingers().iter().enumerate().all(|(f, finger)| {
        finger.bones.windows(2).all(|w| w[0] < w[1])
            && finger.bones.iter().all(|&b| finger_of(b) == Some(f))
    });
    let couplings_within =
        hand.couplings().iter().filter(|c| c.rigid).all(|c| {
            finger_of(hand.bone_of_dof(c.leader)) == finger_of(hand.bone_of_dof(c.follower))
        });
    hang_from_their_finger && fingers_in_order && couplings_within
}

/// Is bone `leader` an ancestor of bone `follower` along one chain, so that
/// finger closing's `stop_coupled_followers` finds their contact together?
pub(crate) fn leads_its_chain(hand: &HandModel, leader: usize, follower: usize) -> bool {
    leader < follower && (leader + 1..=follower).all(|k| hand.chain_predecessor(k) == Some(k - 1))
}

/// Does finger closing check every pose it leaves `finger` in for contact? Not when a bone of
/// the finger follows a rigid coupling's leader outside its chain: when the leader stops,
/// closing moves such a bone to the leader's fraction without asking whether it touches.
pub fn closes_checked(hand: &HandModel, finger: &Finger) -> bool {
    hand.couplings().iter().filter(|c| c.rigid).all(|c| {
        let (leader, follower) = (hand.bone_of_dof(c.leader), hand.bone_of_dof(c.follower));
        !finger.bones.contains(&follower) || leads_its_chain(hand, leader, follower)
    })
}

/// The radius finger `finger` adds to a hook's depth in the search's `finger_fdist_floor`: its thinnest
/// capsule's, or `None` when the finger adds nothing (its last bone has no capsules, or finger
/// closing may leave it unchecked). Depends on the hand alone; [`HandModel::finger_floor_radius`]
/// keeps it from when the hand was built.
pub fn finger_floor_radius(hand: &HandModel, finger: usize) -> Option<f64> {
    let finger = &hand.fingers()[finger];
    let has_capsules = |b: usize| !hand.bone_capsules(b).is_empty();
    let last = *finger.bones.last().expect("fingers have bones");
    let unchecked_follower = hand
        .couplings()
        .iter()
        .filter(|c| c.rigid)
        .map(|c| hand.bone_of_dof(c.follower))
        .any(|b| finger.bones.contains(&b) && !has_capsules(b));
    if !has_capsules(last) || unchecked_follower || !closes_checked(hand, finger) {
        return None;
    }
    let thinnest = finger
        .bones
        .iter()
        .flat_map(|&b| hand.bone_capsules(b))
        .map(|c| c.radius)
        .fold(f64::INFINITY, f64::min);
    Some(thinnest)
}
