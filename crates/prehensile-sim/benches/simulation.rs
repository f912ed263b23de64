//! One simulation step of a hand gripping an object (contacts active), at the paper's 0.2 ms and
//! at 1 ms, each with the default substeps for its step: the human hand and the Shadow hand
//! (MJCF fixture) on the built-in sphere, gravity pressing the sphere into the palm; and the
//! human hand at 0.2 ms with 1, 2 and 4 substeps. Steps per second = 1 / time per step;
//! real-time factor = dt / time.
//!
//! Run: `cargo bench -p prehensile-sim --bench simulation`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use prehensile_core::math::Transform;
use prehensile_core::{shapes, HandModel, ObjectModel};
use prehensile_sim::scenarios::{grasp_arm, plan_grasp, GraspTimes};
use prehensile_sim::{DistanceTo, HandSetup, Settings, Simulation};

fn sphere() -> ObjectModel {
    ObjectModel::new("sphere", shapes::builtin_object("sphere").unwrap(), None).unwrap()
}

/// A simulation of `hand` gripping the sphere with `substeps` solver iterations per step of
/// `dt`: the grasp scenario run to just after let-go, the arm then held still. With gravity
/// into the palm the sphere stays in the hand (human: 12–14 capsules touching it, Shadow: 4).
fn gripping(hand: &HandModel, dt: f64, substeps: usize) -> Simulation {
    let object = sphere();
    let grasp = plan_grasp(hand, &object).unwrap();
    // Gravity presses the object into the palm (against the approach), as in the MuJoCo scene
    // of tools/benchmark/mujoco_side_by_side.py.
    let gravity = -9.81 * grasp.approach.normalize();
    let mut controller = grasp.controller(hand, &gravity).unwrap();
    controller.alpha = 0.5;
    // Held in place after the grip: the lift never comes, so the scene stays the same however
    // many steps criterion takes.
    let times = GraspTimes {
        lift: 1e6,
        lifted: 1e6 + 1.0,
        release: 1e6 + 2.0,
        end: 1e6 + 3.0,
        ..GraspTimes::default()
    };
    let mut sim = Simulation::new(Settings {
        dt,
        solver_iterations: substeps,
        gravity,
        ..Settings::default()
    })
    .unwrap();
    sim.add_object(&object, &Transform::identity(), true)
        .unwrap();
    sim.add_hand(HandSetup {
        hand: hand.clone(),
        start: controller.setpoints.neutral.clone(),
        controller,
        arm: grasp_arm(&grasp, &Transform::identity(), &times),
        distance: DistanceTo::GraspPlace(grasp.place()),
        release_at: None,
        compensate_gravity: true,
        compensate_arm: true,
        manual: Vec::new(),
    })
    .unwrap();
    while sim.time() < times.let_go + 0.05 {
        if sim.time() >= times.let_go {
            sim.let_go_object();
        }
        sim.step().unwrap();
    }
    sim
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

/// The cost of solver substeps at the paper's 0.2 ms (the default is 2; see
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
