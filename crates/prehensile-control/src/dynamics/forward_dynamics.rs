//! Forward dynamics without contact: q̈ = M(q)⁻¹ (τ − b(q, q̇)), with the bias b (gravity,
//! Coriolis, base motion) from inverse dynamics at zero acceleration. A reference integrator for
//! tests and fitting; the simulation with contacts belongs to a physics engine.

use nalgebra::DVector;

use crate::dynamics::inverse_dynamics::{velocity_bias, BaseMotion};
use crate::dynamics::mass_matrix::crba;
use crate::dynamics::model::{DynamicsData, DynamicsModel};
use crate::error::DynamicsError;

/// Joint accelerations under torques `tau`.
pub fn forward_dynamics(
    model: &DynamicsModel,
    data: &mut DynamicsData,
    q: &[f64],
    qd: &[f64],
    tau: &[f64],
    base: &BaseMotion,
) -> Result<DVector<f64>, DynamicsError> {
    model.check(&[("tau", tau)])?;
    let rhs = DVector::from_column_slice(tau)
        - DVector::from_column_slice(velocity_bias(model, data, q, qd, base)?);
    crba(model, data, q)?
        .clone()
        .cholesky()
        .map(|c| c.solve(&rhs))
        .ok_or(DynamicsError::NonFinite(
            "mass matrix (not positive definite: a moving bone without mass?)",
        ))
}
