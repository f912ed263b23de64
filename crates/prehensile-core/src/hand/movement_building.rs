//! Building a [`GraspMovement`] for a hand: from its description in a hand file, the generic
//! `close` every hand gets, an end pose, or another movement's closing between other angles.

use crate::geometry::slerp_path::SlerpPath;
use crate::hand::movement::{GraspMovement, Via};
use std::collections::BTreeMap;

use crate::hand::{HandError, HandModel, MovementDescription, MovementProblem};
use crate::math::{Point3, Rotation, Transform};

impl GraspMovement {
    /// This movement passing through `angles` (limits and couplings applied) at `fraction` of
    /// its closing; `None` angles of a degree of freedom keep it on its straight way (the
    /// start–end interpolation at `fraction`). Errors if `fraction` is not strictly between 0
    /// and 1 or `angles` has the wrong length.
    pub fn through(
        mut self,
        hand: &HandModel,
        fraction: f64,
        angles: &[Option<f64>],
    ) -> Result<Self, HandError> {
        if !(fraction > 0.0 && fraction < 1.0) {
            return Err(movement_error(
                &self.name,
                MovementProblem::ViaFraction(fraction),
            ));
        }
        if angles.len() != hand.dof_count() {
            let problem = MovementProblem::ViaLength {
                got: angles.len(),
                dofs: hand.dof_count(),
            };
            return Err(movement_error(&self.name, problem));
        }
        let mut q: Vec<f64> = angles
            .iter()
            .zip(self.start_angles.iter().zip(&self.end_angles))
            .map(|(a, (s, e))| a.unwrap_or(s + fraction * (e - s)))
            .collect();
        hand.constrain(&mut q);
        let mut rotations = vec![Rotation::identity(); hand.bones().len()];
        hand.joint_rotations(&q, &mut rotations);
        let mut end = vec![Rotation::identity(); hand.bones().len()];
        hand.joint_rotations(&self.end_angles, &mut end);
        self.via = Some(Via {
            fraction,
            angles: q,
            paths_in: self
                .start
                .iter()
                .zip(&rotations)
                .map(|(s, v)| SlerpPath::new(s, v))
                .collect(),
            paths_out: rotations
                .iter()
                .zip(&end)
                .map(|(v, e)| SlerpPath::new(v, e))
                .collect(),
        });
        Ok(self)
    }

    /// Builds a movement from its description, checking names, counts and limits.
    pub fn from_description(hand: &HandModel, d: &MovementDescription) -> Result<Self, HandError> {
        let error = |problem| movement_error(&d.name, problem);
        let start_angles = pose_angles(hand, "start", &d.start).map_err(error)?;
        let end_angles = pose_angles(hand, "end", &d.end).map_err(error)?;
        let between = finger_indices(hand, &d.grasp_center_between).map_err(error)?;
        let contact_fingers = finger_indices(hand, &d.contact_fingers).map_err(error)?;
        let mut movement =
            Self::from_angles(hand, &d.name, start_angles, end_angles, Point3::origin());
        if !d.via.is_empty() {
            let via = named_angles(hand, "via", &d.via).map_err(error)?;
            movement = movement.through(hand, d.via_fraction, &via)?;
        }
        movement.contact_fingers = contact_fingers;
        movement.grasp_center = match (d.grasp_center, between.is_empty()) {
            (Some(c), true) if c.iter().all(|x| x.is_finite()) => Point3::from(c),
            (Some(_), true) => return Err(error(MovementProblem::GraspCenterNotFinite)),
            (Some(_), false) => return Err(error(MovementProblem::GraspCenterTwice)),
            (None, false) => movement.tip_centroid(hand, &between, 1.0),
            (None, true) => {
                let all: Vec<usize> = (0..hand.fingers().len()).collect();
                movement.tip_centroid(hand, &all, 0.5)
            }
        };
        Ok(movement)
    }

    /// The generic movement every hand gets: from the open pose (all angles zero, clamped into the
    /// limits) to every flexion at its upper limit; grasp center between the fingertips half-way.
    /// A ball joint flexes like a hinge, about its bone's −x axis (z along the bone, y toward
    /// where it flexes), as far as the lower limit of its x component allows; it neither
    /// abducts nor twists.
    pub fn generic_close(hand: &HandModel) -> Self {
        let mut end = vec![0.0; hand.dof_count()];
        for bone in hand.bones().iter().skip(1) {
            match bone.joint {
                crate::hand::Joint::Fixed => {}
                crate::hand::Joint::Ball { limits } => end[bone.first_dof] = limits[0][0],
                _ => end[bone.first_dof] = bone.joint.limits(0)[1],
            }
        }
        Self::close_to(hand, end)
    }

    /// A `close` movement from the open pose to the given end angles (limits and couplings
    /// applied), grasp center between the fingertips half-way.
    pub fn close_to(hand: &HandModel, mut end: Vec<f64>) -> Self {
        let mut start = vec![0.0; hand.dof_count()];
        hand.constrain(&mut start);
        hand.constrain(&mut end);
        let mut m = Self::from_angles(hand, "close", start, end, Point3::origin());
        let all: Vec<usize> = (0..hand.fingers().len()).collect();
        m.grasp_center = m.tip_centroid(hand, &all, 0.5);
        m.contact_fingers = Vec::new();
        m
    }

    /// A movement from the open pose to `end` (limits and couplings applied) with the given
    /// grasp center and contact fingers; see [`crate::hand::movement_derivation`].
    pub fn to_end_pose(
        hand: &HandModel,
        name: &str,
        mut end: Vec<f64>,
        grasp_center: Point3,
        contact_fingers: Vec<usize>,
    ) -> Self {
        let mut start = vec![0.0; hand.dof_count()];
        hand.constrain(&mut start);
        hand.constrain(&mut end);
        let mut m = Self::from_angles(hand, name, start, end, grasp_center);
        m.contact_fingers = contact_fingers;
        m
    }

    /// This movement (name, grasp center, contact fingers) between other start and end joint
    /// angles (limits and couplings applied): the closing a controller with those setpoints
    /// will make.
    pub fn between(&self, hand: &HandModel, mut start: Vec<f64>, mut end: Vec<f64>) -> Self {
        hand.constrain(&mut start);
        hand.constrain(&mut end);
        let mut m = Self::from_angles(hand, &self.name, start, end, self.grasp_center);
        m.contact_fingers = self.contact_fingers.clone();
        m
    }

    fn from_angles(
        hand: &HandModel,
        name: &str,
        start_angles: Vec<f64>,
        end_angles: Vec<f64>,
        grasp_center: Point3,
    ) -> Self {
        let n = hand.bones().len();
        let mut start = vec![Rotation::identity(); n];
        let mut end = vec![Rotation::identity(); n];
        hand.joint_rotations(&start_angles, &mut start);
        hand.joint_rotations(&end_angles, &mut end);
        Self {
            name: name.to_string(),
            start_angles,
            end_angles,
            paths: start
                .iter()
                .zip(&end)
                .map(|(s, e)| SlerpPath::new(s, e))
                .collect(),
            start,
            grasp_center,
            contact_fingers: Vec::new(),
            via: None,
        }
    }

    /// Centroid of the given fingers' tips (hand frame) at fraction `f` of the movement.
    fn tip_centroid(&self, hand: &HandModel, fingers: &[usize], f: f64) -> Point3 {
        let rotations: Vec<Rotation> = (0..hand.bones().len())
            .map(|b| self.rotation_at(b, f))
            .collect();
        let world = hand.pose_transforms(&Transform::identity(), &rotations);
        let sum = fingers.iter().fold(Point3::origin().coords, |acc, &fi| {
            let finger = &hand.fingers()[fi];
            acc + (world[*finger.bones.last().unwrap()] * finger.tip).coords
        });
        Point3::from(sum / fingers.len().max(1) as f64)
    }
}

/// A [`HandError`] about movement `name`.
fn movement_error(name: &str, problem: MovementProblem) -> HandError {
    HandError::Movement {
        movement: name.to_string(),
        problem,
    }
}

/// The angles a pose of a hand file names, radians, by degree of freedom (`None` where it names
/// none), each checked against its joint's limits.
fn named_angles(
    hand: &HandModel,
    pose: &'static str,
    angles: &BTreeMap<String, Vec<f64>>,
) -> Result<Vec<Option<f64>>, MovementProblem> {
    let mut out = vec![None; hand.dof_count()];
    for (bone_name, values) in angles {
        let i = hand
            .bone_index(bone_name)
            .ok_or_else(|| MovementProblem::UnknownBone {
                pose,
                bone: bone_name.clone(),
            })?;
        let bone = &hand.bones()[i];
        if values.len() != bone.joint.dofs() {
            return Err(MovementProblem::AngleCount {
                pose,
                bone: bone_name.clone(),
                got: values.len(),
                joint: bone.joint.dofs(),
            });
        }
        for (k, v) in values.iter().enumerate() {
            let [lo, hi] = bone.joint.limits(k);
            let rad = v.to_radians();
            if !rad.is_finite() || rad < lo - 1e-9 || rad > hi + 1e-9 {
                return Err(MovementProblem::OutsideLimits {
                    pose,
                    bone: bone_name.clone(),
                    index: k,
                    degrees: *v,
                    low: lo.to_degrees(),
                    high: hi.to_degrees(),
                });
            }
            out[bone.first_dof + k] = Some(rad);
        }
    }
    Ok(out)
}

/// A whole pose of a hand file: the degrees of freedom it does not name at zero, then limits and
/// couplings applied.
fn pose_angles(
    hand: &HandModel,
    pose: &'static str,
    angles: &BTreeMap<String, Vec<f64>>,
) -> Result<Vec<f64>, MovementProblem> {
    let mut q: Vec<f64> = named_angles(hand, pose, angles)?
        .into_iter()
        .map(|a| a.unwrap_or(0.0))
        .collect();
    hand.constrain(&mut q);
    Ok(q)
}

/// The indices of fingers named in a hand file.
fn finger_indices(hand: &HandModel, names: &[String]) -> Result<Vec<usize>, MovementProblem> {
    names
        .iter()
        .map(|f| {
            hand.finger_index(f)
                .ok_or_else(|| MovementProblem::UnknownFinger {
                    finger: f.clone(),
                    fingers: hand.fingers().iter().map(|f| f.name.clone()).collect(),
                })
        })
        .collect()
}
