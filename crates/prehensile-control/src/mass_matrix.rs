//! The joint-space mass matrix by the composite-rigid-body algorithm (Featherstone, *Rigid Body
//! Dynamics Algorithms*, §6.2): composite inertias summed as rigid-body inertias, forces
//! carried inboard with 6×6 spatial transforms in each bone's frame, `[ω; v]` order.

use nalgebra::{DMatrix, Matrix3, Matrix6, Vector6};
use prehensile_core::hand::Inertial;
use prehensile_core::math::Vec3;
use prehensile_core::HandModel;

use crate::inverse_dynamics::{check, links, DynamicsError, Link};

fn skew(v: &Vec3) -> Matrix3<f64> {
    v.cross_matrix()
}

/// Spatial motion transform from the parent's frame to the bone's: rotation `e` (parent→bone),
/// bone origin `r` in the parent frame.
fn motion_transform(e: &Matrix3<f64>, r: &Vec3) -> Matrix6<f64> {
    let mut x = Matrix6::zeros();
    x.fixed_view_mut::<3, 3>(0, 0).copy_from(e);
    x.fixed_view_mut::<3, 3>(3, 3).copy_from(e);
    x.fixed_view_mut::<3, 3>(3, 0).copy_from(&(-e * skew(r)));
    x
}

/// A body's inertia about a frame's origin, in that frame: mass, first moment (mass times
/// centre of mass) and rotational inertia (Featherstone §2.13's rigid-body inertia). Ten numbers
/// instead of a 6×6 spatial inertia: moving one to the parent's frame costs a few 3×3 products
/// rather than two 6×6 ones, which matters because the simulation sums them every step.
#[derive(Debug, Clone, Copy)]
struct BodyInertia {
    mass: f64,
    moment: Vec3,
    rotational: Matrix3<f64>,
}

impl BodyInertia {
    fn zero() -> Self {
        Self {
            mass: 0.0,
            moment: Vec3::zeros(),
            rotational: Matrix3::zeros(),
        }
    }

    /// A bone's own mass properties, about its frame origin.
    fn of(inertial: &Inertial) -> Self {
        let c = skew(&inertial.center_of_mass.coords);
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
    fn in_parent(&self, to_bone: &Matrix3<f64>, origin: &Vec3) -> Self {
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
    fn spatial(&self) -> Matrix6<f64> {
        let h = skew(&self.moment);
        let mut s = Matrix6::zeros();
        s.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.rotational);
        s.fixed_view_mut::<3, 3>(0, 3).copy_from(&h);
        s.fixed_view_mut::<3, 3>(3, 0).copy_from(&h.transpose());
        s.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(Matrix3::identity() * self.mass));
        s
    }

    fn add(&mut self, other: &Self) {
        self.mass += other.mass;
        self.moment += other.moment;
        self.rotational += other.rotational;
    }
}

/// The links of a hand at one pose and the composite inertia of each link's subtree about its
/// frame origin, in its frame (Featherstone's CRBA, first pass).
fn composite_inertias(
    hand: &HandModel,
    q: &[f64],
) -> Result<(Vec<Link>, Vec<BodyInertia>), DynamicsError> {
    check(hand, &[("q", q)])?;
    let links = links(hand, q)?;
    let mut composite: Vec<BodyInertia> = links
        .iter()
        .map(|l| {
            l.inertial
                .as_ref()
                .map_or(BodyInertia::zero(), BodyInertia::of)
        })
        .collect();
    for i in (0..links.len()).rev() {
        if let Some(p) = links[i].parent {
            let moved = composite[i].in_parent(&links[i].to_bone, &links[i].origin);
            composite[p].add(&moved);
        }
    }
    Ok((links, composite))
}

/// The motion subspace of a link's degree of freedom (a hinge about its axis).
fn subspace(link: &Link) -> Vector6<f64> {
    let a = link.axis;
    Vector6::new(a.x, a.y, a.z, 0.0, 0.0, 0.0)
}

/// M(q): torques per unit joint acceleration, symmetric. A ball joint's 3×3 block is the inertia
/// of everything outboard of it about the joint, in the bone's frame (the paper's `I` for a
/// ball joint; see [`crate::inverse_dynamics`] for its coordinates).
pub fn mass_matrix(hand: &HandModel, q: &[f64]) -> Result<DMatrix<f64>, DynamicsError> {
    let (links, composite) = composite_inertias(hand, q)?;
    let transforms: Vec<Matrix6<f64>> = links
        .iter()
        .map(|l| motion_transform(&l.to_bone, &l.origin))
        .collect();
    let mut m = DMatrix::zeros(hand.dof_count(), hand.dof_count());
    for i in 0..links.len() {
        let Some(di) = links[i].dof else { continue };
        let mut force = composite[i].spatial() * subspace(&links[i]);
        m[(di, di)] = subspace(&links[i]).dot(&force);
        let mut j = i;
        while let Some(p) = links[j].parent {
            force = transforms[j].transpose() * force;
            j = p;
            if let Some(dj) = links[j].dof {
                let value = subspace(&links[j]).dot(&force);
                m[(di, dj)] = value;
                m[(dj, di)] = value;
            }
        }
    }
    Ok(m)
}

/// The outboard inertia of every joint, Pollard & Zordan's `I` (Eq. 3, 5): for a hinge the
/// inertia of all bodies outboard of it about its axis (the diagonal of M), for a ball joint the
/// 3×3 block of M (their inertia about the joint, in the bone's frame).
#[derive(Debug, Clone, PartialEq)]
pub struct OutboardInertia {
    /// Per degree of freedom, the diagonal of M: a hinge's whole `I`.
    pub diagonal: Vec<f64>,
    /// Every ball joint's first degree of freedom and its 3×3 block.
    pub balls: Vec<(usize, Matrix3<f64>)>,
}

impl OutboardInertia {
    /// `I·u`: joint torques from torques per unit inertia `u` (the control laws' bracketed
    /// terms), each ball joint's block applied whole.
    pub fn times(&self, u: &[f64]) -> Vec<f64> {
        let mut tau: Vec<f64> = self.diagonal.iter().zip(u).map(|(i, u)| i * u).collect();
        for (first, block) in &self.balls {
            let t = block * Vec3::from_column_slice(&u[*first..first + 3]);
            tau[*first..first + 3].copy_from_slice(t.as_slice());
        }
        tau
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

    /// `I·u` minus its diagonal part: the cross terms of the ball joints' blocks (zero for
    /// hinges). A simulation that integrates each degree of freedom's diagonal spring implicitly
    /// adds these as torques.
    pub fn coupling(&self, u: &[f64]) -> Vec<f64> {
        let mut tau = self.times(u);
        for ((t, i), u) in tau.iter_mut().zip(&self.diagonal).zip(u) {
            *t -= i * u;
        }
        tau
    }
}

/// The outboard inertia of every joint at pose `q` (see [`OutboardInertia`]). Computed from the
/// composite inertias alone, without the rest of M (the simulation calls it every step).
pub fn outboard_inertia(hand: &HandModel, q: &[f64]) -> Result<OutboardInertia, DynamicsError> {
    let (links, composite) = composite_inertias(hand, q)?;
    let mut diagonal = vec![0.0; hand.dof_count()];
    let mut balls = Vec::new();
    for (link, inertia) in links.iter().zip(&composite) {
        // A hinge's motion subspace is its axis, turning only.
        if let Some(d) = link.dof {
            diagonal[d] = link.axis.dot(&(inertia.rotational * link.axis));
        }
        // The three links of a ball joint share the bone's frame and only the last has mass,
        // so the last one's composite inertia is the whole joint's; its axes are the bone's.
        if let Some(first) = link.ball {
            balls.push((first, inertia.rotational));
        }
    }
    Ok(OutboardInertia { diagonal, balls })
}
