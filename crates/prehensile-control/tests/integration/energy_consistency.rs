//! The dynamics checked against quantities computed without them, on the human hand (two-axis
//! joints, masses from its capsules): kinetic energy ½ q̇ᵀ M q̇ against body velocities from finite
//! differences of forward kinematics, and gravity torques against the finite-difference gradient
//! of the potential energy.

use prehensile_control::{gravity_torques, inverse_dynamics, mass_matrix};
use prehensile_core::math::{Rotation, Transform, Vec3};
use prehensile_core::HandModel;

fn poses(hand: &HandModel, q: &[f64]) -> Vec<Transform> {
    let mut rotations = vec![Rotation::identity(); hand.bones().len()];
    hand.joint_rotations(q, &mut rotations);
    hand.pose_transforms(&Transform::identity(), &rotations)
}

fn state(hand: &HandModel, seed: u64) -> (Vec<f64>, Vec<f64>) {
    let mut rng = prehensile_core::random::SplitMix64::new(seed);
    let q = (0..hand.dof_count())
        .map(|_| rng.uniform(-0.8, 0.8))
        .collect();
    let qd = (0..hand.dof_count())
        .map(|_| rng.uniform(-2.0, 2.0))
        .collect();
    (q, qd)
}

#[test]
fn kinetic_energy_matches_finite_differences_of_kinematics() {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    assert!(hand
        .bones()
        .iter()
        .all(|b| b.inertial.is_some_and(|i| i.mass > 0.0)));
    for seed in 1..=5 {
        let (q, qd) = state(&hand, seed);
        let m = mass_matrix(&hand, &q).unwrap();
        let v = nalgebra::DVector::from_vec(qd.clone());
        let from_matrix = 0.5 * v.dot(&(&m * &v));
        let h = 1e-6;
        let step = |s: f64| -> Vec<f64> { q.iter().zip(&qd).map(|(a, b)| a + s * b).collect() };
        let (plus, minus) = (poses(&hand, &step(h)), poses(&hand, &step(-h)));
        let now = poses(&hand, &q);
        let mut from_motion = 0.0;
        for (k, bone) in hand.bones().iter().enumerate() {
            let i = bone.inertial.unwrap();
            let com = |t: &Transform| t * i.center_of_mass;
            let velocity = (com(&plus[k]) - com(&minus[k])) / (2.0 * h);
            let turn = plus[k].rotation * minus[k].rotation.inverse();
            let omega_world = turn.scaled_axis() / (2.0 * h);
            let omega = now[k].rotation.inverse() * omega_world;
            from_motion +=
                0.5 * i.mass * velocity.norm_squared() + 0.5 * omega.dot(&(i.inertia * omega));
        }
        assert!(
            (from_matrix - from_motion).abs() <= 1e-6 * from_motion,
            "seed {seed}: {from_matrix} vs {from_motion}"
        );
        // M is symmetric and positive definite.
        assert!((&m - m.transpose()).amax() < 1e-15);
        assert!(m.clone().cholesky().is_some());
        // And inverse dynamics at zero velocity and gravity is M q̈.
        let zero = vec![0.0; q.len()];
        let tau = inverse_dynamics(&hand, &q, &zero, &qd, Vec3::zeros()).unwrap();
        assert!((tau - &m * &v).amax() < 1e-12);
    }
}

#[test]
fn gravity_torques_are_the_gradient_of_potential_energy() {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let g = Vec3::new(0.3, -9.7, 1.2);
    let potential = |q: &[f64]| -> f64 {
        poses(&hand, q)
            .iter()
            .zip(hand.bones())
            .map(|(t, b)| {
                let i = b.inertial.unwrap();
                -i.mass * g.dot(&(t * i.center_of_mass).coords)
            })
            .sum()
    };
    for seed in 1..=5 {
        let (q, _) = state(&hand, seed);
        let tau = gravity_torques(&hand, &q, g).unwrap();
        let scale = tau.amax();
        for k in 0..q.len() {
            let h = 1e-6;
            let (mut up, mut down) = (q.clone(), q.clone());
            up[k] += h;
            down[k] -= h;
            let gradient = (potential(&up) - potential(&down)) / (2.0 * h);
            assert!(
                (tau[k] - gradient).abs() <= 1e-6 * scale,
                "seed {seed} dof {k}: {} vs {gradient}",
                tau[k]
            );
        }
    }
}
