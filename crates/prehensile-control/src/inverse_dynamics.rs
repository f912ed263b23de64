//! Recursive Newton–Euler inverse dynamics (Featherstone, *Rigid Body Dynamics Algorithms*,
//! §5.3), in each bone's own frame, with gravity entered as an upward acceleration of the fixed
//! base. Written by hand: no Rust crate computes dynamics on our hand model's bone tree.

use nalgebra::{DVector, Matrix3};
use prehensile_core::hand::{Inertial, Joint};
use prehensile_core::math::{Rotation, Vec3};
use prehensile_core::HandModel;

/// Why dynamics cannot be computed for this hand or state.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// A vector has the wrong length.
    #[error("{what} has {got} entries, the hand has {expected} degrees of freedom")]
    Length {
        /// Which vector.
        what: &'static str,
        /// Its length.
        got: usize,
        /// Degrees of freedom.
        expected: usize,
    },
    /// A number is NaN or infinite.
    #[error("{0} contains a non-finite number")]
    NonFinite(&'static str),
    /// A motion or controller file is malformed (what and where).
    #[error("{0}")]
    Motion(String),
}

/// One link of the dynamics chain. Every hinge bone is one link; a two-axis bone is two hinges
/// in series (outer axis, then a massless link, then the inner axis carrying the bone's mass),
/// exactly its rotation R = R(abduction)·R(flexion). A ball bone is three hinges about its own
/// x, y and z axes at the current rotation (two massless links, then the bone): their rates are
/// the components of the bone's angular velocity relative to its parent, in the bone's frame.
pub(crate) struct Link {
    /// Rotation from the parent link's frame to this link's.
    pub to_bone: Matrix3<f64>,
    /// This link's origin in the parent link's frame.
    pub origin: Vec3,
    /// Joint axis in this link's frame (zero for fixed joints).
    pub axis: Vec3,
    /// Degree of freedom the axis turns, if any.
    pub dof: Option<usize>,
    /// Parent link.
    pub parent: Option<usize>,
    /// Mass properties carried by this link.
    pub inertial: Option<Inertial>,
    /// For the last link of a ball joint, the joint's first degree of freedom: the three hinges
    /// in series add velocity products a single spherical joint does not have (see
    /// [`ball_acceleration_correction`]).
    pub ball: Option<usize>,
}

/// What three hinges about x, y, z in series add to the angular acceleration of a body turning
/// at `w` (bone frame) relative to its parent, beyond a spherical joint's: each hinge's rate
/// crossed with the later hinges' axes, w_x w_y e_z − w_x w_z e_y + w_y w_z e_x. Subtracting it
/// makes the three rates the bone's relative angular velocity, whose derivative is the joint
/// acceleration.
fn ball_acceleration_correction(w: &[f64]) -> Vec3 {
    Vec3::new(w[1] * w[2], -w[0] * w[2], w[0] * w[1])
}

pub(crate) fn links(hand: &HandModel, q: &[f64]) -> Result<Vec<Link>, DynamicsError> {
    let mut out: Vec<Link> = Vec::with_capacity(hand.bones().len() + 8);
    // The link that carries each bone's frame (its last link).
    let mut carrier = vec![0usize; hand.bones().len()];
    for (k, bone) in hand.bones().iter().enumerate() {
        let parent = bone.parent.map(|p| carrier[p]);
        let rotate =
            |axis: &nalgebra::Unit<Vec3>, angle: f64| Rotation::from_axis_angle(axis, angle);
        let to = |r: Rotation| r.to_rotation_matrix().into_inner().transpose();
        match &bone.joint {
            Joint::Fixed => out.push(Link {
                to_bone: to(bone.rest.rotation),
                origin: bone.rest.translation.vector,
                axis: Vec3::zeros(),
                dof: None,
                parent,
                inertial: bone.inertial,
                ball: None,
            }),
            Joint::Hinge(a) => out.push(Link {
                to_bone: to(bone.rest.rotation * rotate(&a.axis, q[bone.first_dof])),
                origin: bone.rest.translation.vector,
                axis: a.axis.into_inner(),
                dof: Some(bone.first_dof),
                parent,
                inertial: bone.inertial,
                ball: None,
            }),
            Joint::TwoAxis { flexion, abduction } => {
                out.push(Link {
                    to_bone: to(bone.rest.rotation * rotate(&abduction.axis, q[bone.first_dof + 1])),
                    origin: bone.rest.translation.vector,
                    axis: abduction.axis.into_inner(),
                    dof: Some(bone.first_dof + 1),
                    parent,
                    inertial: None,
                    ball: None,
                });
                out.push(Link {
                    to_bone: to(rotate(&flexion.axis, q[bone.first_dof])),
                    origin: Vec3::zeros(),
                    axis: flexion.axis.into_inner(),
                    dof: Some(bone.first_dof),
                    parent: Some(out.len() - 1),
                    inertial: bone.inertial,
                    ball: None,
                });
            }
            Joint::Ball { .. } => {
                let turn = bone.joint.rotation(&q[bone.first_dof..bone.first_dof + 3]);
                for (k, axis) in [Vec3::x(), Vec3::y(), Vec3::z()].into_iter().enumerate() {
                    let (to_bone, origin, parent) = if k == 0 {
                        (
                            to(bone.rest.rotation * turn),
                            bone.rest.translation.vector,
                            parent,
                        )
                    } else {
                        (Matrix3::identity(), Vec3::zeros(), Some(out.len() - 1))
                    };
                    out.push(Link {
                        to_bone,
                        origin,
                        axis,
                        dof: Some(bone.first_dof + k),
                        parent,
                        inertial: if k == 2 { bone.inertial } else { None },
                        ball: (k == 2).then_some(bone.first_dof),
                    });
                }
            }
        }
        carrier[k] = out.len() - 1;
    }
    Ok(out)
}

pub(crate) fn check(
    hand: &HandModel,
    vectors: &[(&'static str, &[f64])],
) -> Result<(), DynamicsError> {
    for (what, v) in vectors {
        if v.len() != hand.dof_count() {
            return Err(DynamicsError::Length {
                what,
                got: v.len(),
                expected: hand.dof_count(),
            });
        }
        if !v.iter().all(|x| x.is_finite()) {
            return Err(DynamicsError::NonFinite(what));
        }
    }
    Ok(())
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

/// Joint torques that produce accelerations `qdd` at positions `q` and velocities `qd`, with the
/// root bone fixed and `gravity` given in the root bone's frame (m/s²).
///
/// For a ball joint, `q` is its rotation vector (axis × angle, as in Pollard & Zordan), its
/// three entries of `qd` are the bone's angular velocity relative to its parent in the bone's
/// frame, those of `qdd` that velocity's rate, and its torques are about the bone's own axes.
pub fn inverse_dynamics(
    hand: &HandModel,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    gravity: Vec3,
) -> Result<DVector<f64>, DynamicsError> {
    inverse_dynamics_moving_base(hand, q, qd, qdd, &BaseMotion::at_rest(gravity))
}

/// Inverse dynamics with a moving base: with `qd` and `qdd` zero, the torques that hold the
/// fingers still against gravity and the arm's motion (Pollard & Zordan's τG + τARM, Eq. 2).
pub fn inverse_dynamics_moving_base(
    hand: &HandModel,
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
    base: &BaseMotion,
) -> Result<DVector<f64>, DynamicsError> {
    check(hand, &[("q", q), ("qd", qd), ("qdd", qdd)])?;
    let b = [
        base.angular_velocity,
        base.angular_acceleration,
        base.linear_acceleration_minus_gravity,
    ];
    if !b.iter().all(|v| v.iter().all(|x| x.is_finite())) {
        return Err(DynamicsError::NonFinite("base motion"));
    }
    let links = links(hand, q)?;
    let n = links.len();
    let (mut w, mut dw, mut a) = (
        vec![Vec3::zeros(); n],
        vec![Vec3::zeros(); n],
        vec![Vec3::zeros(); n],
    );
    let (mut f, mut m) = (vec![Vec3::zeros(); n], vec![Vec3::zeros(); n]);
    for i in 0..n {
        let l = &links[i];
        let (rate, accel) = l.dof.map_or((0.0, 0.0), |k| (qd[k], qdd[k]));
        match l.parent {
            None => {
                // Accelerating the base by -g stands for gravity on every body.
                w[i] = base.angular_velocity;
                dw[i] = base.angular_acceleration;
                a[i] = base.linear_acceleration_minus_gravity;
            }
            Some(p) => {
                let (wp, dwp, ap) = (w[p], dw[p], a[p]);
                w[i] = l.to_bone * wp + l.axis * rate;
                dw[i] = l.to_bone * dwp + l.axis * accel + w[i].cross(&(l.axis * rate));
                if let Some(first) = l.ball {
                    dw[i] -= ball_acceleration_correction(&qd[first..first + 3]);
                }
                a[i] = l.to_bone * (ap + dwp.cross(&l.origin) + wp.cross(&wp.cross(&l.origin)));
            }
        }
        if let Some(inertial) = l.inertial {
            let c = inertial.center_of_mass.coords;
            let ac = a[i] + dw[i].cross(&c) + w[i].cross(&w[i].cross(&c));
            f[i] = ac * inertial.mass;
            m[i] =
                inertial.inertia * dw[i] + w[i].cross(&(inertial.inertia * w[i])) + c.cross(&f[i]);
        }
    }
    let mut tau = DVector::zeros(hand.dof_count());
    for i in (0..n).rev() {
        let l = &links[i];
        if let Some(k) = l.dof {
            tau[k] = l.axis.dot(&m[i]);
        }
        if let Some(p) = l.parent {
            let to_parent = l.to_bone.transpose();
            let (fi, mi) = (to_parent * f[i], to_parent * m[i]);
            f[p] += fi;
            m[p] += mi + l.origin.cross(&fi);
        }
    }
    Ok(tau)
}

/// Torques that hold the hand still against gravity at positions `q`.
pub fn gravity_torques(
    hand: &HandModel,
    q: &[f64],
    gravity: Vec3,
) -> Result<DVector<f64>, DynamicsError> {
    let zero = vec![0.0; hand.dof_count()];
    inverse_dynamics(hand, q, &zero, &zero, gravity)
}
