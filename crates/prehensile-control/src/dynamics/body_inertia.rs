//! A body's inertia as ten numbers (mass, first moment, rotational inertia), moved between link
//! frames and summed by the composite-rigid-body algorithm (Featherstone, *Rigid Body Dynamics
//! Algorithms*, §2.13 and §6.2); and the outboard inertia of every joint that the controller
//! scales its torques by.

use nalgebra::{Matrix3, Matrix6};
use prehensile_core::hand::Inertial;
use prehensile_core::math::Vec3;

/// A body's inertia about a frame's origin, in that frame: mass, first moment (mass times
/// centre of mass) and rotational inertia (Featherstone §2.13's rigid-body inertia). Ten numbers
/// instead of a 6×6 spatial inertia: moving one to the parent's frame costs a few 3×3 products
/// rather than two 6×6 ones, which matters because the simulation sums them every step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BodyInertia {
    mass: f64,
    moment: Vec3,
    pub rotational: Matrix3<f64>,
}

impl BodyInertia {
    pub(crate) fn zero() -> Self {
        Self {
            mass: 0.0,
            moment: Vec3::zeros(),
            rotational: Matrix3::zeros(),
        }
    }

    /// A bone's own mass properties, about its frame origin.
    pub(crate) fn of(inertial: &Inertial) -> Self {
        let c = inertial.center_of_mass.coords.cross_matrix();
        Self {
            mass: inertial.mass,
            moment: inertial.center_of_mass.coords * inertial.mass,
            rotational: inertial.inertia - c * c * inertial.mass,
        }
    }

    /// The same inertia about the parent's origin in the parent's frame, for a link turned by
    /// `to_bone` (parent→link) with its origin at `origin` in the parent's frame: rotate, then
    /// shift by the parallel-axis theorem written with the first moment (so massless links
    /// need no division).
    pub(crate) fn in_parent(&self, to_bone: &Matrix3<f64>, origin: &Vec3) -> Self {
        let moment = to_bone.transpose() * self.moment;
        // −m[r]×² − [r]×[h]× − [h]×[r]×, with [a]×[b]× = b·aᵀ − (a·b)·1.
        let (r, m) = (origin, self.mass);
        let shift = Matrix3::from_diagonal_element(m * r.norm_squared() + 2.0 * r.dot(&moment))
            - r * (r * m + moment).transpose()
            - moment * r.transpose();
        Self {
            mass: m,
            moment: moment + r * m,
            rotational: to_bone.tr_mul(&(self.rotational * to_bone)) + shift,
        }
    }

    /// The 6×6 spatial inertia, `[ω; v]` order.
    pub(crate) fn spatial(&self) -> Matrix6<f64> {
        let h = self.moment.cross_matrix();
        let mut s = Matrix6::zeros();
        s.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.rotational);
        s.fixed_view_mut::<3, 3>(0, 3).copy_from(&h);
        s.fixed_view_mut::<3, 3>(3, 0).copy_from(&h.transpose());
        s.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(Matrix3::identity() * self.mass));
        s
    }

    pub(crate) fn add(&mut self, other: &Self) {
        self.mass += other.mass;
        self.moment += other.moment;
        self.rotational += other.rotational;
    }
}

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
