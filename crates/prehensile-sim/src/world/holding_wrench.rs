//! The compensation τG + τARM of Pollard & Zordan (Eq. 2) as one wrench per body: the force and
//! torque that keep a body moving rigidly with the palm (and, for τG, hold it against gravity)
//! when no joint works. Summed through the joints' Jacobians these wrenches are exactly the
//! inverse dynamics with the joints held still, `inverse_dynamics_moving_base(q, 0, 0, base)`
//! (tested to 1e-9), so the fingers move as under the paper's joint torques.
//!
//! Why wrenches rather than the joint torques themselves: an iterative constraint solver must
//! pass a joint torque through every joint of the chain, and with a few iterations per step it
//! does not (measured with rapier 0.36 at 4 iterations: the metacarpophalangeal joints still
//! sagged 0.2–0.5 rad under fully compensated gravity). A wrench acts on its own body and needs
//! no joint to carry it.

use nalgebra::Matrix3;
use prehensile_core::math::{Point3, Vec3};

/// How a frame moves, world coordinates: its origin's acceleration, angular velocity and angular
/// acceleration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameMotion {
    /// The origin, metres.
    pub origin: Point3,
    /// The origin's acceleration, m/s².
    pub linear_acceleration: Vec3,
    /// rad/s.
    pub angular_velocity: Vec3,
    /// rad/s².
    pub angular_acceleration: Vec3,
}

impl FrameMotion {
    /// A frame at rest at `origin`.
    pub fn at_rest(origin: Point3) -> Self {
        Self {
            origin,
            linear_acceleration: Vec3::zeros(),
            angular_velocity: Vec3::zeros(),
            angular_acceleration: Vec3::zeros(),
        }
    }
}

/// The force (at the centre of mass) and torque that make a body of `mass`, centre of mass
/// `center_of_mass` and inertia `inertia` (about the centre of mass, world axes) move rigidly
/// with `base`, with `gravity` acting on it (pass zero to leave gravity uncompensated).
pub fn holding_wrench(
    mass: f64,
    center_of_mass: &Point3,
    inertia: &Matrix3<f64>,
    base: &FrameMotion,
    gravity: &Vec3,
) -> (Vec3, Vec3) {
    let r = center_of_mass - base.origin;
    let (w, dw) = (base.angular_velocity, base.angular_acceleration);
    let acceleration = base.linear_acceleration + dw.cross(&r) + w.cross(&w.cross(&r));
    let force = mass * (acceleration - gravity);
    let torque = inertia * dw + w.cross(&(inertia * w));
    (force, torque)
}
