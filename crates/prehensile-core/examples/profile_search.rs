//! Runs whole grasps for profiling (e.g. under `valgrind --tool=callgrind`): the human hand's
//! power grasp, seeds 1–3, from the default shoulder, of the built-in object or mesh file named
//! by the first argument (default sphere). The seeds share one object, so the first search fills
//! the distance grid's nodes it needs and the later ones reuse them. A second argument runs the
//! three seeds that many rounds (default 1), so that a profile of the later rounds sees the
//! search on a warm grid, as a batch or a game that keeps its object does. A third argument names
//! another hand (built-in or a hand file) whose `power` movement is searched instead. The
//! environment variable `THREADS` sets the search's threads (default 1).
use prehensile_core::math::Vec3;
use prehensile_core::search::{default_shoulder, GraspPlanner, SearchParams};
use prehensile_core::{shapes, ObjectModel};
fn main() {
    let hand = prehensile_formats::sources::hand_from_spec(
        &std::env::args().nth(3).unwrap_or_else(|| "human".into()),
    )
    .expect("a built-in hand or a hand file");
    let name = std::env::args().nth(1).unwrap_or_else(|| "sphere".into());
    let object = match shapes::builtin_object(&name) {
        Some(mesh) => ObjectModel::new(&name, mesh, None).unwrap(),
        None => prehensile_formats::load_object(std::path::Path::new(&name), 1.0)
            .expect("a built-in object (sphere, box, cylinder, torus, mug) or a mesh file"),
    };
    let m = hand.movement("power").unwrap();
    let shoulder = default_shoulder(&hand, &object.center_of_mass(), &Vec3::z());
    let rounds: usize = std::env::args()
        .nth(2)
        .map_or(1, |r| r.parse().expect("a number of rounds"));
    for seed in (0..rounds).flat_map(|_| 1..=3) {
        let mut p = GraspPlanner::new(
            &hand,
            &object,
            m,
            shoulder,
            SearchParams {
                seed,
                threads: std::env::var("THREADS")
                    .map_or(1, |t| t.parse().expect("a number of threads")),
                ..Default::default()
            },
        )
        .unwrap();
        p.run_to_end();
        eprintln!("seed {seed}: {:?}", p.stats());
    }
    if let Some(grid) = object.collider().grid() {
        eprintln!(
            "distance grid: {} of {} nodes filled",
            grid.filled_nodes(),
            grid.node_count()
        );
    }
}
