//! Active setpoints from an example motion by least squares (Pollard & Zordan §5.1, Eq. 13–14):
//! each frame gives, per degree of freedom, k_S·B·P_S + k_D·B·P_D = k_S θ + k_D θ̇ +
//! I⁻¹(τ − τ_G − τ_ARM − τ_P), with τ from inverse dynamics of the motion.
//!
//! Only the combination k_S·P_S + k_D·P_D of each setpoint enters these equations, so the system
//! is rank-deficient; we take the minimum-norm least-squares solution (SVD), which splits each
//! combination between position and velocity in proportion k_S : k_D. Setpoints whose blend
//! weight is zero in every frame stay (numerically) zero.

use nalgebra::DMatrix;
use prehensile_core::HandModel;

use crate::controller::{passive_torque, Gains, Setpoints};
use crate::inverse_dynamics::{inverse_dynamics_moving_base, BaseMotion, DynamicsError};
use crate::mass_matrix::outboard_inertia;

/// Fits `positions` and `velocities` of `setpoints` (its neutral pose and limits are used as
/// given) to frames `q` sampled every `dt` seconds, with the blend weights of each frame and the
/// base's motion. Frames at both ends are used only for differences.
pub fn fit_active(
    hand: &HandModel,
    q: &[Vec<f64>],
    dt: f64,
    blends: &[[f64; 6]],
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
    for t in 1..q.len() - 1 {
        let qd: Vec<f64> = (0..n)
            .map(|k| (q[t + 1][k] - q[t - 1][k]) / (2.0 * dt))
            .collect();
        let qdd: Vec<f64> = (0..n)
            .map(|k| (q[t + 1][k] - 2.0 * q[t][k] + q[t - 1][k]) / (dt * dt))
            .collect();
        let tau = inverse_dynamics_moving_base(hand, &q[t], &qd, &qdd, base)?;
        let zero = vec![0.0; n];
        let compensation = inverse_dynamics_moving_base(hand, &q[t], &zero, &zero, base)?;
        let inertia = outboard_inertia(hand, &q[t])?;
        let passive = passive_torque(&inertia, &q[t], &qd, setpoints, gains);
        for j in 0..6 {
            a[(t - 1, j)] = gains.k_s * blends[t][j];
            a[(t - 1, 6 + j)] = gains.k_d * blends[t][j];
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
    for j in 0..6 {
        for k in 0..n {
            setpoints.positions[j][k] = x[(j, k)];
            setpoints.velocities[j][k] = x[(6 + j, k)];
        }
    }
    Ok(())
}
