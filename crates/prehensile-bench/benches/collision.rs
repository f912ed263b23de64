//! Capsule tests, exact vs fast, and one finger closing, on a closed mesh of 16,384 triangles.
//!
//! Run: `cargo bench -p prehensile-bench --bench collision`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use prehensile_core::finger_closing::{close_fingers, ClosingParams};
use prehensile_core::math::{Point3, Transform, Vec3};
use prehensile_core::random::SplitMix64;
use prehensile_core::search::translate_to_free::{hand_root, translate_to_free, TranslateMode};
use prehensile_core::{shapes, Capsule, CollisionCounters, ObjectModel, Workspace};

/// The benchmark mesh: a torus with 128 × 64 quads = 16,384 triangles, 11.8 cm across.
fn torus16k() -> ObjectModel {
    ObjectModel::new("torus16k", shapes::torus(0.045, 0.014, 128, 64), None).unwrap()
}

/// Finger-sized capsules (1–5 cm long, 6–15 mm radius) within 4 cm of the torus, seeded.
fn capsules(n: usize) -> Vec<Capsule> {
    let mut rng = SplitMix64::new(42);
    (0..n)
        .map(|_| {
            let u = rng.uniform(0.0, std::f64::consts::TAU);
            let v = rng.uniform(0.0, std::f64::consts::TAU);
            let r = 0.014 + rng.uniform(-0.02, 0.04);
            let centre = Point3::new(
                (0.045 + r * v.cos()) * u.cos(),
                (0.045 + r * v.cos()) * u.sin(),
                r * v.sin(),
            );
            let d = Vec3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            )
            .normalize();
            let half = rng.uniform(0.005, 0.025);
            Capsule {
                a: centre - d * half,
                b: centre + d * half,
                radius: rng.uniform(0.006, 0.015),
            }
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let object = torus16k();
    let queries = capsules(1000);
    let mut counters = CollisionCounters::default();
    for q in &queries {
        object.capsule_touches(q, &mut counters);
    }
    eprintln!(
        "torus16k: {} triangles; {} of {} near-surface queries fell back to the exact path",
        object.mesh().triangles.len(),
        counters.exact_fallbacks,
        counters.queries
    );
    let mut group = c.benchmark_group("capsule_query_16k_triangles");
    group.bench_function("exact_per_1000", |b| {
        b.iter(|| {
            let exact = object.collider().exact();
            queries
                .iter()
                .filter(|q| exact.capsule_touches(&q.a, &q.b, q.radius))
                .count()
        })
    });
    group.bench_function("fast_per_1000", |b| {
        let mut counters = CollisionCounters::default();
        b.iter(|| {
            queries
                .iter()
                .filter(|q| object.capsule_touches(q, &mut counters))
                .count()
        })
    });
    group.finish();

    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let movement = hand.movement("power").unwrap();
    let mut ws = Workspace::new(&hand);
    let hook = Transform::from_parts(
        Point3::new(0.045, 0.0, 0.0).coords.into(),
        nalgebra::UnitQuaternion::from_axis_angle(&Vec3::x_axis(), std::f64::consts::FRAC_PI_2),
    );
    let offset = translate_to_free(
        &hand,
        &object,
        movement,
        &hook,
        TranslateMode::default(),
        0.3,
        f64::INFINITY,
        &mut ws,
    )
    .unwrap();
    let root = hand_root(&hook, movement, offset);
    let params = ClosingParams::default();
    c.bench_function("finger_closing_human_power_16k_triangles", |b| {
        b.iter(|| close_fingers(&hand, &object, movement, black_box(&root), &params, &mut ws))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).measurement_time(std::time::Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
