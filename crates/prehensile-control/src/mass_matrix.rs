//! The joint-space mass matrix by the composite-rigid-body algorithm (Featherstone, *Rigid Body
//! Dynamics Algorithms*, §6.2), with 6×6 spatial inertias in each bone's frame, `[ω; v]` order.

use nalgebra::{DMatrix, Matrix3, Matrix6, Vector6};
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

/// The links of a hand at one pose, with each link's parent→link motion transform and the
/// composite spatial inertia of its subtree about its frame origin (in its frame).
struct Composite {
    links: Vec<Link>,
    transforms: Vec<Matrix6<f64>>,
    inertias: Vec<Matrix6<f64>>,
}

/// The composite inertias of every link (Featherstone's CRBA, first pass).
fn composite_inertias(hand: &HandModel, q: &[f64]) -> Result<Composite, DynamicsError> {
    check(hand, &[("q", q)])?;
    let links = links(hand, q)?;
    // Spatial inertia of each bone about its frame origin.
    let mut composite: Vec<Matrix6<f64>> = links
        .iter()
        .map(|b| {
            let Some(i) = b.inertial else {
                return Matrix6::zeros();
            };
            let c = skew(&i.center_of_mass.coords);
            let mut s = Matrix6::zeros();
            s.fixed_view_mut::<3, 3>(0, 0)
                .copy_from(&(i.inertia + c * c.transpose() * i.mass));
            s.fixed_view_mut::<3, 3>(0, 3).copy_from(&(c * i.mass));
            s.fixed_view_mut::<3, 3>(3, 0)
                .copy_from(&(c.transpose() * i.mass));
            s.fixed_view_mut::<3, 3>(3, 3)
                .copy_from(&(Matrix3::identity() * i.mass));
            s
        })
        .collect();
    let transforms: Vec<Matrix6<f64>> = links
        .iter()
        .map(|l| motion_transform(&l.to_bone, &l.origin))
        .collect();
    for i in (0..links.len()).rev() {
        if let Some(p) = links[i].parent {
            let add = transforms[i].transpose() * composite[i] * transforms[i];
            composite[p] += add;
        }
    }
    Ok(Composite {
        links,
        transforms,
        inertias: composite,
    })
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
    let Composite {
        links,
        transforms,
        inertias: composite,
    } = composite_inertias(hand, q)?;
    let mut m = DMatrix::zeros(hand.dof_count(), hand.dof_count());
    for i in 0..links.len() {
        let Some(di) = links[i].dof else { continue };
        let mut force = composite[i] * subspace(&links[i]);
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

/// The outboard inertia of every degree of freedom about its joint (the diagonal of M): the
/// inertia of all bodies outboard of a hinge about its axis, Pollard & Zordan's `I` (Eq. 3, 5).
/// Computed from the composite inertias alone, without the rest of M (the simulation calls it
/// every step).
pub fn outboard_inertia(hand: &HandModel, q: &[f64]) -> Result<Vec<f64>, DynamicsError> {
    let composite = composite_inertias(hand, q)?;
    let mut diagonal = vec![0.0; hand.dof_count()];
    for (link, inertia) in composite.links.iter().zip(&composite.inertias) {
        if let Some(d) = link.dof {
            diagonal[d] = subspace(link).dot(&(inertia * subspace(link)));
        }
    }
    Ok(diagonal)
}
