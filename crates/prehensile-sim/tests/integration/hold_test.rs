//! The hold test: a searched power grasp holds its object against loads in several directions,
//! the same on one thread as on several; the same hand kept open beside the object holds it in
//! none; a search result round-trips into the simulation's grasp.

use prehensile_core::math::{Point3, Vec3};
use prehensile_core::search::{default_shoulder, GraspPlanner, GraspResult, SearchParams};
use prehensile_core::stability::LOAD_DIRECTIONS;
use prehensile_core::{shapes, ObjectModel, Workspace};
use prehensile_sim::scenarios::{hold_test, plan_grasp, PlannedGrasp, HOLD_ALPHA};
use prehensile_sim::Settings;

fn sphere() -> ObjectModel {
    ObjectModel::new("sphere", shapes::builtin_object("sphere").unwrap(), None).unwrap()
}

#[test]
fn a_searched_power_grasp_of_the_sphere_holds_in_most_directions() {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let object = sphere();
    let grasp = plan_grasp(&hand, &object).unwrap();
    let report = hold_test(&hand, &object, &grasp, Settings::default(), HOLD_ALPHA).unwrap();
    assert_eq!(report.directions.len(), 6);
    assert!(report.held >= 4, "{report:#?}");
    // Gravity along −z, the usual one, is among them.
    assert!(report.directions[5].held, "{report:#?}");
    for d in &report.directions {
        assert!(d.diverged.is_none());
        assert_eq!(d.held, d.moved_m < 0.02 && d.turned_degrees < 30.0);
    }
    // The six loads run side by side: on one thread the report is the same, in the same order.
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| hold_test(&hand, &object, &grasp, Settings::default(), HOLD_ALPHA))
        .unwrap();
    let labels: Vec<_> = one_thread.directions.iter().map(|d| d.direction).collect();
    assert_eq!(labels, LOAD_DIRECTIONS);
    assert_eq!(
        serde_json::to_value(&one_thread).unwrap(),
        serde_json::to_value(&report).unwrap()
    );
}

#[test]
fn an_open_hand_beside_the_object_holds_it_in_no_direction() {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let object = sphere();
    let mut grasp = plan_grasp(&hand, &object).unwrap();
    // Back the hand off 10 cm and keep it open: nothing holds the object.
    grasp.root.translation.vector -= grasp.approach * 0.10;
    grasp.closed = grasp.open.clone();
    let report = hold_test(&hand, &object, &grasp, Settings::default(), HOLD_ALPHA).unwrap();
    assert_eq!(report.held, 0, "{report:#?}");
}

#[test]
fn a_search_result_becomes_the_same_planned_grasp() {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let object = sphere();
    let hook = object.center_of_mass();
    let movement = hand.movement("power").unwrap();
    let shoulder = default_shoulder(&hand, &hook, &Vec3::z());
    let mut planner =
        GraspPlanner::new(&hand, &object, movement, shoulder, SearchParams::default()).unwrap();
    planner.run_to_end();
    let result = GraspResult::from_planner(&planner, &mut Workspace::new(&hand));
    let from_result = PlannedGrasp::from_result(&hand, &result).unwrap();
    let planned = plan_grasp(&hand, &object).unwrap();
    let root = |g: &PlannedGrasp| Point3::from(g.root.translation.vector);
    assert!((root(&from_result) - root(&planned)).norm() < 1e-9);
    assert!((from_result.approach - planned.approach).norm() < 1e-9);
    for (a, b) in from_result.closed.iter().zip(&planned.closed) {
        assert!((a - b).abs() < 1e-9);
    }
    // A bad grip strength is refused with the reason.
    let e = hold_test(&hand, &object, &planned, Settings::default(), 1.5).unwrap_err();
    assert!(e.to_string().contains("alpha"));
}
