//! One simulation step of a hand gripping an object (contacts active), at the paper's 0.2 ms and
//! at 1 ms, each with the default solver for its step (`Settings::for_step`), on each engine
//! (rapier, and the reduced-coordinate engine: `_reduced`): the human hand and the Shadow hand
//! (MJCF fixture) on the built-in sphere, gravity pressing the sphere into the palm; and the
//! human hand at 1 ms with the rapier solver settings the default was chosen from (substeps ×
//! sweeps). Steps per second = 1 / time per step; real-time factor = dt / time.
//!
//! Run: `cargo bench -p prehensile-bench --bench simulation`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use prehensile_core::{shapes, HandModel, ObjectModel};
use prehensile_sim::scenarios::held_still;
use prehensile_sim::{Engine, RapierSettings, Settings, Simulation};

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
            for (engine, suffix) in [(Engine::Rapier, ""), (Engine::Reduced, "_reduced")] {
                let settings = Settings {
                    engine,
                    ..Settings::for_step(dt)
                };
                let mut sim = gripping(hand, settings);
                group.bench_function(format!("{name}_sphere_dt_{}ms{suffix}", dt * 1e3), |b| {
                    b.iter(|| black_box(&mut sim).step().unwrap())
                });
            }
        }
    }
    group.finish();
}

/// The solver settings at 1 ms that keep every scenario's outcome: two substeps of 3 sweeps (the
/// earlier default) and one substep of 7 or 8 sweeps (8 is the default; see
/// `RapierSettings::inner_iterations_for`).
fn solver_at_1ms(c: &mut Criterion) {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let mut group = c.benchmark_group("solver_at_1ms");
    for (substeps, sweeps) in [(2, 3), (1, 7), (1, 8)] {
        let mut sim = gripping(
            &hand,
            Settings {
                engine: Engine::Rapier,
                rapier: RapierSettings {
                    solver_iterations: substeps,
                    inner_iterations: sweeps,
                    ..RapierSettings::for_step(0.001)
                },
                ..Settings::for_step(0.001)
            },
        );
        group.bench_function(format!("human_sphere_{substeps}x{sweeps}"), |b| {
            b.iter(|| black_box(&mut sim).step().unwrap())
        });
    }
    group.finish();
}

/// The parts of a reduced-coordinate step, measured apart (what the engine's design rests on), on
/// the Shadow hand at its grip on the sphere: Newton–Euler and the mass matrix, and the narrow
/// phase: every capsule of the hand against the sphere's collision shape as the rapier world
/// has it (its convex hull, 482 vertices), by parry's contact query with a 1 mm margin after a
/// bounding-box test; against an exact sphere (what MuJoCo collides in the side-by-side
/// scene); the object's distance grid read along every capsule; and the contacts the engine
/// makes from the grid, cold and warm-started. The whole engine's step is
/// `simulation_step/*_reduced`.
fn reduced_coordinate_floor(c: &mut Criterion) {
    use prehensile_control::{crba, rnea, BaseMotion, DynamicsModel};
    use prehensile_core::search::{SearchParams, ValidityRule};

    let shadow_file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/hands/shadow_hand/reach.xml"
    );
    let hand = prehensile_formats::load_hand(std::path::Path::new(shadow_file)).unwrap();
    let params = SearchParams {
        validity: ValidityRule::Thesis,
        ..SearchParams::default()
    };
    let planned = prehensile_sim::scenarios::plan_grasp_with(&hand, &sphere(), params).unwrap();
    let grip = planned.closed.clone();
    let n = grip.len();
    // Two poses a hair apart, taken in turn, so that every step turns the links afresh.
    let poses = [
        grip.clone(),
        grip.iter().map(|a| a + 1e-6).collect::<Vec<_>>(),
    ];
    let model = DynamicsModel::new(&hand);
    let mut data = model.data();
    let base = BaseMotion::at_rest(prehensile_core::math::Vec3::new(0.0, 0.0, -9.81));
    let qd: Vec<f64> = (0..n).map(|k| 0.01 * (k as f64).sin()).collect();
    let zeros = vec![0.0; n];
    let mut group = c.benchmark_group("reduced_coordinate_floor");
    let mut turn = 0;
    group.bench_function("shadow_rnea", |b| {
        b.iter(|| {
            turn ^= 1;
            black_box(rnea(&model, &mut data, &poses[turn], &qd, &zeros, &base).unwrap()[0])
        })
    });
    group.bench_function("shadow_crba", |b| {
        b.iter(|| {
            turn ^= 1;
            black_box(crba(&model, &mut data, &poses[turn]).unwrap()[(0, 0)])
        })
    });
    let capsules = world_capsules(&hand, &planned.root, &grip);
    let (hull, _) = prehensile_sim::object_shape(&sphere()).unwrap();
    group.bench_function("shadow_contacts_vs_sphere_hull", |b| {
        b.iter(|| black_box(hull_contacts(&capsules, &hull)))
    });
    let centre = sphere().center_of_mass();
    group.bench_function("shadow_contacts_vs_exact_sphere", |b| {
        b.iter(|| {
            black_box(
                capsules
                    .iter()
                    .filter(|c| {
                        let ab = c.b - c.a;
                        let s = ((centre - c.a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
                        (centre - (c.a + ab * s)).norm() - 0.04 - c.radius <= CONTACT_MARGIN
                    })
                    .count(),
            )
        })
    });
    // A narrow phase from the object's own distance grid instead: the grid's bound of every
    // capsule's clearance (nodes one spacing apart along it, each an exact distance filled on
    // first use), which a grid-based contact would read.
    let object = sphere();
    let collider = object.collider();
    group.bench_function("shadow_clearances_from_distance_grid", |b| {
        b.iter(|| {
            capsules
                .iter()
                .map(|c| {
                    collider.segment_clearance_upper_bound(&c.a, &c.b, f64::INFINITY) - c.radius
                })
                .fold(f64::INFINITY, f64::min)
        })
    });
    // The contacts themselves from the grid (`MeshCollider::capsule_contact`: the grid's
    // conservative test, then the capsule's nearest point by trilinear samples), cold and
    // warm-started from each capsule's fraction of the step before, as an engine would.
    let grid_contacts = |warm: &[Option<f64>]| {
        capsules
            .iter()
            .zip(warm)
            .map(|(c, &w)| collider.capsule_contact(c, CONTACT_MARGIN, w))
            .map(|contact| contact.map(|c| c.fraction))
            .collect::<Vec<_>>()
    };
    let cold = vec![None; capsules.len()];
    group.bench_function("shadow_contacts_from_distance_grid_cold", |b| {
        b.iter(|| black_box(grid_contacts(&cold)))
    });
    let warm = grid_contacts(&cold);
    group.bench_function("shadow_contacts_from_distance_grid_warm", |b| {
        b.iter(|| black_box(grid_contacts(&warm)))
    });
    eprintln!(
        "contacts at the grip: {} against the hull, {} from the distance grid",
        hull_contacts(&capsules, &hull),
        warm.iter().flatten().count()
    );
    group.finish();
}

/// Contacts are made this far out (metres), as an engine keeps a resting contact.
const CONTACT_MARGIN: f64 = 0.001;

/// Every capsule of `hand` in world coordinates, its root at `root` and its joints at `q`.
fn world_capsules(
    hand: &HandModel,
    root: &prehensile_core::math::Transform,
    q: &[f64],
) -> Vec<prehensile_core::collision::Capsule> {
    let mut ws = prehensile_core::Workspace::new(hand);
    hand.joint_rotations(q, &mut ws.rotations);
    prehensile_core::hand::kinematics::forward_kinematics(hand, root, &ws.rotations, &mut ws.world);
    prehensile_core::finger_closing::update_world_capsules(hand, &mut ws);
    ws.capsules.clone()
}

/// How many of `capsules` touch `shape` (at the origin) within [`CONTACT_MARGIN`]: a bounding-box
/// test, then parry's contact query (GJK/EPA against a convex hull), as an engine's narrow
/// phase does each step.
fn hull_contacts(
    capsules: &[prehensile_core::collision::Capsule],
    shape: &rapier3d_f64::prelude::SharedShape,
) -> usize {
    use rapier3d_f64::parry::bounding_volume::BoundingVolume;
    use rapier3d_f64::parry::query;
    use rapier3d_f64::parry::shape::{Capsule, Shape};
    use rapier3d_f64::prelude::{Pose, Vector};
    let at_origin = Pose::IDENTITY;
    let bounds = shape.compute_aabb(&at_origin).loosened(CONTACT_MARGIN);
    capsules
        .iter()
        .filter(|c| {
            let point = |p: &prehensile_core::math::Point3| Vector::new(p.x, p.y, p.z);
            let capsule = Capsule::new(point(&c.a), point(&c.b), c.radius);
            if !capsule.compute_aabb(&at_origin).intersects(&bounds) {
                return false;
            }
            query::contact(
                &at_origin,
                &capsule,
                &at_origin,
                shape.as_ref(),
                CONTACT_MARGIN,
            )
            .ok()
            .flatten()
            .is_some()
        })
        .count()
}

criterion_group!(benches, step, solver_at_1ms, reduced_coordinate_floor);
criterion_main!(benches);
