//! One simulation step of a hand gripping an object (contacts active), at the paper's 0.2 ms and
//! at 1 ms: the human hand on the built-in sphere, and the Shadow hand (MJCF fixture) holding a
//! sphere against its palm. Steps per second = 1 / time per step; real-time factor = dt / time.
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

/// A simulation of `hand` gripping the sphere: the grasp scenario run to just after let-go.
fn gripping(hand: &HandModel, dt: f64) -> Simulation {
    let object = sphere();
    let grasp = plan_grasp(hand, &object).unwrap();
    let gravity = Settings::default().gravity;
    let mut controller = grasp.controller(hand, &gravity).unwrap();
    controller.alpha = 0.5;
    let times = GraspTimes::default();
    let mut sim = Simulation::new(Settings {
        dt,
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
            let mut sim = gripping(hand, dt);
            group.bench_function(format!("{name}_sphere_dt_{}ms", dt * 1e3), |b| {
                b.iter(|| black_box(&mut sim).step().unwrap())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, step);
criterion_main!(benches);
