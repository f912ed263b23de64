//! One simulation step of a hand gripping an object (contacts active), at the paper's 0.2 ms and
//! at 1 ms, each with the default solver for its step (`Settings::for_step`): the human hand and
//! the Shadow hand (MJCF fixture) on the built-in sphere, gravity pressing the sphere into the
//! palm; and the human hand at 1 ms with the solver settings the default was chosen from
//! (substeps × sweeps). Steps per second = 1 / time per step; real-time factor = dt / time.
//!
//! Run: `cargo bench -p prehensile-bench --bench simulation`

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use prehensile_core::{shapes, HandModel, ObjectModel};
use prehensile_sim::scenarios::held_still;
use prehensile_sim::{Settings, Simulation};

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
            let mut sim = gripping(hand, Settings::for_step(dt));
            group.bench_function(format!("{name}_sphere_dt_{}ms", dt * 1e3), |b| {
                b.iter(|| black_box(&mut sim).step().unwrap())
            });
        }
    }
    group.finish();
}

/// The solver settings at 1 ms that keep every scenario's outcome: two substeps of 3 sweeps (the
/// earlier default) and one substep of 7 or 8 sweeps (8 is the default; see
/// `Settings::inner_iterations_for`).
fn solver_at_1ms(c: &mut Criterion) {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let mut group = c.benchmark_group("solver_at_1ms");
    for (substeps, sweeps) in [(2, 3), (1, 7), (1, 8)] {
        let mut sim = gripping(
            &hand,
            Settings {
                solver_iterations: substeps,
                inner_iterations: sweeps,
                ..Settings::for_step(0.001)
            },
        );
        group.bench_function(format!("human_sphere_{substeps}x{sweeps}"), |b| {
            b.iter(|| black_box(&mut sim).step().unwrap())
        });
    }
    group.finish();
}

/// What one step of a reduced-coordinate engine built on our own dynamics would cost at least,
/// on the Shadow hand at its grip on the sphere (issue 15: measure the project's own dynamics
/// with a contact solver against rapier before choosing). Each step: the links turned to a new
/// pose, the velocity bias (RNEA), the mass matrix (CRBA), M + dt·Kd + dt²·Kp factored (position
/// servos integrated implicitly, as MuJoCo's are), the free velocity, the Delassus matrix
/// J M⁻¹ Jᵀ of 5 contacts × 3 rows (MuJoCo counts 3–5 contacts in this scene) plus the free
/// object's rank-6 term, and 20 projected Gauss–Seidel sweeps with a friction pyramid
/// ([`pgs`]). Once with a dense factorization, once by finger: under the held (kinematic) palm
/// each finger is a tree of its own, so M is block diagonal and a contact's rows touch one
/// finger's columns. Not counted there: collision detection and assembling the contact Jacobians
/// (J is fixed here), which an engine adds. A cost floor, not an engine: nothing is integrated.
/// The collision detection it would add is measured beside it: every capsule of the hand at its
/// grip against the sphere's collision shape as the rapier world has it (its convex hull, 482
/// vertices), by parry's contact query with a 1 mm margin after a bounding-box test; against
/// an exact sphere (what MuJoCo collides in the side-by-side scene); and the object's distance
/// grid read along every capsule, what a narrow phase on the grid would read.
fn reduced_coordinate_floor(c: &mut Criterion) {
    use nalgebra::{DMatrix, DVector};
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
    let (dt, kp, kd, mu) = (0.001, 1.0, 0.05, 1.0);
    let servo = dt * kd + dt * dt * kp;
    let contacts = 5;
    let rows = 3 * contacts;
    let mut blocks: Vec<Vec<usize>> = vec![Vec::new(); hand.fingers().len()];
    for bone in hand.bones() {
        if let Some(f) = bone.finger {
            blocks[f].extend(bone.first_dof..bone.first_dof + bone.joint.dofs());
        }
    }
    let full = crba(&model, &mut data, &grip).unwrap().clone();
    let coupled = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .filter(|&(i, j)| blocks.iter().all(|b| !(b.contains(&i) && b.contains(&j))))
        .map(|(i, j)| full[(i, j)].abs())
        .fold(0.0, f64::max);
    assert!(coupled < 1e-12, "M couples fingers by {coupled}");
    // Contact k on finger k, its rows (normal, two tangents) with lever arms of a few
    // centimetres; the object's 6 columns; a 5 g object.
    let finger_rows: Vec<DMatrix<f64>> = (0..contacts)
        .map(|k| {
            let cols = blocks[k % blocks.len()].len();
            DMatrix::from_fn(3, cols, |i, j| 0.03 * ((i * 7 + j * 3 + k) as f64).sin())
        })
        .collect();
    let mut jacobian = DMatrix::zeros(rows, n);
    for (k, j) in finger_rows.iter().enumerate() {
        for (c, &col) in blocks[k % blocks.len()].iter().enumerate() {
            jacobian
                .view_mut((3 * k, col), (3, 1))
                .copy_from(&j.column(c));
        }
    }
    let object_rows = DMatrix::from_fn(rows, 6, |i, j| ((i * 5 + j) as f64).cos());
    let object_term = &object_rows * object_rows.transpose() / 0.0054;
    let mut group = c.benchmark_group("reduced_coordinate_floor");
    let mut turn = 0;
    group.bench_function("shadow_5_contacts_dt_1ms_dense", |b| {
        b.iter(|| {
            turn ^= 1;
            let q = &poses[turn];
            let bias =
                DVector::from_column_slice(rnea(&model, &mut data, q, &qd, &zeros, &base).unwrap());
            let mut m = crba(&model, &mut data, q).unwrap().clone();
            for k in 0..n {
                m[(k, k)] += servo;
            }
            let cholesky = m.cholesky().unwrap();
            let free = DVector::from_column_slice(&qd) - cholesky.solve(&(bias * dt));
            let mj = cholesky.solve(&jacobian.transpose());
            let delassus = &jacobian * &mj + &object_term;
            let lambda = pgs(&delassus, &(&jacobian * &free), mu);
            black_box(free + mj * lambda)
        })
    });
    group.bench_function("shadow_5_contacts_dt_1ms_by_finger", |b| {
        b.iter(|| {
            turn ^= 1;
            let q = &poses[turn];
            let bias = rnea(&model, &mut data, q, &qd, &zeros, &base)
                .unwrap()
                .to_vec();
            let m = crba(&model, &mut data, q).unwrap();
            let mut free = DVector::from_column_slice(&qd);
            let mut delassus = object_term.clone();
            let mut velocity = DVector::zeros(rows);
            for (k, cols) in blocks.iter().enumerate() {
                let block = DMatrix::from_fn(cols.len(), cols.len(), |i, j| {
                    m[(cols[i], cols[j])] + if i == j { servo } else { 0.0 }
                });
                let cholesky = block.cholesky().unwrap();
                let rhs = DVector::from_fn(cols.len(), |i, _| bias[cols[i]] * dt);
                let step = cholesky.solve(&rhs);
                for (i, &c) in cols.iter().enumerate() {
                    free[c] -= step[i];
                }
                if k < contacts {
                    let j = &finger_rows[k];
                    let r = 3 * k;
                    let local = j * cholesky.solve(&j.transpose());
                    let mut corner = delassus.view_mut((r, r), (3, 3));
                    corner += local;
                    let finger_free = DVector::from_fn(cols.len(), |i, _| free[cols[i]]);
                    velocity.rows_mut(r, 3).copy_from(&(j * finger_free));
                }
            }
            black_box(pgs(&delassus, &velocity, mu))
        })
    });
    let delassus = &jacobian * jacobian.transpose() + &object_term;
    let velocity = DVector::from_fn(rows, |i, _| if i % 3 == 0 { -0.01 } else { 0.001 });
    group.bench_function("pgs_20_sweeps", |b| {
        b.iter(|| black_box(pgs(&delassus, &velocity, mu)))
    });
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
    prehensile_core::kinematics::forward_kinematics(hand, root, &ws.rotations, &mut ws.world);
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

/// 20 projected Gauss–Seidel sweeps of the contact impulses λ (per contact: normal ≥ 0, then two
/// tangents within the friction pyramid μ·λₙ) for the Delassus matrix `delassus` and the free
/// contact velocities `velocity`.
fn pgs(
    delassus: &nalgebra::DMatrix<f64>,
    velocity: &nalgebra::DVector<f64>,
    mu: f64,
) -> nalgebra::DVector<f64> {
    let rows = velocity.len();
    let mut lambda = nalgebra::DVector::zeros(rows);
    for _ in 0..20 {
        for r in 0..rows {
            // The Delassus matrix is symmetric: its column is its row, and contiguous.
            let residual = velocity[r] + delassus.column(r).dot(&lambda);
            let value = lambda[r] - residual / delassus[(r, r)];
            let normal = r - r % 3;
            lambda[r] = if r == normal {
                value.max(0.0)
            } else {
                value.clamp(-mu * lambda[normal], mu * lambda[normal])
            };
        }
    }
    lambda
}

criterion_group!(benches, step, solver_at_1ms, reduced_coordinate_floor);
criterion_main!(benches);
