//! The pose search end to end: what a grasp must be (issue: no capsule enters the object by more
//! than 1 mm; power touches with ≥ 3 fingers, precision with thumb and index; palm faces the hook).

mod common;

use prehensile_core::math::{Point3, Vec3};
use prehensile_core::search::{GraspPlanner, SearchParams};
use prehensile_core::shapes::BUILTIN_OBJECTS;
use prehensile_core::{ObjectModel, Workspace};

#[test]
fn tmp_smoke() {
    let hand = common::hand("human");
    for name in BUILTIN_OBJECTS {
        let object = common::object(name);
        for movement in ["power", "precision"] {
            let m = hand.movement(movement).unwrap();
            let shoulder = object.center_of_mass() + Vec3::new(-0.35, -0.1, 0.35);
            let t = std::time::Instant::now();
            let mut planner =
                GraspPlanner::new(&hand, &object, m, shoulder, SearchParams::default()).unwrap();
            let status = planner.run_to_end();
            let st = planner.stats();
            eprintln!(
                "{name:9} {movement:9} {status:?} best {:?} current q {:.4} valid {:?} fingers {} steps {} evals {} queries {} fallbacks {} time {:?}",
                planner.best().map(|b| (b.quality, b.fingers_touching)),
                planner.current().quality,
                planner.current().validity,
                planner.current().fingers_touching,
                st.steps, st.evaluations, st.collision_queries, st.exact_fallbacks, t.elapsed()
            );
        }
    }
    let _ = (Point3::origin(), Workspace::new(&hand), None::<ObjectModel>);
    panic!();
}
