//! The exact and fast capsule tests against independent answers from libigl
//! (`tools/oracle/collision_oracle.py`, committed as `tests/data/collision_oracle.json`).

use crate::common;

use prehensile_core::math::Point3;
use prehensile_core::{Capsule, CollisionCounters, ObjectModel};

#[derive(serde::Deserialize)]
struct Case {
    a: [f64; 3],
    b: [f64; 3],
    radius: f64,
    distance: f64,
    inside: bool,
    touches: bool,
}

#[derive(serde::Deserialize)]
struct MeshCases {
    scale: f64,
    cases: Vec<Case>,
}

#[derive(serde::Deserialize)]
struct Oracle {
    samples_per_segment: usize,
    meshes: std::collections::BTreeMap<String, MeshCases>,
}

fn mesh_path(name: &str) -> String {
    if name.starts_with("robosuite") || name.starts_with("pybullet") {
        format!("assets/objects/{name}")
    } else {
        format!("crates/prehensile-core/tests/data/{name}")
    }
}

#[test]
fn exact_and_fast_paths_match_libigl() {
    let text = std::fs::read_to_string(common::repo_path(
        "crates/prehensile-core/tests/data/collision_oracle.json",
    ))
    .unwrap();
    let oracle: Oracle = serde_json::from_str(&text).unwrap();
    let mut total = 0;
    let mut counters = CollisionCounters::default();
    for (name, set) in &oracle.meshes {
        let mesh = common::obj_mesh(&mesh_path(name), set.scale);
        let object = ObjectModel::new(name, mesh, None).unwrap();
        let exact = object.collider().exact();
        for (i, c) in set.cases.iter().enumerate() {
            let (a, b) = (Point3::from(c.a), Point3::from(c.b));
            // The oracle over-estimates the segment distance by at most half its sample spacing.
            let spacing = (b - a).norm() / (oracle.samples_per_segment - 1) as f64;
            let ours = exact.segment_distance(&a, &b);
            assert!(
                ours <= c.distance + 1e-9 && ours >= c.distance - spacing / 2.0 - 1e-9,
                "{name} case {i}: distance {ours} vs oracle {}",
                c.distance
            );
            assert_eq!(
                exact.signed_distance(&a) < 0.0,
                c.inside,
                "{name} case {i}: inside"
            );
            assert_eq!(
                exact.capsule_touches(&a, &b, c.radius),
                c.touches,
                "{name} case {i}: exact"
            );
            let capsule = Capsule {
                a,
                b,
                radius: c.radius,
            };
            assert_eq!(
                object.capsule_touches(&capsule, &mut counters),
                c.touches,
                "{name} case {i}: fast"
            );
            total += 1;
        }
    }
    assert_eq!(total, 750);
    // The grid must decide a real share of these near-surface cases on its own.
    assert!(counters.exact_fallbacks < counters.queries, "{counters:?}");
}

#[test]
fn capsule_wholly_inside_touches() {
    let object = common::object("sphere");
    let capsule = Capsule {
        a: Point3::new(-0.005, 0.0, 0.0),
        b: Point3::new(0.005, 0.0, 0.0),
        radius: 0.002,
    };
    assert!(object
        .collider()
        .exact()
        .capsule_touches(&capsule.a, &capsule.b, capsule.radius));
    assert!(object.capsule_touches(&capsule, &mut CollisionCounters::default()));
}

#[test]
fn capsule_inside_the_mug_cavity_is_free_and_in_its_wall_touches() {
    let object = common::object("mug");
    // The cavity: radius 3.5 cm above the 5 mm bottom; a 1 cm capsule on the axis is clear.
    let free = Capsule {
        a: Point3::new(0.0, 0.0, 0.03),
        b: Point3::new(0.0, 0.0, 0.06),
        radius: 0.01,
    };
    let mut counters = CollisionCounters::default();
    assert!(!object.capsule_touches(&free, &mut counters));
    assert!(!object
        .collider()
        .exact()
        .capsule_touches(&free.a, &free.b, free.radius));
    // Inside the 5 mm wall on the -x side (the handle is on +x).
    let wall = Capsule {
        a: Point3::new(-0.0375, 0.0, 0.04),
        b: Point3::new(-0.0375, 0.0, 0.05),
        radius: 0.001,
    };
    assert!(object.capsule_touches(&wall, &mut counters));
}

#[test]
fn far_capsules_are_decided_by_the_grid_alone() {
    let object = common::object("torus");
    let mut counters = CollisionCounters::default();
    for k in 0..100 {
        let x = 0.2 + 0.001 * k as f64;
        let c = Capsule {
            a: Point3::new(x, 0.0, 0.0),
            b: Point3::new(x, 0.03, 0.0),
            radius: 0.01,
        };
        assert!(!object.capsule_touches(&c, &mut counters));
    }
    assert_eq!(counters.exact_fallbacks, 0);
}
