//! Grasps per second with object setup amortized: the human and Shadow hands (`auto`: every
//! movement, the best kept) on the five built-in objects and five closed robosuite scans, seed 1,
//! on one core and on every core (rayon). Setup is done once, outside the timed loop, as the
//! batch does per object. Criterion's throughput line is grasps per second.

use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use prehensile_core::search::{default_shoulder, find_grasp, GraspRequest, SearchParams};
use prehensile_core::{HandModel, ObjectModel};
use prehensile_formats::sources::{hand_from_spec, object_from_spec};
use rayon::prelude::*;

fn assets(path: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets")
        .join(path)
        .display()
        .to_string()
}

fn grasp(hand: &HandModel, object: &ObjectModel) -> bool {
    let params = SearchParams::default();
    let request = GraspRequest {
        movement: "auto".into(),
        shoulder: default_shoulder(hand, &object.hooks()[0], &params.up),
        params,
        budget: None,
    };
    find_grasp(hand, object, &request, &mut ()).is_ok_and(|r| r.valid)
}

fn throughput(c: &mut Criterion) {
    let hands: Vec<HandModel> = ["human".to_string(), assets("hands/shadow_hand/reach.xml")]
        .iter()
        .map(|h| hand_from_spec(h).unwrap())
        .collect();
    let mut specs: Vec<String> = prehensile_core::shapes::BUILTIN_OBJECTS
        .iter()
        .map(|s| s.to_string())
        .collect();
    for scan in [
        "lemon.stl",
        "milk.stl",
        "bread.stl",
        "cereal.stl",
        "can.obj",
    ] {
        specs.push(assets(&format!("objects/robosuite_{scan}")));
    }
    let objects: Vec<ObjectModel> = specs
        .iter()
        .map(|s| object_from_spec(s, 1.0, None).unwrap().0)
        .collect();
    let pairs: Vec<(&HandModel, &ObjectModel)> = hands
        .iter()
        .flat_map(|h| objects.iter().map(move |o| (h, o)))
        .collect();
    let mut group = c.benchmark_group("grasps");
    group.sample_size(10);
    group.throughput(Throughput::Elements(pairs.len() as u64));
    group.bench_function("one core", |b| {
        b.iter(|| pairs.iter().filter(|(h, o)| grasp(h, o)).count())
    });
    group.bench_function(format!("{} cores", rayon::current_num_threads()), |b| {
        b.iter(|| pairs.par_iter().filter(|(h, o)| grasp(h, o)).count())
    });
    group.finish();
}

criterion_group!(benches, throughput);
criterion_main!(benches);
