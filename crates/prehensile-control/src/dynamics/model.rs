//! A hand's dynamics split as Pinocchio (`Model`/`Data`) and MuJoCo (`mjModel`/`mjData`) split
//! theirs: a [`DynamicsModel`] built once from the hand holds what does not change with the pose
//! (the link tree, axes, offsets, mass properties), and a [`DynamicsData`] holds every buffer the
//! algorithms write ([`crate::rnea`], [`crate::crba`], [`crate::outboard_inertia_into`]), so that
//! a control or simulation step allocates nothing.
//!
//! Links: every hinge bone is one link; a two-axis bone is two hinges in series (outer axis, then
//! a massless link, then the inner axis carrying the bone's mass), exactly its rotation
//! R = R(abduction)·R(flexion). A ball bone is three hinges about its own x, y and z axes at the
//! current rotation (two massless links, then the bone): their rates are the components of the
//! bone's angular velocity relative to its parent, in the bone's frame.

use nalgebra::{DMatrix, Matrix3, Unit};
use prehensile_core::hand::{Inertial, Joint};
use prehensile_core::math::{Rotation, Vec3};
use prehensile_core::HandModel;

use crate::dynamics::body_inertia::BodyInertia;
use crate::dynamics::body_inertia::OutboardInertia;
use crate::error::DynamicsError;

/// How a link's rotation from its parent depends on the pose.
#[derive(Debug, Clone, PartialEq)]
enum Turn {
    /// The rest rotation only.
    Fixed,
    /// The rest rotation, then a turn about `axis` by angle `q[dof]`.
    Hinge { axis: Unit<Vec3>, dof: usize },
    /// The rest rotation, then the ball joint's rotation vector `q[first..first + 3]`.
    Ball { joint: Joint, first: usize },
}

/// One link of the tree, pose-independent.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Link {
    /// Rotation from the parent link's frame before the joint turns.
    rest: Rotation,
    turn: Turn,
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
    /// [`crate::inverse_dynamics`]).
    pub ball: Option<usize>,
}

/// The pose-independent dynamics of a hand: its link tree. Build once per hand.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicsModel {
    links: Vec<Link>,
    dof_count: usize,
}

/// Every buffer the dynamics algorithms write for one [`DynamicsModel`]; make it with
/// [`DynamicsModel::data`] and reuse it.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicsData {
    /// Per link, rotation from the parent's frame to the link's at the pose `placed_at`.
    pub(crate) to_bone: Vec<Matrix3<f64>>,
    /// The pose `to_bone` was computed at (NaN before the first): the algorithms called one
    /// after another at one pose (the controller's outboard inertia and compensation, forward
    /// dynamics' bias and mass matrix) turn the links once.
    placed_at: Vec<f64>,
    /// Per link: angular velocity, angular acceleration, linear acceleration (own frame).
    pub(crate) velocity: Vec<[Vec3; 3]>,
    /// Per link: force and moment carried to the parent (own frame).
    pub(crate) wrench: Vec<[Vec3; 2]>,
    /// Per link, the composite inertia of its subtree about its origin.
    pub(crate) composite: Vec<BodyInertia>,
    /// Joint torques written by [`crate::rnea`] and [`crate::bias_torques`].
    pub(crate) tau: Vec<f64>,
    /// The joint-space mass matrix written by [`crate::crba`].
    pub(crate) mass: DMatrix<f64>,
    /// The outboard inertia written by [`crate::outboard_inertia_into`].
    pub(crate) outboard: OutboardInertia,
}

impl DynamicsModel {
    /// The link tree of `hand`.
    pub fn new(hand: &HandModel) -> Self {
        let mut links: Vec<Link> = Vec::with_capacity(hand.bones().len() + 8);
        // The link that carries each bone's frame (its last link).
        let mut carrier = vec![0usize; hand.bones().len()];
        for (k, bone) in hand.bones().iter().enumerate() {
            // A fixed link at the bone's rest pose; the joints below change what they turn.
            let rest = Link {
                rest: bone.rest.rotation,
                turn: Turn::Fixed,
                origin: bone.rest.translation.vector,
                axis: Vec3::zeros(),
                dof: None,
                parent: bone.parent.map(|p| carrier[p]),
                inertial: bone.inertial,
                ball: None,
            };
            let first = bone.first_dof;
            let hinge = |axis: Unit<Vec3>, dof: usize| Turn::Hinge { axis, dof };
            match &bone.joint {
                Joint::Fixed => links.push(rest),
                Joint::Hinge(a) => links.push(Link {
                    turn: hinge(a.axis, first),
                    axis: a.axis.into_inner(),
                    dof: Some(first),
                    ..rest
                }),
                Joint::TwoAxis { flexion, abduction } => {
                    links.push(Link {
                        turn: hinge(abduction.axis, first + 1),
                        axis: abduction.axis.into_inner(),
                        dof: Some(first + 1),
                        inertial: None,
                        ..rest.clone()
                    });
                    links.push(Link {
                        rest: Rotation::identity(),
                        turn: hinge(flexion.axis, first),
                        origin: Vec3::zeros(),
                        axis: flexion.axis.into_inner(),
                        dof: Some(first),
                        parent: Some(links.len() - 1),
                        ..rest
                    });
                }
                Joint::Ball { .. } => {
                    links.push(Link {
                        turn: Turn::Ball {
                            joint: bone.joint.clone(),
                            first,
                        },
                        axis: Vec3::x(),
                        dof: Some(first),
                        inertial: None,
                        ..rest.clone()
                    });
                    for (k, axis) in [(1, Vec3::y()), (2, Vec3::z())] {
                        links.push(Link {
                            rest: Rotation::identity(),
                            origin: Vec3::zeros(),
                            axis,
                            dof: Some(first + k),
                            parent: Some(links.len() - 1),
                            inertial: if k == 2 { bone.inertial } else { None },
                            ball: (k == 2).then_some(first),
                            ..rest.clone()
                        });
                    }
                }
            }
            carrier[k] = links.len() - 1;
        }
        Self {
            links,
            dof_count: hand.dof_count(),
        }
    }

    /// Degrees of freedom: the length of every joint vector.
    pub fn dof_count(&self) -> usize {
        self.dof_count
    }

    /// Buffers for this model.
    pub fn data(&self) -> DynamicsData {
        let n = self.links.len();
        DynamicsData {
            to_bone: vec![Matrix3::identity(); n],
            placed_at: vec![f64::NAN; self.dof_count],
            velocity: vec![[Vec3::zeros(); 3]; n],
            wrench: vec![[Vec3::zeros(); 2]; n],
            composite: vec![BodyInertia::zero(); n],
            tau: vec![0.0; self.dof_count],
            mass: DMatrix::zeros(self.dof_count, self.dof_count),
            outboard: OutboardInertia {
                diagonal: vec![0.0; self.dof_count],
                balls: self
                    .links
                    .iter()
                    .filter_map(|l| l.ball.map(|first| (first, Matrix3::zeros())))
                    .collect(),
            },
        }
    }

    /// The links, parents before children.
    pub(crate) fn links(&self) -> &[Link] {
        &self.links
    }

    /// Checks `q` and writes every link's rotation from its parent at that pose.
    pub(crate) fn place(&self, data: &mut DynamicsData, q: &[f64]) -> Result<(), DynamicsError> {
        self.check(&[("q", q)])?;
        if data.placed_at == q {
            return Ok(());
        }
        let to = |r: Rotation| r.to_rotation_matrix().into_inner().transpose();
        for (link, to_bone) in self.links.iter().zip(&mut data.to_bone) {
            *to_bone = match &link.turn {
                Turn::Fixed => to(link.rest),
                Turn::Hinge { axis, dof } => {
                    to(link.rest * Rotation::from_axis_angle(axis, q[*dof]))
                }
                Turn::Ball { joint, first } => {
                    to(link.rest * joint.rotation(&q[*first..first + 3]))
                }
            };
        }
        data.placed_at.copy_from_slice(q);
        Ok(())
    }

    /// Checks that every vector has one finite entry per degree of freedom.
    pub(crate) fn check(&self, vectors: &[(&'static str, &[f64])]) -> Result<(), DynamicsError> {
        for (what, v) in vectors {
            if v.len() != self.dof_count {
                return Err(DynamicsError::Length {
                    what,
                    got: v.len(),
                    expected: self.dof_count,
                });
            }
            if !v.iter().all(|x| x.is_finite()) {
                return Err(DynamicsError::NonFinite(what));
            }
        }
        Ok(())
    }
}
