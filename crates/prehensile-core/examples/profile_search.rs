//! Runs whole grasps for profiling (e.g. under `valgrind --tool=callgrind`): the human hand's
//! power grasp, seeds 1–3, of the built-in object named by the first argument (default sphere).
use prehensile_core::math::Point3;
use prehensile_core::search::{GraspPlanner, SearchParams};
use prehensile_core::{shapes, ObjectModel};
fn main() {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let name = std::env::args().nth(1).unwrap_or_else(|| "sphere".into());
    let mesh = shapes::builtin_object(&name)
        .expect("a built-in object: sphere, box, cylinder, torus, mug");
    let object = ObjectModel::new(&name, mesh, None).unwrap();
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
