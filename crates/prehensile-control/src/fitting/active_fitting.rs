//! Active setpoints from an example motion by least squares (Pollard & Zordan §5.1, Eq. 13–14):
//! each frame gives, per degree of freedom, k_S·B·P_S + k_D·B·P_D = k_S θ + k_D θ̇ +
//! I⁻¹(τ − τ_G − τ_ARM − τ_P), with τ from inverse dynamics of the motion.
//!
//! Only the combination k_S·P_S + k_D·P_D of each setpoint enters these equations, so the system
//! is rank-deficient; we take the minimum-norm least-squares solution (SVD), which splits each
//! combination between position and velocity in proportion k_S : k_D. Setpoints whose blend
//! weight is zero in every frame stay (numerically) zero.

use nalgebra::DMatrix;
use prehensile_core::hand::Joint;
use prehensile_core::math::{Rotation, Vec3};
use prehensile_core::HandModel;

use crate::controller::setpoint::{Blend, Setpoint};
use crate::controller::torque_laws::{passive_torque, Gains, Setpoints};
use crate::dynamics::inverse_dynamics::{bias_torques, rnea, BaseMotion};
use crate::dynamics::model::DynamicsModel;
use crate::dynamics::outboard_inertia::outboard_inertia_into;
use crate::error::DynamicsError;

/// Fits `positions` and `velocities` of `setpoints` (its neutral pose and limits are used as
/// given) to frames `q` sampled every `dt` seconds, with the blend weights of each frame and the
/// base's motion. Frames at both ends are used only for differences.
pub fn fit_active(
    hand: &HandModel,
    q: &[Vec<f64>],
    dt: f64,
    blends: &[Blend],
    base: &BaseMotion,
    gains: &Gains,
    setpoints: &mut Setpoints,
) -> Result<(), DynamicsError> {
    let n = hand.dof_count();
    if q.len() < 3 || blends.len() != q.len() {
        return Err(DynamicsError::Length {
            what: "motion frames (at least 3, one blend each)",
            got: q.len(),
            expected: blends.len(),
        });
    }
    if !(dt.is_finite() && dt > 0.0) {
        return Err(DynamicsError::NonFinite("frame time"));
    }
    let frames = q.len() - 2;
    let mut a = DMatrix::zeros(frames, 12);
    let mut b = DMatrix::zeros(frames, n);
    let model = DynamicsModel::new(hand);
    let mut data = model.data();
    let mut passive = vec![0.0; n];
    for t in 1..q.len() - 1 {
        let (qd, qdd) = rates(hand, [&q[t - 1], &q[t], &q[t + 1]], dt);
        let tau = rnea(&model, &mut data, &q[t], &qd, &qdd, base)?.to_vec();
        let compensation = bias_torques(&model, &mut data, &q[t], base)?.to_vec();
        let inertia = outboard_inertia_into(&model, &mut data, &q[t])?;
        passive_torque(inertia, &q[t], &qd, setpoints, gains, &mut passive);
        for (s, b) in blends[t].iter() {
            a[(t - 1, s.index())] = gains.k_s * b;
            a[(t - 1, 6 + s.index())] = gains.k_d * b;
        }
        let driving: Vec<f64> = (0..n)
            .map(|k| tau[k] - compensation[k] - passive[k])
            .collect();
        let unit = inertia.solve(&driving);
        for k in 0..n {
            b[(t - 1, k)] = gains.k_s * q[t][k] + gains.k_d * qd[k] + unit[k];
        }
    }
    let svd = a.svd(true, true);
    let x = svd
        .solve(&b, 1e-12)
        .map_err(|_| DynamicsError::NonFinite("least-squares system"))?;
    for s in Setpoint::ALL {
        let j = s.index();
        for k in 0..n {
            setpoints.positions[s][k] = x[(j, k)];
            setpoints.velocities[s][k] = x[(6 + j, k)];
        }
    }
    Ok(())
}

/// Joint rates and accelerations at the middle of three frames `dt` apart, by central
/// differences. A ball joint's rates are the bone-frame angular velocity the dynamics use, not the
/// rate of its rotation vector (they differ by a tenth and more at a few tenths of a radian):
/// ω = log(R₀⁻¹ R₂) / 2dt, and its acceleration the change of the half-step velocities.
fn rates(hand: &HandModel, [before, now, after]: [&[f64]; 3], dt: f64) -> (Vec<f64>, Vec<f64>) {
    let mut qd: Vec<f64> = (0..now.len())
        .map(|k| (after[k] - before[k]) / (2.0 * dt))
        .collect();
    let mut qdd: Vec<f64> = (0..now.len())
        .map(|k| (after[k] - 2.0 * now[k] + before[k]) / (dt * dt))
        .collect();
    for bone in hand.bones() {
        if !matches!(bone.joint, Joint::Ball { .. }) {
            continue;
        }
        let range = bone.first_dof..bone.first_dof + 3;
        let turn =
            |q: &[f64]| Rotation::from_scaled_axis(Vec3::from_column_slice(&q[range.clone()]));
        let (r0, r1, r2) = (turn(before), turn(now), turn(after));
        let velocity = (r0.inverse() * r2).scaled_axis() / (2.0 * dt);
        let first_half = (r0.inverse() * r1).scaled_axis() / dt;
        let second_half = (r1.inverse() * r2).scaled_axis() / dt;
        qd[range.clone()].copy_from_slice(velocity.as_slice());
        qdd[range.clone()].copy_from_slice(((second_half - first_half) / dt).as_slice());
    }
    (qd, qdd)
}
