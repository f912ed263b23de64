//! One simulation step of a hand gripping an object (contacts active), at the paper's 0.2 ms and
//! at 1 ms, each with the default substeps for its step: the human hand and the Shadow hand
//! (MJCF fixture) on the built-in sphere, gravity pressing the sphere into the palm; and the
//! human hand at 0.2 ms with 1, 2 and 4 substeps (3 sweeps each). Steps per second = 1 / time per step;
//! real-time factor = dt / time.
//!
//! Run: `cargo bench -p prehensile-sim --bench simulation`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use prehensile_core::{shapes, HandModel, ObjectModel};
use prehensile_sim::scenarios::held_still;
use prehensile_sim::{Settings, Simulation};

fn sphere() -> ObjectModel {
    ObjectModel::new("sphere", shapes::builtin_object("sphere").unwrap(), None).unwrap()
}

/// `hand` holding the sphere still (human: 12–14 capsules touching it, Shadow: 4).
fn gripping(hand: &HandModel, dt: f64, substeps: usize) -> Simulation {
    held_still(hand, &sphere(), dt, substeps).unwrap()
}

fn step(c: &mut Criterion) {
    let shadow_file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/hands/shadow_hand/reach.xml"
    );
    let hands = [
        ("human", prehensile_formats::builtin_hand("human").unwrap()),
        (
            "shadow",
            prehensile_formats::load_hand(std::path::Path::new(shadow_file)).unwrap(),
        ),
    ];
    let mut group = c.benchmark_group("simulation_step");
    for (name, hand) in &hands {
        for dt in [0.0002, 0.001] {
            let mut sim = gripping(hand, dt, Settings::iterations_for(dt));
            group.bench_function(format!("{name}_sphere_dt_{}ms", dt * 1e3), |b| {
                b.iter(|| black_box(&mut sim).step().unwrap())
            });
        }
    }
    group.finish();
}

/// The cost of solver substeps at the paper's 0.2 ms (the default is 1; see
/// `Settings::iterations_for`).
fn substeps(c: &mut Criterion) {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let mut group = c.benchmark_group("substeps_at_0.2ms");
    for substeps in [1, 2, 4] {
        let mut sim = gripping(&hand, 0.0002, substeps);
        group.bench_function(format!("human_sphere_{substeps}_substeps"), |b| {
            b.iter(|| black_box(&mut sim).step().unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, step, substeps);
criterion_main!(benches);
