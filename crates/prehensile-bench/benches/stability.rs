//! The grasp wrench space's hull (force closure, ε, load ratios) on the 89 contact sets of the
//! scipy oracle (`tests/data/stability_oracle.json`, 2–17 contacts each), computed once per
//! search result, and ε alone (how `auto` compares its movements' grasps).
//!
//! Run: `cargo bench -p prehensile-bench --bench stability`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use prehensile_core::stability::GraspWrenchSpace;

// The bench reads only the inputs; the answers are the test's.
#[allow(dead_code)]
#[path = "../../prehensile-core/tests/common/stability_cases.rs"]
mod stability_cases;

fn bench(c: &mut Criterion) {
    let cases = stability_cases::oracle_cases();
    let mut gws = GraspWrenchSpace::new();
    c.bench_function("wrench_space/89_oracle_cases", |b| {
        b.iter(|| {
            for case in &cases {
                black_box(gws.evaluate(&case.contacts, &case.model, &case.center, case.scale));
            }
        })
    });
    c.bench_function("wrench_space/89_oracle_cases_epsilon_alone", |b| {
        b.iter(|| {
            for case in &cases {
                black_box(gws.epsilon(&case.contacts, &case.model, &case.center, case.scale));
            }
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
