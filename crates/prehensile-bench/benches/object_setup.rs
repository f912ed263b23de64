//! Object setup (`ObjectModel::new`: checks, repairs, BVH, distance grid, hooks, mass
//! properties) on tori of 16k, 262k and 1M triangles, 11.8 cm across, and on three open scans of
//! `assets/objects`, whose inside comes from winding numbers.
//!
//! Run: `cargo bench -p prehensile-bench --bench object_setup`

use std::hint::black_box;
use std::path::PathBuf;

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
    for scan in [
        "robosuite_bottle.stl",
        "robosuite_can_with_holes.stl",
        "pybullet_mug.obj",
    ] {
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/objects/")
            .join(scan);
        let mesh = prehensile_formats::read_mesh(&path, 1.0).unwrap();
        group.bench_function(format!("open_scan_{scan}"), |b| {
            b.iter(|| black_box(ObjectModel::new(scan, mesh.clone(), None).unwrap()))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
