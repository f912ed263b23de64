//! Building a [`GraspMovement`] for a hand: from its description in a hand file, the generic
//! `close` every hand gets, an end pose, or another movement's closing between other angles.

use crate::geometry::slerp_path::SlerpPath;
use crate::hand::movement::{GraspMovement, Via};
use crate::hand::{HandError, HandModel, MovementDescription};
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
            return Err(HandError::Invalid(format!(
                "movement '{}': via_fraction = {fraction:?} is not strictly between 0 and 1",
                self.name
            )));
        }
        if angles.len() != hand.dof_count() {
            return Err(HandError::Invalid(format!(
                "movement '{}': the via pose has {} angles, the hand {} degrees of freedom",
                self.name,
                angles.len(),
                hand.dof_count()
            )));
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
        // The angles a pose names, by degree of freedom; `None` where it names none.
        let named = |which: &str,
                     pose: &std::collections::BTreeMap<String, Vec<f64>>|
         -> Result<Vec<Option<f64>>, HandError> {
            let mut out = vec![None; hand.dof_count()];
            for (bone_name, values) in pose {
                let i = hand.bone_index(bone_name).ok_or_else(|| {
                    HandError::Invalid(format!(
                        "movement '{}' ({which} pose) names bone '{bone_name}', which does not exist",
                        d.name
                    ))
                })?;
                let bone = &hand.bones()[i];
                if values.len() != bone.joint.dofs() {
                    return Err(HandError::Invalid(format!(
                        "movement '{}' ({which} pose) gives {} angle(s) for bone '{bone_name}', whose joint has {}",
                        d.name,
                        values.len(),
                        bone.joint.dofs()
                    )));
                }
                for (k, v) in values.iter().enumerate() {
                    let [lo, hi] = bone.joint.limits(k);
                    let rad = v.to_radians();
                    if !rad.is_finite() || rad < lo - 1e-9 || rad > hi + 1e-9 {
                        return Err(HandError::Invalid(format!(
                            "movement '{}' ({which} pose): bone '{bone_name}' angle {k} = {v:?}° is outside its limits [{:.1}°, {:.1}°]",
                            d.name,
                            lo.to_degrees(),
                            hi.to_degrees()
                        )));
                    }
                    out[bone.first_dof + k] = Some(rad);
                }
            }
            Ok(out)
        };
        // A pose's unnamed degrees of freedom are at zero (then limits and couplings applied).
        let angles = |which: &str, pose| -> Result<Vec<f64>, HandError> {
            let mut q: Vec<f64> = named(which, pose)?
                .into_iter()
                .map(|a| a.unwrap_or(0.0))
                .collect();
            hand.constrain(&mut q);
            Ok(q)
        };
        let start_angles = angles("start", &d.start)?;
        let end_angles = angles("end", &d.end)?;
        let finger_ids = |names: &[String]| -> Result<Vec<usize>, HandError> {
            names
                .iter()
                .map(|f| {
                    hand.finger_index(f).ok_or_else(|| {
                        HandError::Invalid(format!(
                            "movement '{}' names finger '{f}'; the hand's fingers are {:?}",
                            d.name,
                            hand.fingers().iter().map(|f| &f.name).collect::<Vec<_>>()
                        ))
                    })
                })
                .collect()
        };
        let between = finger_ids(&d.grasp_center_between)?;
        let contact_fingers = finger_ids(&d.contact_fingers)?;
        let mut movement =
            Self::from_angles(hand, &d.name, start_angles, end_angles, Point3::origin());
        if !d.via.is_empty() {
            movement = movement.through(hand, d.via_fraction, &named("via", &d.via)?)?;
        }
        movement.contact_fingers = contact_fingers;
        movement.grasp_center = match (d.grasp_center, between.is_empty()) {
            (Some(c), true) if c.iter().all(|x| x.is_finite()) => Point3::from(c),
            (Some(_), true) => {
                return Err(HandError::Invalid(format!(
                    "movement '{}': grasp_center is not finite",
                    d.name
                )))
            }
            (Some(_), false) => {
                return Err(HandError::Invalid(format!(
                    "movement '{}': give either grasp_center or grasp_center_between, not both",
                    d.name
                )))
            }
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
