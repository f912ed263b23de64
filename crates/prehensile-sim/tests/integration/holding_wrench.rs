//! The compensation wrenches are the paper's τG + τARM: mapped through the joints they equal the
//! inverse dynamics with the joints held still.

use prehensile_control::{inverse_dynamics_moving_base, BaseMotion};
use prehensile_core::hand::Joint;
use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use prehensile_sim::{holding_wrench, FrameMotion};

#[test]
fn body_wrenches_through_the_joints_equal_inverse_dynamics_with_a_moving_base() {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    // A bent pose inside the limits, a tilted and moving palm, gravity down.
    let q: Vec<f64> = (hand.dof_limits().into_iter().enumerate())
        .map(|(k, [lo, hi])| lo + (hi - lo) * (0.2 + 0.6 * ((k * 7 % 11) as f64 / 10.0)))
        .collect();
    let root = Transform::from_parts(
        Vec3::new(0.1, -0.2, 0.3).into(),
        Rotation::from_euler_angles(0.4, -0.7, 1.1),
    );
    let gravity = Vec3::new(0.0, 0.0, -9.81);
    let rotations: Vec<Rotation> = hand
        .bones()
        .iter()
        .map(|b| {
            b.joint
                .rotation(&q[b.first_dof..b.first_dof + b.joint.dofs()])
        })
        .collect();
    let mut frames = vec![Transform::identity(); hand.bones().len()];
    prehensile_core::hand::kinematics::forward_kinematics(&hand, &root, &rotations, &mut frames);
    let palm = frames[0];
    let motion = FrameMotion {
        origin: palm.translation.vector.into(),
        linear_acceleration: Vec3::new(3.0, -1.5, 2.0),
        angular_velocity: Vec3::new(2.0, 1.0, -3.0),
        angular_acceleration: Vec3::new(-20.0, 15.0, 8.0),
    };

    // Each bone's wrench, world frame, at its centre of mass.
    let wrenches: Vec<Option<(Point3, Vec3, Vec3)>> = hand
        .bones()
        .iter()
        .zip(&frames)
        .map(|(bone, frame)| {
            let inertial = bone.inertial.filter(|_| bone.parent.is_some())?;
            let turn = frame.rotation.to_rotation_matrix().into_inner();
            let com = frame * inertial.center_of_mass;
            let (force, torque) = holding_wrench(
                inertial.mass,
                &com,
                &(turn * inertial.inertia * turn.transpose()),
                &motion,
                &gravity,
            );
            Some((com, force, torque))
        })
        .collect();
    let outboard_of = |i: usize, b: usize| {
        let mut k = Some(i);
        while let Some(j) = k {
            if j == b {
                return true;
            }
            k = hand.bones()[j].parent;
        }
        false
    };
    let mut generalized = vec![0.0; hand.dof_count()];
    for (b, bone) in hand.bones().iter().enumerate() {
        let Some(parent) = bone.parent else { continue };
        let origin: Point3 = frames[b].translation.vector.into();
        let axes: Vec<(usize, Vec3)> = match &bone.joint {
            Joint::Hinge(a) => vec![(bone.first_dof, frames[b].rotation * a.axis.into_inner())],
            Joint::TwoAxis { flexion, abduction } => vec![
                (
                    bone.first_dof,
                    frames[b].rotation * flexion.axis.into_inner(),
                ),
                (
                    bone.first_dof + 1,
                    (frames[parent] * bone.rest).rotation * abduction.axis.into_inner(),
                ),
            ],
            _ => vec![],
        };
        for (dof, axis) in axes {
            generalized[dof] = (0..hand.bones().len())
                .filter(|&i| outboard_of(i, b))
                .filter_map(|i| wrenches[i])
                .map(|(com, force, torque)| axis.dot(&(torque + (com - origin).cross(&force))))
                .sum();
        }
    }

    let to_palm = palm.rotation.inverse();
    let base = BaseMotion {
        angular_velocity: to_palm * motion.angular_velocity,
        angular_acceleration: to_palm * motion.angular_acceleration,
        linear_acceleration_minus_gravity: to_palm * (motion.linear_acceleration - gravity),
    };
    let zero = vec![0.0; hand.dof_count()];
    let expected = inverse_dynamics_moving_base(&hand, &q, &zero, &zero, &base).unwrap();
    let scale = expected.amax();
    assert!(scale > 1e-3, "the test pose must load the joints");
    for (k, (got, want)) in generalized.iter().zip(expected.iter()).enumerate() {
        assert!(
            (got - want).abs() <= 1e-9 * scale,
            "{}: wrenches give {got}, inverse dynamics {want}",
            hand.dof_names()[k]
        );
    }
}
