//! The joint-space mass matrix, column by column from inverse dynamics with unit accelerations
//! (no gravity, no velocity): exact, O(n²) inverse-dynamics passes. The composite-rigid-body
//! algorithm (O(n²) flops in one pass) is the planned faster replacement.

use nalgebra::DMatrix;
use prehensile_core::math::Vec3;
use prehensile_core::HandModel;

use crate::inverse_dynamics::{inverse_dynamics, DynamicsError};

/// M(q): torques per unit joint acceleration, symmetric.
pub fn mass_matrix(hand: &HandModel, q: &[f64]) -> Result<DMatrix<f64>, DynamicsError> {
    let n = hand.dof_count();
    let zero = vec![0.0; n];
    let mut m = DMatrix::zeros(n, n);
    let mut unit = vec![0.0; n];
    for j in 0..n {
        unit[j] = 1.0;
        let column = inverse_dynamics(hand, q, &zero, &unit, Vec3::zeros())?;
        m.set_column(j, &column);
        unit[j] = 0.0;
    }
    Ok(m)
}

/// The outboard inertia of every degree of freedom about its joint (the diagonal of M): the
/// inertia of all bodies outboard of a hinge about its axis, Pollard & Zordan's `I` (Eq. 3, 5).
pub fn outboard_inertia(hand: &HandModel, q: &[f64]) -> Result<Vec<f64>, DynamicsError> {
    let m = mass_matrix(hand, q)?;
    Ok((0..m.nrows()).map(|i| m[(i, i)]).collect())
}
