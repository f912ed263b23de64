//! The outboard inertia of every joint, Pollard & Zordan's `I` (Eq. 3, 5), from the composite
//! inertias alone, without the rest of the mass matrix (the simulation needs it every step).

use nalgebra::Matrix3;
use prehensile_core::math::Vec3;
use prehensile_core::HandModel;

use crate::dynamics_model::{DynamicsData, DynamicsModel};
use crate::inverse_dynamics::DynamicsError;
use crate::mass_matrix::composite_inertias;

/// The outboard inertia of every joint: for a hinge the inertia of all bodies outboard of it
/// about its axis (the diagonal of M), for a ball joint the 3×3 block of M (their inertia about
/// the joint, in the bone's frame).
#[derive(Debug, Clone, PartialEq)]
pub struct OutboardInertia {
    /// Per degree of freedom, the diagonal of M: a hinge's whole `I`.
    pub diagonal: Vec<f64>,
    /// Every ball joint's first degree of freedom and its 3×3 block.
    pub balls: Vec<(usize, Matrix3<f64>)>,
}

impl OutboardInertia {
    /// Turns torques per unit inertia `u` (the control laws' bracketed terms) into joint torques
    /// `I·u`, in place, each ball joint's block applied whole.
    pub fn apply(&self, u: &mut [f64]) {
        for (first, block) in &self.balls {
            let turned = block * Vec3::from_column_slice(&u[*first..first + 3]);
            u[*first..first + 3].copy_from_slice(turned.as_slice());
        }
        for (k, (u, i)) in u.iter_mut().zip(&self.diagonal).enumerate() {
            if !self.in_ball(k) {
                *u *= i;
            }
        }
    }

    /// Whether degree of freedom `k` belongs to a ball joint.
    pub fn in_ball(&self, k: usize) -> bool {
        self.balls
            .iter()
            .any(|(first, _)| (*first..first + 3).contains(&k))
    }

    /// `I⁻¹·τ`: the torques per unit inertia that give joint torques `tau` (a ball joint's block
    /// is positive definite whenever its bone has mass).
    pub fn solve(&self, tau: &[f64]) -> Vec<f64> {
        let mut u: Vec<f64> = self.diagonal.iter().zip(tau).map(|(i, t)| t / i).collect();
        for (first, block) in &self.balls {
            let t = Vec3::from_column_slice(&tau[*first..first + 3]);
            if let Some(x) = block.cholesky().map(|c| c.solve(&t)) {
                u[*first..first + 3].copy_from_slice(x.as_slice());
            }
        }
        u
    }
}

/// The outboard inertia of every joint at pose `q`, written into `data` and returned from it.
pub fn outboard_inertia_into<'d>(
    model: &DynamicsModel,
    data: &'d mut DynamicsData,
    q: &[f64],
) -> Result<&'d OutboardInertia, DynamicsError> {
    composite_inertias(model, data, q)?;
    let mut ball = 0;
    for (link, inertia) in model.links().iter().zip(&data.composite) {
        // A hinge's motion subspace is its axis, turning only.
        if let Some(d) = link.dof {
            data.outboard.diagonal[d] = link.axis.dot(&(inertia.rotational * link.axis));
        }
        // The three links of a ball joint share the bone's frame and only the last has mass,
        // so the last one's composite inertia is the whole joint's; its axes are the bone's.
        if link.ball.is_some() {
            data.outboard.balls[ball].1 = inertia.rotational;
            ball += 1;
        }
    }
    Ok(&data.outboard)
}

/// The outboard inertia of every joint of `hand` at pose `q`. Builds the hand's
/// [`DynamicsModel`] on every call: loops should keep one and call [`outboard_inertia_into`].
pub fn outboard_inertia(hand: &HandModel, q: &[f64]) -> Result<OutboardInertia, DynamicsError> {
    let model = DynamicsModel::new(hand);
    let mut data = model.data();
    outboard_inertia_into(&model, &mut data, q).cloned()
}
