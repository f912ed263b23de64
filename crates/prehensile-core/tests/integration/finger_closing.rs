//! Finger closing (§5.4, Alg. 1–2) with and without contact refinement.

use crate::common;

use prehensile_core::finger_closing::{close_fingers, close_fingers_while, ClosingParams};
use prehensile_core::hand::closing_facts::fingers_close_apart;
use prehensile_core::math::Transform;
use prehensile_core::{ObjectModel, Workspace};

/// Signed gap between a world capsule and the object surface (negative = penetrating).
fn gap(object: &ObjectModel, c: &prehensile_core::Capsule) -> f64 {
    let exact = object.collider().exact();
    let d = exact.segment_distance(&c.a, &c.b);
    if d == 0.0 || exact.signed_distance(&c.a) < 0.0 {
        -c.radius
    } else {
        d - c.radius
    }
}

#[test]
fn power_grasp_on_sphere_touches_without_penetrating() {
    let hand = common::hand("human");
    let object = common::object("sphere");
    let mut ws = Workspace::new(&hand);
    let root = common::free_root(&hand, &object, "power", &mut ws);
    let params = ClosingParams::default();
    let out = close_fingers(
        &hand,
        &object,
        hand.movement("power").unwrap(),
        &root,
        &params,
        &mut ws,
    );
    assert!(!out.started_in_collision);
    assert!(out.touching_bones >= 3, "{out:?}");
    for (k, c) in ws.capsules.iter().enumerate() {
        let g = gap(&object, c);
        assert!(g > -1e-9, "capsule {k} penetrates by {g}");
        let bone = hand.capsules()[k].bone;
        if ws.touching[bone] {
            assert!(g <= 0.0005 + 1e-9, "touching bone {bone} is {g} m away");
        }
    }
    // Fingers touching: at least three distinct fingers.
    let mut fingers: Vec<usize> = (0..hand.bones().len())
        .filter(|&b| ws.touching[b])
        .filter_map(|b| hand.bones()[b].finger)
        .collect();
    fingers.dedup();
    fingers.sort();
    fingers.dedup();
    assert!(fingers.len() >= 3, "fingers touching: {fingers:?}");
}

#[test]
fn thesis_mode_penetrates_by_up_to_a_step_and_refinement_removes_it() {
    let hand = common::hand("human");
    let object = common::object("cylinder");
    let mut ws = Workspace::new(&hand);
    let root = common::free_root(&hand, &object, "power", &mut ws);
    let movement = hand.movement("power").unwrap();
    let thesis = ClosingParams {
        interpolations: 10,
        contact_tolerance: None,
    };
    close_fingers(&hand, &object, movement, &root, &thesis, &mut ws);
    let worst_thesis = ws
        .capsules
        .iter()
        .map(|c| gap(&object, c))
        .fold(f64::INFINITY, f64::min);
    assert!(
        worst_thesis < 0.0,
        "with N = 10 the thesis's closing should penetrate"
    );
    let refined = ClosingParams {
        interpolations: 10,
        contact_tolerance: Some(0.0005),
    };
    close_fingers(&hand, &object, movement, &root, &refined, &mut ws);
    let worst = ws
        .capsules
        .iter()
        .map(|c| gap(&object, c))
        .fold(f64::INFINITY, f64::min);
    assert!(worst > -1e-9, "refined closing penetrates by {worst}");
}

#[test]
fn far_from_the_object_every_bone_reaches_the_end() {
    let hand = common::hand("robot3");
    let object = common::object("box");
    let mut ws = Workspace::new(&hand);
    let root = Transform::translation(1.0, 0.0, 0.0);
    let params = ClosingParams::default();
    let out = close_fingers(
        &hand,
        &object,
        hand.movement("close").unwrap(),
        &root,
        &params,
        &mut ws,
    );
    assert_eq!(out.touching_bones, 0);
    for b in 1..hand.bones().len() {
        assert_eq!(ws.reached[b], params.interpolations);
        assert_eq!(ws.fraction[b], 1.0);
    }
}

/// Finger closing remembers the poses it found free and touching, within one closing only. A
/// workspace that closed the hand on one sphere closes it at the same root on a slightly larger
/// (or smaller) one exactly as a fresh one does: bisections of the same interpolation steps
/// pose the bones at the same fractions, where the other sphere may answer otherwise.
#[test]
fn a_closing_forgets_the_poses_of_closings_before() {
    let hand = common::hand("human");
    let sphere = common::object("sphere");
    let movement = hand.movement("power").unwrap();
    let params = ClosingParams::default();
    let mut ws = Workspace::new(&hand);
    let root = common::free_root(&hand, &sphere, "power", &mut ws);
    let centre = sphere.center_of_mass();
    for growth in [1.0005, 1.001, 1.002, 1.004] {
        let mut mesh = prehensile_core::shapes::builtin_object("sphere").unwrap();
        for v in &mut mesh.vertices {
            *v = centre + (*v - centre) * growth;
        }
        let larger = ObjectModel::new("larger sphere", mesh, None).unwrap();
        for (before, after) in [(&sphere, &larger), (&larger, &sphere)] {
            let mut fresh = Workspace::new(&hand);
            let expected = close_fingers(&hand, after, movement, &root, &params, &mut fresh);
            let mut reused = Workspace::new(&hand);
            close_fingers(&hand, before, movement, &root, &params, &mut reused);
            let again = close_fingers(&hand, after, movement, &root, &params, &mut reused);
            let case = format!(
                "grown by {growth}, {} after {}",
                after.name(),
                before.name()
            );
            assert_eq!(again, expected, "{case}");
            assert_eq!(reused.fraction, fresh.fraction, "{case}");
            assert_eq!(reused.touching, fresh.touching, "{case}");
        }
    }
}

#[test]
fn a_touching_bone_stops_its_predecessors() {
    for hand_name in ["human", "robot3", "cartoon4"] {
        let hand = common::hand(hand_name);
        for object_name in ["sphere", "box", "mug"] {
            let object = common::object(object_name);
            let mut ws = Workspace::new(&hand);
            let root = common::free_root(&hand, &object, "close", &mut ws);
            close_fingers(
                &hand,
                &object,
                hand.movement("close").unwrap(),
                &root,
                &ClosingParams::default(),
                &mut ws,
            );
            for b in 1..hand.bones().len() {
                if !ws.touching[b] {
                    continue;
                }
                let mut at = hand.chain_predecessor(b);
                while let Some(p) = at {
                    assert!(
                        ws.reached[p] <= ws.reached[b],
                        "{hand_name}/{object_name}: predecessor {} moved on after {} touched",
                        hand.bones()[p].name,
                        hand.bones()[b].name
                    );
                    at = hand.chain_predecessor(p);
                }
            }
        }
    }
}

#[test]
fn closing_is_deterministic() {
    let hand = common::hand("human");
    let object = common::object("torus");
    let mut ws = Workspace::new(&hand);
    let root = common::free_root(&hand, &object, "power", &mut ws);
    let m = hand.movement("power").unwrap();
    close_fingers(&hand, &object, m, &root, &ClosingParams::default(), &mut ws);
    let first = ws.capsules.clone();
    close_fingers(&hand, &object, m, &root, &ClosingParams::default(), &mut ws);
    assert_eq!(first, ws.capsules);
}

#[test]
fn the_fingers_of_every_built_in_hand_and_the_shadow_hand_close_one_after_another() {
    // What lets a search's step stop a candidate once its fingers closed so far rule it out
    // (`EvaluationContext::evaluate_pose_to_beat`): each finger hangs from the palm and no
    // rigid coupling crosses fingers, so they may close one after another.
    let shadow = prehensile_formats::load_hand_mjcf(&common::repo_path(
        "assets/hands/shadow_hand/reach.xml",
    ))
    .unwrap();
    let hands = prehensile_formats::BUILTIN_HANDS
        .iter()
        .map(|name| common::hand(name))
        .chain([shadow]);
    for hand in hands {
        assert!(fingers_close_apart(&hand), "{}", hand.name());
        // Asked after each finger, in order; told to stop after the second, it stops there.
        let object = common::object("sphere");
        let mut ws = Workspace::new(&hand);
        let name = if hand.movement("power").is_some() {
            "power"
        } else {
            "close"
        };
        let root = common::free_root(&hand, &object, name, &mut ws);
        let movement = hand.movement(name).unwrap();
        let params = ClosingParams::default();
        let mut asked = Vec::new();
        let mut go_on = |f: usize, _: &Workspace| {
            asked.push(f);
            f < 1
        };
        let stopped = close_fingers_while(
            &hand, &object, movement, &root, &params, &mut ws, &mut go_on,
        );
        assert_eq!(stopped, None, "{}", hand.name());
        assert_eq!(asked, [0, 1], "{}", hand.name());
        // Never told to stop, it closes as `close_fingers` does.
        let mut every = Vec::new();
        let whole = close_fingers_while(
            &hand,
            &object,
            movement,
            &root,
            &params,
            &mut ws,
            &mut |f, _| {
                every.push(f);
                true
            },
        );
        let reached = ws.reached.clone();
        let alone = close_fingers(&hand, &object, movement, &root, &params, &mut ws);
        assert_eq!(whole, Some(alone), "{}", hand.name());
        assert_eq!(reached, ws.reached, "{}", hand.name());
        assert_eq!(every, (0..hand.fingers().len()).collect::<Vec<_>>());
    }
}
