//! One simulation step of a hand gripping an object (contacts active), at the paper's 0.2 ms and
//! at 1 ms, each with the default solver for its step (`Settings::for_step`): the human hand and
//! the Shadow hand (MJCF fixture) on the built-in sphere, gravity pressing the sphere into the
//! palm; and the human hand at 1 ms with the solver settings the default was chosen from
//! (substeps × sweeps). Steps per second = 1 / time per step; real-time factor = dt / time.
//!
//! Run: `cargo bench -p prehensile-bench --bench simulation`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use prehensile_core::{shapes, HandModel, ObjectModel};
use prehensile_sim::scenarios::held_still;
use prehensile_sim::{Settings, Simulation};

fn sphere() -> ObjectModel {
    ObjectModel::new("sphere", shapes::builtin_object("sphere").unwrap(), None).unwrap()
}

/// `hand` holding the sphere still (human: 12–14 capsules touching it, Shadow: 4).
fn gripping(hand: &HandModel, settings: Settings) -> Simulation {
    held_still(hand, &sphere(), settings).unwrap()
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
            let mut sim = gripping(hand, Settings::for_step(dt));
            group.bench_function(format!("{name}_sphere_dt_{}ms", dt * 1e3), |b| {
                b.iter(|| black_box(&mut sim).step().unwrap())
            });
        }
    }
    group.finish();
}

/// The solver settings at 1 ms that keep every scenario's outcome: two substeps of 3 sweeps (the
/// earlier default) and one substep of 7 or 8 sweeps (8 is the default; see
/// `Settings::inner_iterations_for`).
fn solver_at_1ms(c: &mut Criterion) {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let mut group = c.benchmark_group("solver_at_1ms");
    for (substeps, sweeps) in [(2, 3), (1, 7), (1, 8)] {
        let mut sim = gripping(
            &hand,
            Settings {
                solver_iterations: substeps,
                inner_iterations: sweeps,
                ..Settings::for_step(0.001)
            },
        );
        group.bench_function(format!("human_sphere_{substeps}x{sweeps}"), |b| {
            b.iter(|| black_box(&mut sim).step().unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, step, solver_at_1ms);
criterion_main!(benches);
