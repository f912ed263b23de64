//! A measurement, not part of the product: a hand gripping a sphere stepped in reduced
//! coordinates on the project's own dynamics ([`prehensile_control::crba`],
//! [`prehensile_control::rnea`]) with a contact solver of a few dozen lines, to learn what such
//! a step costs and whether it holds the sphere before building an engine on it (issue 15,
//! docs/PERFORMANCE.md).
//!
//! The scene is the held-still one of the rapier benchmark (`scenarios::held_still`): the palm
//! fixed at the grasp the search finds on the built-in sphere (4 cm, 20 kg/m³), gravity pressing
//! the sphere into the palm, the fingers driven by joint servos (kp = 1 N·m/rad, kd = 0.05
//! N·m·s/rad, the Shadow file's servo stiffness) toward the grasp pressed a tenth of the
//! movement further. Each step of `dt`:
//!
//! 1. the bones placed by forward kinematics; every capsule within 1 mm of the sphere (an exact
//!    sphere, as MuJoCo collides it; or, with `mesh`, the built-in sphere's 960-triangle mesh
//!    through its distance grid, `MeshCollider::capsule_contact`, warm-started from each
//!    capsule's contact of the step before) gives a contact: normal, two tangents, its point;
//! 2. the hand's contact Jacobians from the joint axes (hinges and two-axis joints);
//! 3. M(q) (CRBA) and the bias b(q, q̇) (RNEA), the servos integrated implicitly:
//!    (M + dt·kd + dt²·kp) q̇⁺ = M q̇ + dt (kp (q* − q) − b) + Jᵀλ;
//! 4. the sphere's free velocity under gravity; the Delassus matrix of hand and sphere; 10
//!    projected Gauss–Seidel sweeps of the impulses (normal ≥ 0 with a Baumgarte push-out of
//!    the penetration, tangents within the friction pyramid μ = 1);
//! 5. velocities updated and integrated (semi-implicit Euler).
//!
//! Not modelled: joint limits, tendon couplings, hand–hand contacts, rolling friction. Run:
//! `cargo run --release -p prehensile-sim --example reduced_coordinate_step -- [HAND] [DT] [SECONDS] [exact|mesh]`
//! (default: the Shadow hand, 0.001, 1, exact). Prints the sphere's drift and the median µs per step.

use std::time::Instant;

use nalgebra::{DMatrix, DVector, UnitQuaternion};
use prehensile_control::{crba, rnea, BaseMotion, DynamicsModel};
use prehensile_core::collision::Capsule;
use prehensile_core::hand::Joint;
use prehensile_core::kinematics::forward_kinematics;
use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use prehensile_core::search::{SearchParams, ValidityRule};
use prehensile_core::{shapes, HandModel, ObjectModel};

const RADIUS: f64 = 0.04;
const DENSITY: f64 = 20.0;
const KP: f64 = 1.0;
const KD: f64 = 0.05;
const MU: f64 = 1.0;
const SWEEPS: usize = 10;
/// Contacts are made this far out, so that a resting contact stays one.
const MARGIN: f64 = 0.001;
/// Share of the penetration pushed out per step.
const BAUMGARTE: f64 = 0.2;

/// One contact row: its direction (object frame = world), the point, and the hand's Jacobian
/// row (the point's velocity along the direction per joint rate).
struct Row {
    direction: Vec3,
    point: Point3,
    hand: DVector<f64>,
    /// Penetration push-out for normal rows (m/s), 0 for tangents; the row's normal index.
    push: f64,
    normal: usize,
    /// The capsule the contact is on (its impulses start the next step's sweeps).
    capsule: usize,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let shadow = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/hands/shadow_hand/reach.xml"
    );
    let hand_name = args.first().map_or(shadow, String::as_str);
    let dt: f64 = args.get(1).map_or(Ok(0.001), |s| s.parse())?;
    let seconds: f64 = args.get(2).map_or(Ok(1.0), |s| s.parse())?;
    let use_mesh = match args.get(3).map(String::as_str) {
        None | Some("exact") => false,
        Some("mesh") => true,
        Some(other) => {
            return Err(format!("the fourth argument is exact or mesh, not {other}").into())
        }
    };
    let hand = prehensile_formats::builtin_hand(hand_name).map_or_else(
        || prehensile_formats::load_hand(std::path::Path::new(hand_name)),
        Ok,
    )?;
    let sphere = ObjectModel::new("sphere", shapes::builtin_object("sphere").unwrap(), None)?;
    let params = SearchParams {
        validity: ValidityRule::Thesis,
        ..SearchParams::default()
    };
    let grasp = prehensile_sim::scenarios::plan_grasp_with(&hand, &sphere, params)?;
    let palm = grasp.root;
    let gravity_world = -9.81 * grasp.approach.normalize();
    let palm_bone = palm * hand.bones()[0].rest;
    let base = BaseMotion::at_rest(palm_bone.rotation.inverse() * gravity_world);
    let target = grasp.pressed();
    let n = hand.dof_count();
    let model = DynamicsModel::new(&hand);
    let mut data = model.data();

    let mass = DENSITY * 4.0 / 3.0 * std::f64::consts::PI * RADIUS.powi(3);
    let inverse_inertia = 1.0 / (0.4 * mass * RADIUS * RADIUS);
    let mut centre = sphere.center_of_mass();
    let start = centre;
    let mut orientation = UnitQuaternion::identity();
    let (mut v, mut w) = (Vec3::zeros(), Vec3::zeros());
    let mut q = grasp.closed.clone();
    let mut qd = vec![0.0; n];

    // The blocks of M: one per finger, or one of every joint when the palm's own chain moves.
    let mut blocks: Vec<Vec<usize>> = vec![Vec::new(); hand.fingers().len()];
    for bone in hand.bones() {
        let dofs = bone.first_dof..bone.first_dof + bone.joint.dofs();
        match bone.finger {
            Some(f) => blocks[f].extend(dofs),
            None if dofs.is_empty() => {}
            None => blocks = vec![(0..n).collect()],
        }
    }
    if blocks.iter().map(Vec::len).sum::<usize>() != n {
        blocks = vec![(0..n).collect()];
    }
    blocks.retain(|b| !b.is_empty());
    let mut previous = vec![[0.0f64; 3]; hand.capsules().len()];
    // Each capsule's contact fraction of the step before (the mesh narrow phase's warm start).
    let mut fractions: Vec<Option<f64>> = vec![None; hand.capsules().len()];
    let mut rotations = vec![Rotation::identity(); hand.bones().len()];
    let mut world = vec![Transform::identity(); hand.bones().len()];
    let zeros = vec![0.0; n];
    let steps = (seconds / dt).round() as usize;
    let mut times = Vec::with_capacity(steps);
    let mut most_contacts = 0;
    let mut settled = None;
    for step in 0..steps {
        if step == steps / 2 {
            settled = Some(centre);
        }
        let began = Instant::now();
        // 1. Bones and contacts.
        hand.joint_rotations(&q, &mut rotations);
        forward_kinematics(&hand, &palm, &rotations, &mut world);
        let mut rows: Vec<Row> = Vec::new();
        for (capsule, c) in hand.capsules().iter().enumerate() {
            let (a, b) = (world[c.bone] * c.a, world[c.bone] * c.b);
            // The contact's gap, its normal from the capsule into the object, and its point.
            let (gap, normal, point) = if use_mesh {
                // The capsule in the mesh's own frame, where its distance grid lies.
                let to_mesh = |p: Point3| start + orientation.inverse() * (p - centre);
                let local = Capsule {
                    a: to_mesh(a),
                    b: to_mesh(b),
                    radius: c.radius,
                };
                let found = sphere
                    .collider()
                    .capsule_contact(&local, MARGIN, fractions[capsule]);
                fractions[capsule] = found.map(|f| f.fraction);
                let Some(contact) = found else {
                    continue;
                };
                (
                    contact.gap,
                    -(orientation * contact.normal),
                    centre + orientation * (contact.point - start),
                )
            } else {
                let ab = b - a;
                let s = ((centre - a).dot(&ab) / ab.norm_squared().max(1e-300)).clamp(0.0, 1.0);
                let nearest = a + ab * s;
                let normal = (centre - nearest).normalize();
                (
                    (centre - nearest).norm() - RADIUS - c.radius,
                    normal,
                    nearest + normal * c.radius,
                )
            };
            if gap > MARGIN {
                continue;
            }
            let t1 = normal
                .cross(&Vec3::x())
                .try_normalize(1e-6)
                .unwrap_or_else(|| normal.cross(&Vec3::y()).normalize());
            let t2 = normal.cross(&t1);
            let first = rows.len();
            for (k, direction) in [normal, t1, t2].into_iter().enumerate() {
                rows.push(Row {
                    direction,
                    point,
                    hand: hand_jacobian_row(&hand, &palm, &world, c.bone, &point, &direction, &q),
                    push: if k == 0 {
                        (-gap).max(0.0) * BAUMGARTE / dt
                    } else {
                        0.0
                    },
                    normal: first,
                    capsule,
                });
            }
        }
        most_contacts = most_contacts.max(rows.len() / 3);
        // 3. The hand's free velocity with implicit servos, block by block (M is block
        // diagonal: under the fixed palm each finger is its own tree).
        let bias = rnea(&model, &mut data, &q, &qd, &zeros, &base)?.to_vec();
        let m = crba(&model, &mut data, &q)?;
        let count = rows.len();
        let mut free = vec![0.0; n];
        let mut delassus: DMatrix<f64> = DMatrix::zeros(count, count);
        let mut solved = Vec::with_capacity(blocks.len());
        for dofs in &blocks {
            let size = dofs.len();
            let effective = DMatrix::from_fn(size, size, |i, j| {
                m[(dofs[i], dofs[j])] + if i == j { dt * KD + dt * dt * KP } else { 0.0 }
            });
            let cholesky = effective
                .cholesky()
                .ok_or("the mass matrix is not positive definite")?;
            let rhs = DVector::from_fn(size, |i, _| {
                let k = dofs[i];
                (0..size)
                    .map(|j| m[(k, dofs[j])] * qd[dofs[j]])
                    .sum::<f64>()
                    + dt * (KP * (target[k] - q[k]) - bias[k])
            });
            let block_free = cholesky.solve(&rhs);
            for (i, &k) in dofs.iter().enumerate() {
                free[k] = block_free[i];
            }
            // The rows on this block's bones, and M̃⁻¹ Hᵀ for them.
            let on: Vec<usize> = (0..count)
                .filter(|&r| dofs.iter().any(|&k| rows[r].hand[k] != 0.0))
                .collect();
            let h = DMatrix::from_fn(on.len(), size, |r, j| rows[on[r]].hand[dofs[j]]);
            let mj = cholesky.solve(&h.transpose());
            let local = &h * &mj;
            for (a, &ra) in on.iter().enumerate() {
                for (b, &rb) in on.iter().enumerate() {
                    delassus[(ra, rb)] += local[(a, b)];
                }
            }
            solved.push((on, mj));
        }
        // 4. The sphere's free velocity; the Delassus matrix; the impulses.
        let v_free = v + gravity_world * dt;
        let object_rows: Vec<(Vec3, Vec3)> = rows
            .iter()
            .map(|r| (r.direction, (r.point - centre).cross(&r.direction)))
            .collect();
        for i in 0..count {
            for j in 0..count {
                let (li, ai) = object_rows[i];
                let (lj, aj) = object_rows[j];
                delassus[(i, j)] += li.dot(&lj) / mass + ai.dot(&aj) * inverse_inertia;
            }
        }
        // Relative velocity, object minus hand, along each row.
        let relative: Vec<f64> = (0..count)
            .map(|i| {
                let (l, a) = object_rows[i];
                let hand_velocity: f64 = (0..n).map(|k| rows[i].hand[k] * free[k]).sum();
                l.dot(&v_free) + a.dot(&w) - hand_velocity
            })
            .collect();
        // Warm start: each capsule's impulses of the step before, in its (slowly turning) frame.
        let mut lambda: DVector<f64> =
            DVector::from_fn(count, |r, _| previous[rows[r].capsule][r - rows[r].normal]);
        for _ in 0..SWEEPS {
            for r in 0..count {
                let residual = relative[r] + delassus.column(r).dot(&lambda) - rows[r].push;
                let value = lambda[r] - residual / delassus[(r, r)];
                let normal = rows[r].normal;
                lambda[r] = if r == normal {
                    value.max(0.0)
                } else {
                    value.clamp(-MU * lambda[normal], MU * lambda[normal])
                };
            }
        }
        for slot in previous.iter_mut() {
            *slot = [0.0; 3];
        }
        for r in 0..count {
            previous[rows[r].capsule][r - rows[r].normal] = lambda[r];
        }
        // 5. Update and integrate.
        for (dofs, (on, mj)) in blocks.iter().zip(&solved) {
            for (i, &k) in dofs.iter().enumerate() {
                let push: f64 = on
                    .iter()
                    .enumerate()
                    .map(|(r, &row)| mj[(i, r)] * lambda[row])
                    .sum();
                qd[k] = free[k] - push;
            }
        }
        for k in 0..n {
            q[k] += dt * qd[k];
        }
        v = v_free;
        for i in 0..count {
            let (l, a) = object_rows[i];
            v += l * (lambda[i] / mass);
            w += a * (lambda[i] * inverse_inertia);
        }
        centre += v * dt;
        orientation = UnitQuaternion::from_scaled_axis(w * dt) * orientation;
        times.push(began.elapsed().as_secs_f64());
        if !centre.coords.iter().all(|x| x.is_finite()) {
            return Err("the step diverged".into());
        }
    }
    times.sort_by(f64::total_cmp);
    let moved = (centre - start).norm();
    let late = settled.map_or(0.0, |p| (centre - p).norm());
    println!(
        "{} steps of {dt} s: the sphere moved {:.2} mm ({:.2} mm in the second half) and turned \
         {:.1}°; up to {most_contacts} contacts; median {:.2} µs a step",
        steps,
        moved * 1e3,
        late * 1e3,
        orientation.angle().to_degrees(),
        times[times.len() / 2] * 1e6
    );
    Ok(())
}

/// The velocity of `point` (on `bone`) along `direction` per joint rate: the sum over the
/// bone's joint and its ancestors' of (axis × (point − joint origin)) · direction.
fn hand_jacobian_row(
    hand: &HandModel,
    palm: &Transform,
    world: &[Transform],
    bone: usize,
    point: &Point3,
    direction: &Vec3,
    q: &[f64],
) -> DVector<f64> {
    let mut row = DVector::zeros(hand.dof_count());
    let mut at = Some(bone);
    while let Some(b) = at {
        let spec = &hand.bones()[b];
        let frame = match spec.parent {
            Some(p) => world[p] * spec.rest,
            None => palm * spec.rest,
        };
        let origin = Point3::from(frame.translation.vector);
        let lever = point - origin;
        let mut add = |dof: usize, axis: Vec3| row[dof] += axis.cross(&lever).dot(direction);
        match &spec.joint {
            Joint::Fixed => {}
            Joint::Hinge(a) => add(spec.first_dof, frame.rotation * a.axis.into_inner()),
            Joint::TwoAxis { flexion, abduction } => {
                let outer = Rotation::from_axis_angle(&abduction.axis, q[spec.first_dof + 1]);
                add(
                    spec.first_dof + 1,
                    frame.rotation * abduction.axis.into_inner(),
                );
                add(
                    spec.first_dof,
                    frame.rotation * (outer * flexion.axis.into_inner()),
                );
            }
            Joint::Ball { .. } => panic!("ball joints are not modelled in this measurement"),
        }
        at = spec.parent;
    }
    row
}
