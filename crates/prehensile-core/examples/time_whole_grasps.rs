//! Times whole power grasps of the built-in human hand, one thread, from the default shoulder:
//! `time_whole_grasps [OBJECT [ROUNDS]]`, OBJECT a built-in object or `torus16k` (the benchmark's
//! 16,384-triangle torus; default sphere), seeds 1–6 each round (default 3 rounds). Each search
//! is timed from making its planner to its end, twice: on an object set up anew for it (its
//! distance grid filled as the search reads it, as a user's first grasp of an object) and on one
//! object kept across all searches (as a game or a batch that grasps one object many times).
//! The object's setup is not timed. Prints both medians and each seed's steps.
use prehensile_core::math::Vec3;
use prehensile_core::search::{default_shoulder, GraspPlanner, SearchParams};
use prehensile_core::{shapes, ObjectModel};
use std::time::Instant;

fn main() {
    let name = std::env::args().nth(1).unwrap_or_else(|| "sphere".into());
    let rounds: usize = std::env::args()
        .nth(2)
        .map_or(3, |r| r.parse().expect("a number of rounds"));
    let mesh = if name == "torus16k" {
        shapes::torus(0.045, 0.014, 128, 64)
    } else {
        shapes::builtin_object(&name).expect("a built-in object or torus16k")
    };
    let hand = prehensile_formats::builtin_hand("human").expect("the built-in human hand");
    let movement = hand.movement("power").expect("a power movement");
    let kept = ObjectModel::new(&name, mesh.clone(), None).expect("the object sets up");
    let search = |object: &ObjectModel, seed: u64| {
        let shoulder = default_shoulder(&hand, &object.center_of_mass(), &Vec3::z());
        let began = Instant::now();
        let params = SearchParams {
            seed,
            ..Default::default()
        };
        let mut planner = GraspPlanner::new(&hand, object, movement, shoulder, params)
            .expect("a planner for the built-in hand");
        planner.run_to_end();
        (began.elapsed().as_secs_f64() * 1e3, planner.stats().steps)
    };
    let (mut anew, mut on_kept, mut steps) = (Vec::new(), Vec::new(), Vec::new());
    for round in 0..rounds {
        for seed in 1..=6 {
            let fresh = ObjectModel::new(&name, mesh.clone(), None).expect("the object sets up");
            let (ms, taken) = search(&fresh, seed);
            anew.push(ms);
            if round == 0 {
                steps.push(taken);
            }
            on_kept.push(search(&kept, seed).0);
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    println!(
        "{name}: median {:.1} ms on a new object, {:.1} ms on one kept; steps of seeds 1-6: {steps:?}",
        median(&mut anew),
        median(&mut on_kept)
    );
}
