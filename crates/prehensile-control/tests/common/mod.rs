//! Helpers shared by the integration tests.

use prehensile_control::{
    forward_dynamics, BaseMotion, Blend, ControllerState, DynamicsModel, GraspController,
    GraspState,
};
use prehensile_core::HandModel;

/// A recorded motion: its step, every step's angles and blend, and the last angles.
pub struct Motion {
    pub dt: f64,
    pub frames: Vec<Vec<f64>>,
    pub blends: Vec<Blend>,
    pub last: Vec<f64>,
}

/// A motion the fitting tests recover a controller from: `controller`, in state Opening, drives
/// `hand` from `start` by forward dynamics for 0.25 s in steps of 0.5 ms, while the object comes
/// from 30 cm to 5 cm so that the state stays Opening throughout. `advance(q, qd, dt)` turns the
/// angles by the updated rates.
pub fn opening_motion(
    hand: &HandModel,
    controller: &GraspController,
    base: &BaseMotion,
    start: &[f64],
    advance: impl Fn(&mut [f64], &[f64], f64),
) -> Motion {
    let (dt, steps) = (5e-4, 500);
    let (mut q, mut qd) = (start.to_vec(), vec![0.0; start.len()]);
    let (mut frames, mut blends) = (Vec::new(), Vec::new());
    let model = DynamicsModel::new(hand);
    let mut data = model.data();
    let mut tau = vec![0.0; start.len()];
    let mut run = ControllerState {
        state: GraspState::Opening,
        manual_setpoint: None,
    };
    for s in 0..steps {
        let distance = 0.3 - 0.25 * s as f64 / steps as f64;
        controller
            .torques(
                &mut run, &model, &mut data, &q, &qd, base, distance, false, true, &mut tau,
            )
            .unwrap();
        assert_eq!(run.state, GraspState::Opening);
        frames.push(q.clone());
        blends.push(GraspState::Opening.blend(distance, 0.0, &controller.gains));
        let qdd = forward_dynamics(&model, &mut data, &q, &qd, &tau, base).unwrap();
        for k in 0..qd.len() {
            qd[k] += dt * qdd[k];
        }
        advance(&mut q, &qd, dt);
    }
    Motion {
        dt,
        frames,
        blends,
        last: q,
    }
}
