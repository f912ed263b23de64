//! Recursive Newton–Euler inverse dynamics (Featherstone, *Rigid Body Dynamics Algorithms*,
//! §5.3), in each bone's own frame, with gravity entered as an upward acceleration of the fixed
//! base. Written by hand: no Rust crate computes dynamics on our hand model's bone tree.

use nalgebra::DVector;
use prehensile_core::math::Vec3;
use prehensile_core::HandModel;

use crate::dynamics::model::{DynamicsData, DynamicsModel};
use crate::error::DynamicsError;

/// What three hinges about x, y, z in series add to the angular acceleration of a body turning
/// at `w` (bone frame) relative to its parent, beyond a spherical joint's: each hinge's rate
/// crossed with the later hinges' axes, w_x w_y e_z − w_x w_z e_y + w_y w_z e_x. Subtracting it
/// makes the three rates the bone's relative angular velocity, whose derivative is the joint
/// acceleration.
fn ball_acceleration_correction(w: &[f64]) -> Vec3 {
    Vec3::new(w[1] * w[2], -w[0] * w[2], w[0] * w[1])
}

/// How the root bone (the base) moves, everything in the root bone's frame: angular velocity,
/// angular acceleration, and the classical linear acceleration of its origin minus gravity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaseMotion {
    /// Angular velocity, rad/s.
    pub angular_velocity: Vec3,
    /// Angular acceleration, rad/s².
    pub angular_acceleration: Vec3,
    /// Linear acceleration of the base origin minus gravity, m/s².
    pub linear_acceleration_minus_gravity: Vec3,
}

impl BaseMotion {
    /// A base at rest under `gravity` (root frame).
    pub fn at_rest(gravity: Vec3) -> Self {
        Self {
            angular_velocity: Vec3::zeros(),
            angular_acceleration: Vec3::zeros(),
            linear_acceleration_minus_gravity: -gravity,
        }
    }
}

/// Joint torques that produce accelerations `qdd` at positions `q` and velocities `qd`, the base
/// moving as `base` (gravity included there): the recursive Newton–Euler algorithm, written into
/// `data` and returned from it, allocating nothing.
///
/// For a ball joint, `q` is its rotation vector (axis × angle, as in Pollard & Zordan), its
/// three entries of `qd` are the bone's angular velocity relative to its parent in the bone's
/// frame, those of `qdd` that velocity's rate, and its torques are about the bone's own axes.
pub fn rnea<'d>(
    model: &DynamicsModel,
    data: &'d mut DynamicsData,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    base: &BaseMotion,
) -> Result<&'d [f64], DynamicsError> {
    model.check(&[("qd", qd), ("qdd", qdd)])?;
    recurse(model, data, q, Some(qd), Some(qdd), base)
}

/// The torques that hold the hand still at `q` against gravity and the base's motion (Pollard &
/// Zordan's τG + τARM, Eq. 2): [`rnea`] with zero rates and accelerations.
pub fn bias_torques<'d>(
    model: &DynamicsModel,
    data: &'d mut DynamicsData,
    q: &[f64],
    base: &BaseMotion,
) -> Result<&'d [f64], DynamicsError> {
    recurse(model, data, q, None, None, base)
}

/// The torques at `q`, `qd` with zero acceleration: gravity, base motion and the velocity
/// products (the bias b of forward dynamics).
pub(crate) fn velocity_bias<'d>(
    model: &DynamicsModel,
    data: &'d mut DynamicsData,
    q: &[f64],
    qd: &[f64],
    base: &BaseMotion,
) -> Result<&'d [f64], DynamicsError> {
    model.check(&[("qd", qd)])?;
    recurse(model, data, q, Some(qd), None, base)
}

/// Newton–Euler with rates `qd` and accelerations `qdd`, each zero when `None`.
fn recurse<'d>(
    model: &DynamicsModel,
    data: &'d mut DynamicsData,
    q: &[f64],
    qd: Option<&[f64]>,
    qdd: Option<&[f64]>,
    base: &BaseMotion,
) -> Result<&'d [f64], DynamicsError> {
    let b = [
        base.angular_velocity,
        base.angular_acceleration,
        base.linear_acceleration_minus_gravity,
    ];
    if !b.iter().all(|v| v.iter().all(|x| x.is_finite())) {
        return Err(DynamicsError::NonFinite("base motion"));
    }
    model.place(data, q)?;
    let links = model.links();
    for (i, l) in links.iter().enumerate() {
        let at = |v: Option<&[f64]>| l.dof.zip(v).map_or(0.0, |(k, v)| v[k]);
        let (rate, accel) = (at(qd), at(qdd));
        let [w, dw, a] = match l.parent {
            // Accelerating the base by -g stands for gravity on every body.
            None => b,
            Some(p) => {
                let [wp, dwp, ap] = data.velocity[p];
                let to_bone = &data.to_bone[i];
                let w = to_bone * wp + l.axis * rate;
                let mut dw = to_bone * dwp + l.axis * accel + w.cross(&(l.axis * rate));
                if let (Some(first), Some(qd)) = (l.ball, qd) {
                    dw -= ball_acceleration_correction(&qd[first..first + 3]);
                }
                let a = to_bone * (ap + dwp.cross(&l.origin) + wp.cross(&wp.cross(&l.origin)));
                [w, dw, a]
            }
        };
        data.velocity[i] = [w, dw, a];
        data.wrench[i] = match l.inertial {
            Some(inertial) => {
                let c = inertial.center_of_mass.coords;
                let ac = a + dw.cross(&c) + w.cross(&w.cross(&c));
                let f = ac * inertial.mass;
                let m = inertial.inertia * dw + w.cross(&(inertial.inertia * w)) + c.cross(&f);
                [f, m]
            }
            None => [Vec3::zeros(); 2],
        };
    }
    data.tau.iter_mut().for_each(|t| *t = 0.0);
    for i in (0..links.len()).rev() {
        let l = &links[i];
        let [f, m] = data.wrench[i];
        if let Some(k) = l.dof {
            data.tau[k] = l.axis.dot(&m);
        }
        if let Some(p) = l.parent {
            let to_parent = data.to_bone[i].transpose();
            let (fi, mi) = (to_parent * f, to_parent * m);
            data.wrench[p][0] += fi;
            data.wrench[p][1] += mi + l.origin.cross(&fi);
        }
    }
    Ok(&data.tau)
}

/// Joint torques that produce accelerations `qdd` at positions `q` and velocities `qd`, with the
/// root bone fixed and `gravity` given in the root bone's frame (m/s²). Builds the hand's
/// [`DynamicsModel`] on every call: loops should keep one and call [`rnea`].
pub fn inverse_dynamics(
    hand: &HandModel,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    gravity: Vec3,
) -> Result<DVector<f64>, DynamicsError> {
    inverse_dynamics_moving_base(hand, q, qd, qdd, &BaseMotion::at_rest(gravity))
}

/// [`inverse_dynamics`] with a moving base (see [`rnea`]).
pub fn inverse_dynamics_moving_base(
    hand: &HandModel,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    base: &BaseMotion,
) -> Result<DVector<f64>, DynamicsError> {
    let model = DynamicsModel::new(hand);
    let mut data = model.data();
    rnea(&model, &mut data, q, qd, qdd, base).map(DVector::from_column_slice)
}

/// Torques that hold the hand still against gravity at positions `q` (see [`bias_torques`]).
pub fn gravity_torques(
    hand: &HandModel,
    q: &[f64],
    gravity: Vec3,
) -> Result<DVector<f64>, DynamicsError> {
    let model = DynamicsModel::new(hand);
    let mut data = model.data();
    bias_torques(&model, &mut data, q, &BaseMotion::at_rest(gravity))
        .map(DVector::from_column_slice)
}
