//! Runs whole grasps for profiling (e.g. under `valgrind --tool=callgrind`).
use prehensile_core::math::Point3;
use prehensile_core::search::{GraspPlanner, SearchParams};
use prehensile_core::{shapes, ObjectModel};
fn main() {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let object =
        ObjectModel::new("sphere", shapes::builtin_object("sphere").unwrap(), None).unwrap();
    let m = hand.movement("power").unwrap();
    for seed in 1..=3 {
        let mut p = GraspPlanner::new(
            &hand,
            &object,
            m,
            Point3::new(-0.35, -0.2, 0.35),
            SearchParams {
                seed,
                ..Default::default()
            },
        )
        .unwrap();
        p.run_to_end();
        eprintln!("seed {seed}: {:?}", p.stats());
    }
}
