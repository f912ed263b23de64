//! Object setup (`ObjectModel::new`: checks, repairs, BVH, distance grid, hooks, mass
//! properties) on tori of 16k, 262k and 1M triangles, 11.8 cm across.
//!
//! Run: `cargo bench -p prehensile-bench --bench object_setup`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use prehensile_core::{shapes, ObjectModel};

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("object_setup");
    group.sample_size(10);
    for (u, v) in [(128, 64), (512, 256), (1024, 512)] {
        let mesh = shapes::torus(0.045, 0.014, u, v);
        let label = format!("torus_{}_triangles", mesh.triangles.len());
        group.bench_function(label, |b| {
            b.iter(|| black_box(ObjectModel::new("torus", mesh.clone(), None).unwrap()))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
