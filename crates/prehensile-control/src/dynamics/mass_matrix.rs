//! The joint-space mass matrix by the composite-rigid-body algorithm (Featherstone, *Rigid Body
//! Dynamics Algorithms*, §6.2): composite inertias summed as rigid-body inertias, forces
//! carried inboard with 6×6 spatial transforms in each bone's frame, `[ω; v]` order.

use nalgebra::{DMatrix, Matrix3, Matrix6, Vector6};
use prehensile_core::math::Vec3;
use prehensile_core::HandModel;

use crate::dynamics::body_inertia::BodyInertia;
use crate::dynamics::model::{DynamicsData, DynamicsModel, Link};
use crate::error::DynamicsError;

/// Spatial motion transform from the parent's frame to the bone's: rotation `e` (parent→bone),
/// bone origin `r` in the parent frame.
fn motion_transform(e: &Matrix3<f64>, r: &Vec3) -> Matrix6<f64> {
    let mut x = Matrix6::zeros();
    x.fixed_view_mut::<3, 3>(0, 0).copy_from(e);
    x.fixed_view_mut::<3, 3>(3, 3).copy_from(e);
    x.fixed_view_mut::<3, 3>(3, 0)
        .copy_from(&(-e * r.cross_matrix()));
    x
}

/// Writes into `data` the links' rotations at `q` and the composite inertia of each link's
/// subtree about its frame origin, in its frame (Featherstone's CRBA, first pass).
pub(crate) fn composite_inertias(
    model: &DynamicsModel,
    data: &mut DynamicsData,
    q: &[f64],
) -> Result<(), DynamicsError> {
    model.place(data, q)?;
    let links = model.links();
    for (link, composite) in links.iter().zip(&mut data.composite) {
        *composite = link
            .inertial
            .as_ref()
            .map_or(BodyInertia::zero(), BodyInertia::of);
    }
    for i in (0..links.len()).rev() {
        if let Some(p) = links[i].parent {
            let moved = data.composite[i].in_parent(&data.to_bone[i], &links[i].origin);
            data.composite[p].add(&moved);
        }
    }
    Ok(())
}

/// The motion subspace of a link's degree of freedom (a hinge about its axis).
fn subspace(link: &Link) -> Vector6<f64> {
    let a = link.axis;
    Vector6::new(a.x, a.y, a.z, 0.0, 0.0, 0.0)
}

/// M(q), torques per unit joint acceleration, symmetric, written into `data` and returned from
/// it. A ball joint's 3×3 block is the inertia of everything outboard of it about the joint, in
/// the bone's frame (the paper's `I` for a ball joint; see [`crate::rnea`] for its coordinates).
pub fn crba<'d>(
    model: &DynamicsModel,
    data: &'d mut DynamicsData,
    q: &[f64],
) -> Result<&'d DMatrix<f64>, DynamicsError> {
    composite_inertias(model, data, q)?;
    let links = model.links();
    data.mass.fill(0.0);
    for i in 0..links.len() {
        let Some(di) = links[i].dof else { continue };
        let mut force = data.composite[i].spatial() * subspace(&links[i]);
        data.mass[(di, di)] = subspace(&links[i]).dot(&force);
        let mut j = i;
        while let Some(p) = links[j].parent {
            force = motion_transform(&data.to_bone[j], &links[j].origin).transpose() * force;
            j = p;
            if let Some(dj) = links[j].dof {
                let value = subspace(&links[j]).dot(&force);
                data.mass[(di, dj)] = value;
                data.mass[(dj, di)] = value;
            }
        }
    }
    Ok(&data.mass)
}

/// M(q) of `hand` (see [`crba`]). Builds the hand's [`DynamicsModel`] on every call: loops should
/// keep one and call [`crba`].
pub fn mass_matrix(hand: &HandModel, q: &[f64]) -> Result<DMatrix<f64>, DynamicsError> {
    let model = DynamicsModel::new(hand);
    let mut data = model.data();
    crba(&model, &mut data, q).cloned()
}
