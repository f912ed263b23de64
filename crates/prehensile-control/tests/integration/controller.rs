//! The controller's torque laws, blends and state machine (Pollard & Zordan, Eq. 3–16, Fig. 3).

use crate::common;

use nalgebra::DVector;
use prehensile_control::{
    active_torque, gravity_torques, joint_springs, outboard_inertia, passive_torque, BaseMotion,
    Blend, ControllerState, DynamicsModel, Gains, GraspController, GraspState, JointSpring,
    OutboardInertia, PerSetpoint, Setpoint, Setpoints,
};
use prehensile_core::math::Vec3;

fn setpoints(n: usize) -> Setpoints {
    Setpoints {
        positions: PerSetpoint::from_fn(|s| vec![0.1 * s.index() as f64; n]),
        velocities: PerSetpoint::from_fn(|_| vec![0.0; n]),
        neutral: vec![0.2; n],
        limits: vec![[0.0, 1.0]; n],
    }
}

#[test]
fn blends_follow_figure_3_and_grip_strength_extrapolates() {
    let g = Gains::grasp();
    // Each state's weights sum to one; ramps follow the distance.
    for (state, distance) in [
        (GraspState::Neutral, 0.5),
        (GraspState::Opening, 0.175),
        (GraspState::Closing, 0.025),
        (GraspState::Gripping, 0.0),
        (GraspState::Releasing, 0.0),
        (GraspState::OpeningAgain, 0.025),
        (GraspState::Relaxing, 0.175),
        (GraspState::NeutralAgain, 0.5),
    ] {
        let b = state.blend(distance, 0.0, &g);
        assert!(
            (b.values().sum::<f64>() - 1.0).abs() < 1e-12,
            "{state:?}: {b:?}"
        );
    }
    assert_eq!(
        GraspState::Opening.blend(0.175, 0.0, &g).0,
        [0.5, 0.5, 0.0, 0.0, 0.0, 0.0]
    );
    assert_eq!(
        GraspState::Closing.blend(0.025, 0.0, &g).0,
        [0.0, 0.5, 0.5, 0.0, 0.0, 0.0]
    );
    // Eq. 15–16: B[2] = 1 + α, B[1] = −α.
    assert_eq!(
        GraspState::Gripping.blend(0.0, 0.3, &g).0,
        [0.0, -0.3, 1.3, 0.0, 0.0, 0.0]
    );
}

#[test]
fn the_state_machine_runs_a_whole_grasp_and_release() {
    let g = Gains::grasp();
    let mut state = GraspState::Neutral;
    let mut timeline = vec![state];
    let approach = [0.5, 0.25, 0.1, 0.04, 0.01, 0.0, 0.0];
    for d in approach {
        state = state.next(d, false, &g);
        if timeline.last() != Some(&state) {
            timeline.push(state);
        }
    }
    for (d, release) in [(0.0, true), (0.01, false), (0.08, false), (0.4, false)] {
        state = state.next(d, release, &g);
        if timeline.last() != Some(&state) {
            timeline.push(state);
        }
    }
    use GraspState::*;
    assert_eq!(
        timeline,
        [
            Neutral,
            Opening,
            Closing,
            Gripping,
            Releasing,
            OpeningAgain,
            Relaxing,
            NeutralAgain
        ]
    );
}

/// [`passive_torque`] into a new vector.
fn passive_law(i: &OutboardInertia, q: &[f64], qd: &[f64], s: &Setpoints, g: &Gains) -> Vec<f64> {
    let mut out = vec![f64::NAN; q.len()];
    passive_torque(i, q, qd, s, g, &mut out);
    out
}

/// [`active_torque`] into a new vector.
fn active_law(
    i: &OutboardInertia,
    q: &[f64],
    qd: &[f64],
    s: &Setpoints,
    blend: &Blend,
    g: &Gains,
) -> Vec<f64> {
    let mut out = vec![f64::NAN; q.len()];
    active_torque(i, q, qd, s, blend, g, &mut out);
    out
}

#[test]
fn passive_torque_pulls_to_neutral_and_limits_act_only_outside() {
    let g = Gains::grasp();
    let s = setpoints(3);
    let inertia = OutboardInertia {
        diagonal: vec![2e-6, 1e-6, 5e-7],
        balls: Vec::new(),
    };
    // At neutral and at rest: no torque.
    assert_eq!(
        passive_law(&inertia, &[0.2; 3], &[0.0; 3], &s, &g),
        vec![0.0; 3]
    );
    // Inside the limits only the neutral spring and damping act; Eq. 4: τ/I is the same
    // acceleration change at every joint.
    let tau = passive_law(&inertia, &[0.5; 3], &[1.0; 3], &s, &g);
    let accel: Vec<f64> = tau
        .iter()
        .zip(&inertia.diagonal)
        .map(|(t, i)| t / i)
        .collect();
    assert!(
        accel
            .iter()
            .all(|a| (a - (200.0 * -0.3 - 50.0)).abs() < 1e-9),
        "{accel:?}"
    );
    // Beyond the upper limit the limit spring adds k_JL (θ_L − θ).
    let over = passive_law(&inertia, &[1.1; 3], &[0.0; 3], &s, &g);
    assert!(
        (over[0] / inertia.diagonal[0] - (200.0 * (0.2 - 1.1) + 5000.0 * (1.0 - 1.1))).abs() < 1e-9
    );
    // Active torque toward the blended setpoint.
    let blend = GraspState::Closing.blend(0.025, 0.0, &g);
    let active = active_law(&inertia, &[0.0; 3], &[0.0; 3], &s, &blend, &g);
    assert!((active[1] / inertia.diagonal[1] - 200.0 * 0.15).abs() < 1e-9);
}

#[test]
fn the_controller_adds_compensation_by_inverse_dynamics() {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let n = hand.dof_count();
    let q = vec![0.1; n];
    let zero = vec![0.0; n];
    let gravity = Vec3::new(0.0, 0.0, -9.81);
    let mut s = setpoints(n);
    s.neutral = q.clone();
    s.limits = vec![[-3.0, 3.0]; n];
    s.positions = PerSetpoint::from_fn(|_| q.clone());
    let mut controller = GraspController::new(Gains::grasp(), s);
    let model = DynamicsModel::new(&hand);
    let mut data = model.data();
    let mut run = ControllerState::default();
    let mut torques = |controller: &mut GraspController, distance: f64, compensate: bool| {
        let mut tau = vec![f64::NAN; n];
        let at_rest = BaseMotion::at_rest(gravity);
        controller
            .torques(
                &mut run, &model, &mut data, &q, &zero, &at_rest, distance, false, compensate,
                &mut tau,
            )
            .map(|()| DVector::from_vec(tau))
    };
    // At the setpoints and at rest, all that is left is the compensation: gravity torques.
    let tau = torques(&mut controller, 1.0, true).unwrap();
    let expected = gravity_torques(&hand, &q, gravity).unwrap();
    assert!((tau - expected).amax() < 1e-15);
    let off = torques(&mut controller, 1.0, false).unwrap();
    assert!(off.amax() < 1e-15);
    assert!(outboard_inertia(&hand, &q)
        .unwrap()
        .diagonal
        .iter()
        .all(|i| *i > 0.0));
    assert!(torques(&mut controller, f64::NAN, true).is_err());
}

#[test]
fn passive_parameters_fit_from_a_bvh_motion() {
    use prehensile_core::animation::approach_and_close;
    use prehensile_core::math::Transform;
    // An example motion: the human hand's power grasp exported as BVH and read back.
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let fractions = vec![1.0; hand.bones().len()];
    let frames = approach_and_close(
        &hand,
        hand.movement("power").unwrap(),
        &Transform::identity(),
        0.0,
        &fractions,
        0.1,
        10,
    );
    let text = prehensile_formats::write_bvh(&hand, &frames, 30.0);
    let motion = prehensile_formats::parse_bvh(&text, "power.bvh").unwrap();
    let angles = motion.joint_angles(&hand, "power.bvh").unwrap();
    let (neutral, limits) = prehensile_control::fit_passive(&angles).unwrap();
    let k = hand
        .dof_names()
        .iter()
        .position(|d| d == "index_middle.flexion")
        .unwrap();
    // The index middle flexion goes from 0 to 100° in this motion.
    assert!(
        limits[k][0].abs() < 1e-6 && (limits[k][1] - 100f64.to_radians()).abs() < 1e-6,
        "{:?}",
        limits[k]
    );
    assert!(neutral[k] > limits[k][0] && neutral[k] < limits[k][1]);
}

#[test]
fn active_setpoints_fitted_from_a_simulated_motion_recover_the_controller() {
    use prehensile_control::fit_active;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let hand =
        prehensile_formats::load_hand(&dir.join("../../assets/hands/urdf/hand_tree_public.urdf"))
            .unwrap();
    let n = hand.dof_count();
    let gains = Gains::grasp();
    let gravity = Vec3::new(0.0, 0.0, -9.81);
    let base = BaseMotion::at_rest(gravity);
    // The true controller: open pose (setpoint 0) to a half-closed one (setpoint 1).
    let mut truth = setpoints(n);
    truth.neutral = vec![0.1; n];
    truth.limits = vec![[-1.0, 1.6]; n];
    truth.positions[Setpoint::Neutral] = vec![0.05; n];
    truth.positions[Setpoint::Open] = (0..n).map(|k| 0.2 + 0.03 * k as f64).collect();
    let controller = GraspController::new(gains, truth.clone());
    // Simulate 0.25 s while the object comes from 30 cm to 5 cm (state Opening throughout).
    let common::Motion {
        dt,
        frames,
        blends,
        last: q,
    } = common::opening_motion(&hand, &controller, &base, &vec![0.05; n], |q, qd, dt| {
        q.iter_mut().zip(qd).for_each(|(q, qd)| *q += dt * qd)
    });
    assert!(q.iter().all(|x| x.is_finite()));
    // Fit from the motion alone (the passive parameters are known).
    let mut fitted = setpoints(n);
    fitted.neutral = truth.neutral.clone();
    fitted.limits = truth.limits.clone();
    fit_active(&hand, &frames, dt, &blends, &base, &gains, &mut fitted).unwrap();
    // The motion determines k_S·P_S + k_D·P_D for the setpoints it uses (0 and 1).
    for j in [Setpoint::Neutral, Setpoint::Open] {
        for k in 0..n {
            let got = gains.k_s * fitted.positions[j][k] + gains.k_d * fitted.velocities[j][k];
            let want = gains.k_s * truth.positions[j][k];
            assert!(
                (got - want).abs() < 0.02 * want.abs().max(1.0),
                "setpoint {j:?} dof {k}: {got} vs {want}"
            );
        }
    }
    // Setpoints the motion never blends in stay zero.
    assert!(fitted.positions[Setpoint::Release]
        .iter()
        .all(|v| v.abs() < 1e-9));
}

#[test]
fn joint_springs_are_the_passive_plus_active_torque() {
    let g = Gains::grasp();
    let n = 4;
    let mut s = setpoints(n);
    s.velocities[Setpoint::Grip] = vec![0.3; n];
    let inertia = OutboardInertia {
        diagonal: vec![1e-4, 2e-5, 3e-6, 5e-7],
        balls: Vec::new(),
    };
    // Inside the range, below it and above it (limit springs act outside only).
    let q = [0.5, -0.2, 1.3, 0.9];
    let qd = [0.1, -2.0, 0.5, 0.0];
    for (blend, active) in [
        (GraspState::Closing.blend(0.02, 0.0, &g), true),
        (GraspState::Gripping.blend(0.0, 0.4, &g), true),
        (GraspState::Neutral.blend(1.0, 0.0, &g), false),
    ] {
        let mut springs = [JointSpring {
            stiffness: f64::NAN,
            damping: f64::NAN,
            target: f64::NAN,
            target_velocity: f64::NAN,
        }; 4];
        joint_springs(&inertia, &q, &s, &blend, &g, active, &mut springs);
        let passive = passive_law(&inertia, &q, &qd, &s, &g);
        let active_tau = active_law(&inertia, &q, &qd, &s, &blend, &g);
        for k in 0..n {
            let expected = passive[k] + if active { active_tau[k] } else { 0.0 };
            let got = springs[k].torque(q[k], qd[k]);
            assert!(
                (got - expected).abs() <= 1e-12 * expected.abs().max(1e-9),
                "dof {k}: spring {got}, laws {expected}"
            );
        }
    }
}

#[test]
fn a_manual_setpoint_overrides_the_state_machine() {
    let c = GraspController::new(Gains::grasp(), setpoints(3));
    let mut run = ControllerState::default();
    assert_eq!(
        c.advance(&mut run, 0.175, false).0,
        [0.5, 0.5, 0.0, 0.0, 0.0, 0.0]
    );
    run.manual_setpoint = Some(Setpoint::Release);
    assert_eq!(
        c.advance(&mut run, 0.0, false).0,
        [0.0, 0.0, 0.0, 1.0, 0.0, 0.0]
    );
    // The state machine keeps running underneath.
    assert_eq!(run.state, GraspState::Closing);
}

#[test]
fn a_controller_fitted_to_a_synthetic_example_round_trips_through_its_file() {
    use prehensile_control::{fit_controller, ControllerFile, Motion};
    let hand = prehensile_formats::builtin_hand("robot3").unwrap();
    let n = hand.dof_count();
    let open = vec![0.0; n];
    let closed: Vec<f64> = (0..n).map(|k| 0.6 + 0.05 * k as f64).collect();
    let relaxed: Vec<f64> = closed.iter().map(|c| 0.3 * c).collect();
    let g = Gains::grasp();
    let motion = Motion::synthetic_grasp(hand.dof_names(), &relaxed, &open, &closed, &g);
    let base = BaseMotion::at_rest(Vec3::new(0.0, 0.0, -9.81));
    let c = fit_controller(&hand, &motion, g, true, &base).unwrap();
    // Held still in GRIPPING, passive (toward neutral) and active (toward the grip setpoint's
    // equilibrium θ_S + k_D/k_S θ̇_S) balance at their mean: that is the example's closed pose,
    // within the dynamics the least squares absorbs.
    for (k, target) in closed.iter().enumerate() {
        let grip = c.setpoints.positions[Setpoint::Grip][k]
            + g.k_d / g.k_s * c.setpoints.velocities[Setpoint::Grip][k];
        let rest = (grip + c.setpoints.neutral[k]) / 2.0;
        assert!((rest - target).abs() < 0.15, "dof {k}: {rest} vs {target}");
    }
    let text = ControllerFile::new(&hand, &c).to_toml();
    let back = ControllerFile::from_toml(&text, "test")
        .unwrap()
        .controller(&hand)
        .unwrap();
    assert_eq!(back.setpoints, c.setpoints);
    assert!(back.open_while_closing);
    // Bad files say what is wrong.
    let broken = text.replace("name = \"grip\"", "name = \"squeeze\"");
    let e = ControllerFile::from_toml(&broken, "t")
        .unwrap()
        .controller(&hand)
        .unwrap_err();
    assert!(e.to_string().contains("setpoints"), "{e}");
    let other = prehensile_formats::builtin_hand("human").unwrap();
    assert!(ControllerFile::from_toml(&text, "t")
        .unwrap()
        .controller(&other)
        .is_err());
    let mut bad = motion.clone();
    bad.frames[5][0] = f64::NAN;
    let e = fit_controller(&hand, &bad, g, true, &base).unwrap_err();
    assert!(e.to_string().contains("frame 5"), "{e}");
}
