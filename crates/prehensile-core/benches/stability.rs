//! The grasp wrench space's hull (force closure, ε, load ratios) on the 89 contact sets of the
//! scipy oracle (`tests/data/stability_oracle.json`, 2–17 contacts each), computed once per
//! search result.
//!
//! Run: `cargo bench -p prehensile-core --bench stability`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use prehensile_core::math::{Point3, Vec3};
use prehensile_core::stability::{Contact, ContactModel, GraspWrenchSpace};
use serde_json::Value;

/// One oracle case: contacts, contact model, centre of mass and torque scale.
struct Case {
    contacts: Vec<Contact>,
    model: ContactModel,
    center: Point3,
    scale: f64,
}

fn vector(v: &Value) -> [f64; 3] {
    let a = v.as_array().expect("a 3-vector");
    [0, 1, 2].map(|k| a[k].as_f64().expect("a number"))
}

fn cases() -> Vec<Case> {
    let data: Value = serde_json::from_str(include_str!("../tests/data/stability_oracle.json"))
        .expect("oracle JSON");
    data["cases"]
        .as_array()
        .expect("cases")
        .iter()
        .map(|case| Case {
            contacts: case["contacts"]
                .as_array()
                .expect("contacts")
                .iter()
                .map(|c| Contact {
                    bone: 0,
                    capsule: 0,
                    point: Point3::from(vector(&c["point"])),
                    normal: Vec3::from(vector(&c["normal"])),
                    gap: 0.0,
                    radius: c["radius"].as_f64().expect("radius"),
                })
                .collect(),
            model: ContactModel {
                friction: case["friction"].as_f64().expect("friction"),
                cone_edges: case["cone_edges"].as_u64().expect("cone edges") as usize,
                torsion_patch: case["torsion_patch"].as_f64().expect("torsion patch"),
            },
            center: Point3::from(vector(&case["center"])),
            scale: case["scale"].as_f64().expect("scale"),
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let cases = cases();
    let mut gws = GraspWrenchSpace::new();
    c.bench_function("wrench_space/89_oracle_cases", |b| {
        b.iter(|| {
            for case in &cases {
                black_box(gws.evaluate(&case.contacts, &case.model, &case.center, case.scale));
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
