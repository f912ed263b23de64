//! One step of the §6.6 table's row a at a time, for profiling: a seven-pose step, about 7
//! TranslateToFree placements per pose (4.5 mm steps), N = 10 interpolations, the human hand's
//! power grasp of the 16k-triangle torus, as `benches/search.rs` times it. Each of the rounds
//! (first argument, default 200) makes a planner from a new seed and finishes its start outside
//! the timed part, then takes one step; prints the mean step. Under callgrind, count the steps
//! alone with `--toggle-collect='*GraspPlanner::step*'`.
use prehensile_core::finger_closing::ClosingParams;
use prehensile_core::math::Point3;
use prehensile_core::search::{GraspPlanner, SearchParams, StepKind, TranslateMode};
use prehensile_core::{shapes, ObjectModel};

fn main() {
    let hand = prehensile_formats::builtin_hand("human").expect("the built-in human hand");
    let mesh = shapes::torus(0.045, 0.014, 128, 64);
    let object = ObjectModel::new("torus16k", mesh, None).expect("the torus sets up");
    let movement = hand.movement("power").expect("a power movement");
    let rounds: u64 = std::env::args()
        .nth(1)
        .map_or(200, |r| r.parse().expect("a number of rounds"));
    let mut stepping = std::time::Duration::ZERO;
    for seed in 1..=rounds {
        let params = SearchParams {
            step: StepKind::SevenPose,
            seed,
            translate: TranslateMode::Steps { step: 0.0045 },
            closing: ClosingParams {
                interpolations: 10,
                ..Default::default()
            },
            ..Default::default()
        };
        let shoulder = Point3::new(-0.35, -0.2, 0.35);
        let mut planner =
            GraspPlanner::new(&hand, &object, movement, shoulder, params).expect("a planner");
        while planner.restarting() {
            planner.slice();
        }
        let began = std::time::Instant::now();
        planner.step();
        stepping += began.elapsed();
    }
    eprintln!(
        "mean step over {rounds} steps: {:.1} µs",
        stepping.as_secs_f64() * 1e6 / rounds as f64
    );
}
