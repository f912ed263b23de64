//! Skinned glTF hands (the WebXR generic hand, left and right) mapped onto the human hand.

use std::path::PathBuf;

use prehensile_core::math::Point3;
use prehensile_core::search::{GraspPlanner, GraspResult, SearchParams};
use prehensile_core::shapes::builtin_object;
use prehensile_core::{ObjectModel, Workspace};
use prehensile_formats::load_hand;

fn webxr(side: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../../assets/hands/webxr_generic_hand/{side}.glb"))
}

#[test]
fn both_webxr_hands_import_with_human_joints_and_movements() {
    for side in ["left", "right"] {
        let hand = load_hand(&webxr(side)).unwrap();
        // 25 joints less 5 tips.
        assert_eq!(hand.bones().len(), 20, "{side}");
        assert_eq!(hand.capsules().len(), 24, "{side}");
        let mut fingers: Vec<&str> = hand.fingers().iter().map(|f| f.name.as_str()).collect();
        fingers.sort();
        assert_eq!(
            fingers,
            ["index", "little", "middle", "ring", "thumb"],
            "{side}"
        );
        assert!(hand.movement("power").is_some() && hand.movement("precision").is_some());
        assert!(
            hand.dof_names()
                .iter()
                .any(|d| d == "index-finger-phalanx-proximal.flexion"),
            "{:?}",
            hand.dof_names()
        );
        assert_eq!(hand.couplings().len(), 4);
        // Radii measured from the skinned mesh: finger bones between 4 and 20 mm.
        for c in &hand.capsules()[5..] {
            assert!((0.004..0.02).contains(&c.radius), "{side}: {}", c.radius);
        }
    }
}

#[test]
fn the_left_and_right_webxr_hands_grasp_with_power_and_precision() {
    let object = ObjectModel::new("cylinder", builtin_object("cylinder").unwrap(), None).unwrap();
    for side in ["left", "right"] {
        let hand = load_hand(&webxr(side)).unwrap();
        for movement in ["power", "precision"] {
            let m = hand.movement(movement).unwrap();
            let mut planner = GraspPlanner::new(
                &hand,
                &object,
                m,
                Point3::new(-0.35, -0.2, 0.35),
                SearchParams::default(),
            )
            .unwrap();
            planner.run_to_end();
            let r = GraspResult::from_planner(&planner, &mut Workspace::new(&hand));
            assert!(r.valid, "{side} {movement}: {:?}", r.invalid_reason);
        }
    }
}
