//! The outboard inertia of every joint, Pollard & Zordan's `I` (Eq. 3, 5), from the composite
//! inertias alone, without the rest of the mass matrix (the simulation needs it every step).

use prehensile_core::HandModel;

use crate::dynamics::body_inertia::OutboardInertia;
use crate::dynamics::mass_matrix::composite_inertias;
use crate::dynamics::model::{DynamicsData, DynamicsModel};
use crate::error::DynamicsError;

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
