//! Inverse dynamics, mass matrix and gravity torques against Pinocchio 4.1 on the URDF hand tree,
//! read through the formats crate, to 1e-9 relative.

use prehensile_control::{gravity_torques, inverse_dynamics, mass_matrix, outboard_inertia};
use prehensile_core::math::Vec3;

#[derive(serde::Deserialize)]
struct Sample {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    tau: Vec<f64>,
    mass_matrix: Vec<Vec<f64>>,
    gravity: Vec<f64>,
}

#[derive(serde::Deserialize)]
struct Oracle {
    joint_order: Vec<String>,
    gravity: [f64; 3],
    fixed_base: Vec<Sample>,
}

/// The URDF hand tree and, for each of the oracle's joints in its order, our degree of freedom.
fn hand_and_order(joint_order: &[String]) -> (prehensile_core::HandModel, Vec<usize>) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let hand =
        prehensile_formats::load_hand(&dir.join("../../assets/hands/urdf/hand_tree_public.urdf"))
            .unwrap();
    let ours = joint_order
        .iter()
        .map(|name| hand.dof_names().iter().position(|d| d == name).unwrap())
        .collect();
    (hand, ours)
}

fn close(ours: f64, theirs: f64, scale: f64) -> bool {
    (ours - theirs).abs() <= 1e-9 * scale.max(1e-12)
}

#[test]
fn fixed_base_dynamics_match_pinocchio() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let oracle: Oracle = serde_json::from_str(
        &std::fs::read_to_string(dir.join("tests/data/hand_tree_public_fixed_base.json")).unwrap(),
    )
    .unwrap();
    let (hand, ours) = hand_and_order(&oracle.joint_order);
    let reorder = |v: &[f64]| {
        let mut out = vec![0.0; v.len()];
        for (k, &i) in ours.iter().enumerate() {
            out[i] = v[k];
        }
        out
    };
    let g = Vec3::from(oracle.gravity);
    assert_eq!(oracle.fixed_base.len(), 20);
    for (s, sample) in oracle.fixed_base.iter().enumerate() {
        let (q, v, a) = (reorder(&sample.q), reorder(&sample.v), reorder(&sample.a));
        let tau = inverse_dynamics(&hand, &q, &v, &a, g).unwrap();
        let scale = sample.tau.iter().fold(0.0f64, |m, t| m.max(t.abs()));
        for (k, &i) in ours.iter().enumerate() {
            assert!(
                close(tau[i], sample.tau[k], scale),
                "sample {s} tau {}: {} vs {}",
                oracle.joint_order[k],
                tau[i],
                sample.tau[k]
            );
        }
        let gravity = gravity_torques(&hand, &q, g).unwrap();
        let scale = sample.gravity.iter().fold(0.0f64, |m, t| m.max(t.abs()));
        for (k, &i) in ours.iter().enumerate() {
            assert!(
                close(gravity[i], sample.gravity[k], scale),
                "sample {s} gravity {}",
                oracle.joint_order[k]
            );
        }
        let m = mass_matrix(&hand, &q).unwrap();
        let scale = sample
            .mass_matrix
            .iter()
            .flatten()
            .fold(0.0f64, |m, t| m.max(t.abs()));
        for (r, &i) in ours.iter().enumerate() {
            for (c, &j) in ours.iter().enumerate() {
                assert!(
                    close(m[(i, j)], sample.mass_matrix[r][c], scale),
                    "sample {s} M[{r}][{c}]: {} vs {}",
                    m[(i, j)],
                    sample.mass_matrix[r][c]
                );
            }
        }
        let outboard = outboard_inertia(&hand, &q).unwrap().diagonal;
        assert!(outboard.iter().all(|x| *x > 0.0));
        for (k, &i) in ours.iter().enumerate() {
            assert!(
                close(outboard[i], sample.mass_matrix[k][k], scale),
                "sample {s} outboard inertia of {}",
                oracle.joint_order[k]
            );
        }
        // Cross-check: each column is also the torque for a unit acceleration (no gravity).
        let zero = vec![0.0; q.len()];
        for j in [0, 7, 19] {
            let mut unit = zero.clone();
            unit[j] = 1.0;
            let column = inverse_dynamics(&hand, &q, &zero, &unit, Vec3::zeros()).unwrap();
            for i in 0..q.len() {
                assert!(close(m[(i, j)], column[i], scale));
            }
        }
    }
}

#[test]
fn bad_states_are_refused() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let hand =
        prehensile_formats::load_hand(&dir.join("../../assets/hands/urdf/hand_tree_public.urdf"))
            .unwrap();
    let n = hand.dof_count();
    let zero = vec![0.0; n];
    assert!(inverse_dynamics(&hand, &zero[..3], &zero, &zero, Vec3::zeros()).is_err());
    let mut nan = zero.clone();
    nan[4] = f64::NAN;
    assert!(inverse_dynamics(&hand, &nan, &zero, &zero, Vec3::zeros()).is_err());
    assert!(gravity_torques(&hand, &zero, Vec3::new(0.0, f64::INFINITY, 0.0)).is_err());
}

#[derive(serde::Deserialize)]
struct MovingSample {
    base_quaternion_xyzw: [f64; 4],
    joint_positions: Vec<f64>,
    base_angular_velocity_world: [f64; 3],
    base_linear_acceleration_world: [f64; 3],
    base_angular_acceleration_world: [f64; 3],
    joint_torques: Vec<f64>,
}

#[derive(serde::Deserialize)]
struct MovingOracle {
    joint_order: Vec<String>,
    gravity: [f64; 3],
    samples: Vec<MovingSample>,
}

#[test]
fn moving_base_compensation_matches_pinocchio() {
    use prehensile_control::{inverse_dynamics_moving_base, BaseMotion};
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let oracle: MovingOracle = serde_json::from_str(
        &std::fs::read_to_string(dir.join("tests/data/hand_tree_public_moving_base.json")).unwrap(),
    )
    .unwrap();
    let (hand, ours) = hand_and_order(&oracle.joint_order);
    let zero = vec![0.0; hand.dof_count()];
    assert_eq!(oracle.samples.len(), 20);
    for (s, sample) in oracle.samples.iter().enumerate() {
        let [x, y, z, w] = sample.base_quaternion_xyzw;
        let to_base =
            nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z))
                .inverse();
        let world = |v: [f64; 3]| to_base * Vec3::from(v);
        let base = BaseMotion {
            angular_velocity: world(sample.base_angular_velocity_world),
            angular_acceleration: world(sample.base_angular_acceleration_world),
            linear_acceleration_minus_gravity: world(sample.base_linear_acceleration_world)
                - to_base * Vec3::from(oracle.gravity),
        };
        let mut q = vec![0.0; hand.dof_count()];
        for (k, &i) in ours.iter().enumerate() {
            q[i] = sample.joint_positions[k];
        }
        let tau = inverse_dynamics_moving_base(&hand, &q, &zero, &zero, &base).unwrap();
        let scale = sample
            .joint_torques
            .iter()
            .fold(0.0f64, |m, t| m.max(t.abs()));
        for (k, &i) in ours.iter().enumerate() {
            assert!(
                close(tau[i], sample.joint_torques[k], scale),
                "sample {s} {}: {} vs {}",
                oracle.joint_order[k],
                tau[i],
                sample.joint_torques[k]
            );
        }
    }
}
