//! Forward dynamics without contact: q̈ = M(q)⁻¹ (τ − b(q, q̇)), with the bias b (gravity,
//! Coriolis, base motion) from inverse dynamics at zero acceleration. A reference integrator for
//! tests and fitting; the simulation with contacts belongs to a physics engine.

use nalgebra::DVector;
use prehensile_core::HandModel;

use crate::inverse_dynamics::{inverse_dynamics_moving_base, BaseMotion, DynamicsError};
use crate::mass_matrix::mass_matrix;

/// Joint accelerations under torques `tau`.
pub fn forward_dynamics(
    hand: &HandModel,
    q: &[f64],
    qd: &[f64],
    tau: &[f64],
    base: &BaseMotion,
) -> Result<DVector<f64>, DynamicsError> {
    let zero = vec![0.0; hand.dof_count()];
    let bias = inverse_dynamics_moving_base(hand, q, qd, &zero, base)?;
    let m = mass_matrix(hand, q)?;
    let rhs = DVector::from_column_slice(tau) - bias;
    m.cholesky()
        .map(|c| c.solve(&rhs))
        .ok_or(DynamicsError::NonFinite(
            "mass matrix (not positive definite: a moving bone without mass?)",
        ))
}
