//! BVH written from a motion reads back as the same joint angles.

use prehensile_core::animation::approach_and_close;
use prehensile_core::math::Transform;
use prehensile_formats::{builtin_hand, parse_bvh, write_bvh};
use proptest::prelude::*;

#[test]
fn exported_motion_reads_back_as_the_same_joint_angles() {
    for name in ["human", "robot3", "cartoon4"] {
        let hand = builtin_hand(name).unwrap();
        let movement = hand.movement("close").unwrap();
        let fractions = vec![0.7; hand.bones().len()];
        let frames = approach_and_close(
            &hand,
            movement,
            &Transform::identity(),
            0.02,
            &fractions,
            0.1,
            6,
        );
        let text = write_bvh(&hand, &frames, 30.0);
        let motion = parse_bvh(&text, "m.bvh").unwrap();
        assert_eq!(motion.frames.len(), frames.len());
        let angles = motion.joint_angles(&hand, "m.bvh").unwrap();
        for (frame, read) in frames.iter().zip(&angles) {
            let mut expected = vec![0.0; hand.dof_count()];
            for (b, bone) in hand.bones().iter().enumerate() {
                let n = bone.joint.dofs();
                bone.joint.angles(
                    &frame.rotations[b],
                    &mut expected[bone.first_dof..bone.first_dof + n],
                );
            }
            hand.constrain(&mut expected);
            for (e, r) in expected.iter().zip(read) {
                assert!((e - r).abs() < 1e-6, "{name}: {e} vs {r}");
            }
        }
    }
}

#[test]
fn bad_bvh_is_named() {
    let hand = builtin_hand("robot3").unwrap();
    let frames = approach_and_close(
        &hand,
        hand.movement("close").unwrap(),
        &Transform::identity(),
        0.0,
        &[0.5; 7],
        0.1,
        2,
    );
    let text = write_bvh(&hand, &frames, 30.0);
    let e = parse_bvh(&text.replace("Frames: 5", "Frames: 9"), "m.bvh").unwrap_err();
    assert!(e.reason.contains("promises 9"), "{e}");
    let e = parse_bvh(&text.replace("CHANNELS 3", "CHANNELS 4"), "m.bvh").unwrap_err();
    assert!(e.location.is_some() && e.reason.contains("lists 3"), "{e}");
    // Fewer frames promised than given: the extra lines used to be dropped silently.
    let e = parse_bvh(&text.replace("Frames: 5", "Frames: 2"), "m.bvh").unwrap_err();
    assert!(e.reason.contains("more frame lines follow"), "{e}");
    // An unknown channel used to be ignored.
    let e = parse_bvh(&text.replacen("Zrotation", "Wrotation", 1), "m.bvh").unwrap_err();
    assert!(e.reason.contains("unknown channel 'Wrotation'"), "{e}");
    let e = parse_bvh(&text.replace("Frames: 5", "Frames: 99999999999"), "m.bvh").unwrap_err();
    assert!(e.reason.contains("more than"), "{e}");
    let other = builtin_hand("human").unwrap();
    let motion = parse_bvh(&text, "m.bvh").unwrap();
    assert!(motion
        .joint_angles(&other, "m.bvh")
        .unwrap_err()
        .reason
        .contains("no joint of that name"));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn mutated_bvh_never_panics(edits in proptest::collection::vec((any::<usize>(), prop::sample::select(b"0123456789.-{} \\nJOINTEndSite".to_vec())), 1..6)) {
        let hand = builtin_hand("robot3").unwrap();
        let frames = approach_and_close(&hand, hand.movement("close").unwrap(), &Transform::identity(), 0.0, &[0.5; 7], 0.1, 2);
        let mut bytes = write_bvh(&hand, &frames, 30.0).into_bytes();
        for (at, v) in edits {
            let i = at % bytes.len();
            bytes[i] = v;
        }
        if let Ok(m) = parse_bvh(&String::from_utf8_lossy(&bytes), "m.bvh") {
            let _ = m.joint_angles(&hand, "m.bvh");
        }
    }
}
