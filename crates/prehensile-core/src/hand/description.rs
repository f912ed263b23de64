//! The documented, engine-neutral description of a hand, as written in a hand file (TOML).
//!
//! Positions are in metres in the hand frame at rest (z from the wrist along the fingers, x across
//! the knuckles, y the palm normal pointing out of the palm); angles are in degrees. See
//! `docs/HAND_FORMAT.md` for the full format with an example.

use serde::{Deserialize, Serialize};

/// A whole hand: bones, coupling rules and grasp movements.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HandDescription {
    /// Short name, e.g. `human`.
    pub name: String,
    /// One line about the hand and where its numbers come from.
    #[serde(default)]
    pub description: String,
    /// Bones in any order; exactly one has no parent (the root, usually the wrist).
    pub bones: Vec<BoneDescription>,
    /// Intra-finger coupling rules (§4.1.2.2).
    #[serde(default)]
    pub couplings: Vec<CouplingDescription>,
    /// Grasp movements (§5.3). A generic `close` movement is always added.
    #[serde(default)]
    pub movements: Vec<MovementDescription>,
}

impl HandDescription {
    /// The mirror image across the hand's yz-plane (x negated): a left hand from a right one and
    /// back, in every pose. Bone frames are derived again from the mirrored positions (still
    /// right-handed: the bone's x axis is the mirror of the original's, negated), so flexion
    /// about −x still curls toward the palm, while a turn about the bone's y or z is the mirror
    /// image of the opposite turn: abduction angles and limits, and a ball joint's y and z
    /// components, change sign.
    pub fn mirrored(&self, name: &str) -> Self {
        let flip = |p: [f64; 3]| [-p[0], p[1], p[2]];
        let mut out = self.clone();
        out.name = name.to_string();
        out.description = format!("mirror image of {}: {}", self.name, self.description);
        for b in &mut out.bones {
            b.origin = flip(b.origin);
            b.tip = b.tip.map(flip);
            b.flexes_toward = b.flexes_toward.map(flip);
            b.joint.mirror_limits();
        }
        let joints: std::collections::HashMap<&str, &JointDescription> = self
            .bones
            .iter()
            .map(|b| (b.name.as_str(), &b.joint))
            .collect();
        for m in &mut out.movements {
            m.grasp_center = m.grasp_center.map(flip);
            for (bone, angles) in m
                .start
                .iter_mut()
                .chain(m.end.iter_mut())
                .chain(m.via.iter_mut())
            {
                let dofs = joints
                    .get(bone.as_str())
                    .map_or(&[][..], |j| j.mirror_turned());
                for &k in dofs {
                    if let Some(a) = angles.get_mut(k) {
                        *a = -*a;
                    }
                }
            }
        }
        out
    }
}

/// One bone and the joint that moves it relative to its parent.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoneDescription {
    /// Unique name.
    pub name: String,
    /// Name of the parent bone; absent for the root.
    #[serde(default)]
    pub parent: Option<String>,
    /// Joint position at rest, hand frame, metres.
    pub origin: [f64; 3],
    /// End point of the last bone of a finger (the fingertip), hand frame, metres.
    #[serde(default)]
    pub tip: Option<[f64; 3]>,
    /// Capsule radius in metres.
    pub radius: f64,
    /// The joint; fixed when absent.
    #[serde(default)]
    pub joint: JointDescription,
    /// Name of the finger this bone starts (only on the first bone of a chain); defaults to the
    /// bone's name.
    #[serde(default)]
    pub finger: Option<String>,
    /// Direction (hand frame) toward which the bone flexes; the bone's y axis is this direction
    /// made perpendicular to the bone. Defaults to the hand's palm normal `[0, 1, 0]`.
    #[serde(default)]
    pub flexes_toward: Option<[f64; 3]>,
}

/// A joint and its limits in degrees.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum JointDescription {
    /// No motion.
    #[default]
    Fixed,
    /// One flexion axis (the bone's −x, so positive angles curl toward the bone's +y).
    Hinge {
        /// Flexion limits `[min, max]` in degrees.
        flexion: [f64; 2],
    },
    /// Flexion about the bone's −x, then abduction about its y.
    TwoAxis {
        /// Flexion limits in degrees.
        flexion: [f64; 2],
        /// Abduction limits in degrees.
        abduction: [f64; 2],
    },
    /// Three rotational degrees of freedom as a rotation vector in the bone frame.
    Ball {
        /// Limits of the rotation vector's components `[[xmin, xmax], [ymin, ymax], [zmin, zmax]]`.
        limits: [[f64; 2]; 3],
    },
}

impl JointDescription {
    /// The degrees of freedom whose angle changes sign in the mirror image of the hand: turns
    /// about the bone's y and z (abduction; a ball joint's y and z), not flexion about −x.
    fn mirror_turned(&self) -> &'static [usize] {
        match self {
            JointDescription::TwoAxis { .. } => &[1],
            JointDescription::Ball { .. } => &[1, 2],
            JointDescription::Fixed | JointDescription::Hinge { .. } => &[],
        }
    }

    /// Negates (and swaps) the limits of [`JointDescription::mirror_turned`]'s degrees of freedom.
    fn mirror_limits(&mut self) {
        let negated = |[lo, hi]: [f64; 2]| [-hi, -lo];
        match self {
            JointDescription::TwoAxis { abduction, .. } => *abduction = negated(*abduction),
            JointDescription::Ball { limits } => {
                limits[1] = negated(limits[1]);
                limits[2] = negated(limits[2]);
            }
            JointDescription::Fixed | JointDescription::Hinge { .. } => {}
        }
    }
}

/// `follower.dof = ratio * leader.dof` (e.g. distal flexion = 2/3 of middle flexion).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CouplingDescription {
    /// Bone whose angle is derived.
    pub follower: String,
    /// Bone whose angle drives it.
    pub leader: String,
    /// Ratio.
    pub ratio: f64,
    /// Which degree of freedom of each joint (0 = flexion).
    #[serde(default)]
    pub dof: usize,
}

/// A grasp movement: start and end joint angles (degrees per bone; bones left out stay at 0).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MovementDescription {
    /// Name, e.g. `power` or `precision`.
    pub name: String,
    /// Grasp center in the hand frame, metres.
    #[serde(default)]
    pub grasp_center: Option<[f64; 3]>,
    /// Instead of `grasp_center`: the centroid of these fingers' tips at the end pose.
    #[serde(default)]
    pub grasp_center_between: Vec<String>,
    /// Fingers that must touch for the grasp to count (e.g. thumb and index for precision).
    #[serde(default)]
    pub contact_fingers: Vec<String>,
    /// Start pose: bone name -> angles in degrees, one per degree of freedom.
    #[serde(default)]
    pub start: std::collections::BTreeMap<String, Vec<f64>>,
    /// End pose, same form.
    #[serde(default)]
    pub end: std::collections::BTreeMap<String, Vec<f64>>,
    /// A pose to pass through on the way, same form (beyond the thesis); bones it does not name
    /// move straight from start to end. Empty: no via pose.
    #[serde(default)]
    pub via: std::collections::BTreeMap<String, Vec<f64>>,
    /// Fraction of the closing at which the movement is at the via pose, strictly between 0
    /// and 1.
    #[serde(default = "half")]
    pub via_fraction: f64,
}

fn half() -> f64 {
    0.5
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirroring_turns_a_ball_joints_y_and_z_and_twice_is_the_original() {
        let bone = |name: &str, parent: Option<&str>, joint| BoneDescription {
            name: name.into(),
            parent: parent.map(Into::into),
            origin: [0.01, 0.02, 0.03],
            tip: parent.map(|_| [0.02, 0.03, 0.08]),
            radius: 0.01,
            joint,
            finger: None,
            flexes_toward: Some([0.7, 0.7, 0.0]),
        };
        let ball = JointDescription::Ball {
            limits: [[-60.0, 10.0], [-20.0, 30.0], [-5.0, 40.0]],
        };
        let right = HandDescription {
            name: "right".into(),
            description: String::new(),
            bones: vec![
                bone("palm", None, JointDescription::Fixed),
                bone("tip", Some("palm"), ball.clone()),
                BoneDescription {
                    origin: [-0.02, 0.0, 0.03],
                    ..bone("other", Some("palm"), ball)
                },
            ],
            couplings: Vec::new(),
            movements: vec![MovementDescription {
                name: "close".into(),
                grasp_center: Some([0.01, 0.05, 0.09]),
                grasp_center_between: Vec::new(),
                contact_fingers: Vec::new(),
                start: [("tip".to_string(), vec![-10.0, 5.0, 7.0])].into(),
                end: [("tip".to_string(), vec![-50.0, 15.0, -3.0])].into(),
                via: [("tip".to_string(), vec![-20.0, 10.0, -5.0])].into(),
                via_fraction: 0.4,
            }],
        };
        let left = right.mirrored("left");
        assert_eq!(
            left.bones[1].joint,
            JointDescription::Ball {
                limits: [[-60.0, 10.0], [-30.0, 20.0], [-40.0, 5.0]]
            }
        );
        assert_eq!(left.bones[1].origin, [-0.01, 0.02, 0.03]);
        assert_eq!(left.movements[0].start["tip"], [-10.0, -5.0, -7.0]);
        assert_eq!(left.movements[0].end["tip"], [-50.0, -15.0, 3.0]);
        assert_eq!(left.movements[0].via["tip"], [-20.0, -10.0, 5.0]);
        assert_eq!(left.movements[0].grasp_center, Some([-0.01, 0.05, 0.09]));
        let back = left.mirrored("right");
        assert_eq!(back.bones, right.bones);
        assert_eq!(back.movements, right.movements);

        // Posed, the left hand is the mirror image of the right one along the whole closing.
        let (right, left) = (
            crate::HandModel::from_description(&right).unwrap(),
            crate::HandModel::from_description(&left).unwrap(),
        );
        for f in [0.0, 0.2, 0.4, 0.5, 1.0] {
            let tip = |h: &crate::HandModel| {
                let m = h.movement("close").unwrap();
                let r: Vec<_> = (0..h.bones().len()).map(|b| m.rotation_at(b, f)).collect();
                let world = h.pose_transforms(&crate::math::Transform::identity(), &r);
                world[1] * h.fingers()[0].tip
            };
            let (r, l) = (tip(&right), tip(&left));
            assert!(
                (crate::math::Point3::new(-r.x, r.y, r.z) - l).norm() < 1e-12,
                "at {f}: {r} and {l}"
            );
        }
    }
}
