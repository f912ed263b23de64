//! Validation of a [`HandDescription`] into a [`HandModel`]. Every error names the bone (or
//! movement) and says how to fix it.

use std::collections::HashMap;

use super::description::{HandDescription, JointDescription};
use super::model::{Axis, Bone, BoneCapsule, Coupling, Finger, HandModel, Joint};
use crate::kinematics::forward_kinematics;
use crate::math::{Point3, Rotation, Transform, Vec3};
use crate::movement::GraspMovement;

/// Shortest bone accepted, metres.
const MIN_BONE_LENGTH: f64 = 1e-5;
/// Most bones a hand may have.
const MAX_BONES: usize = 1000;

/// Why a hand description cannot become a hand model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum HandError {
    /// The hand has no bones or too many.
    #[error("the hand has {0} bones; it needs at least 3 (a root and two fingers) and at most {MAX_BONES}")]
    BoneCount(usize),
    /// Two bones share a name.
    #[error("bone '{0}' is defined twice; bone names must be unique")]
    DuplicateBone(String),
    /// A parent name refers to no bone.
    #[error("bone '{bone}' names parent '{parent}', which is not a bone of this hand; check the spelling")]
    MissingParent {
        /// The bone.
        bone: String,
        /// The parent it names.
        parent: String,
    },
    /// Zero or several bones without a parent.
    #[error("the hand must have exactly one root bone (one without a parent); found {0:?}")]
    RootCount(Vec<String>),
    /// Following parents from a bone comes back to it.
    #[error("bone '{0}' is part of a parent cycle; every chain of parents must end at the root")]
    Cycle(String),
    /// A number is NaN or infinite.
    #[error("bone '{bone}': {what} is not a finite number")]
    NonFinite {
        /// The bone.
        bone: String,
        /// Which field.
        what: String,
    },
    /// A bone's length is zero.
    #[error("bone '{bone}' has length {length:e} m; its joint and its end (next joint or tip) must differ")]
    ZeroLength {
        /// The bone.
        bone: String,
        /// The measured length.
        length: f64,
    },
    /// A radius is not positive.
    #[error("bone '{bone}' has radius {radius}; radii must be positive metres")]
    BadRadius {
        /// The bone.
        bone: String,
        /// The radius given.
        radius: f64,
    },
    /// Limits with min > max.
    #[error("bone '{bone}': limits [{min}, {max}] are not ordered; write [min, max]")]
    UnorderedLimits {
        /// The bone.
        bone: String,
        /// Lower limit, degrees.
        min: f64,
        /// Upper limit, degrees.
        max: f64,
    },
    /// A finger bone with several children.
    #[error("bone '{bone}' has {children} children; only the root may branch, fingers are chains")]
    Branching {
        /// The bone.
        bone: String,
        /// Child count.
        children: usize,
    },
    /// A finger's last bone has no tip, or a middle bone has one.
    #[error("bone '{0}' ends a finger but has no `tip`; add the fingertip position")]
    MissingTip(String),
    /// Tip on a bone that has a child.
    #[error("bone '{0}' has a `tip` but also a child; only the last bone of a finger has a tip")]
    MisplacedTip(String),
    /// Fewer than two fingers.
    #[error("the hand has {0} finger(s); a prehensile hand needs at least two (§3.1.1)")]
    TooFewFingers(usize),
    /// The flexion direction is along the bone.
    #[error("bone '{0}': `flexes_toward` is parallel to the bone; give a direction across it")]
    DegenerateFrame(String),
    /// A coupling, movement or finger reference is wrong.
    #[error("{0}")]
    Invalid(String),
}

impl HandModel {
    /// Validates a description and builds the model.
    pub fn from_description(desc: &HandDescription) -> Result<Self, HandError> {
        let n = desc.bones.len();
        if !(3..=MAX_BONES).contains(&n) {
            return Err(HandError::BoneCount(n));
        }
        let mut by_name = HashMap::new();
        for (i, b) in desc.bones.iter().enumerate() {
            if by_name.insert(b.name.as_str(), i).is_some() {
                return Err(HandError::DuplicateBone(b.name.clone()));
            }
            check_bone_numbers(b)?;
        }
        // Parents by description index.
        let mut parent = vec![None; n];
        let mut roots = Vec::new();
        for (i, b) in desc.bones.iter().enumerate() {
            match &b.parent {
                None => roots.push(b.name.clone()),
                Some(p) => {
                    let &pi = by_name
                        .get(p.as_str())
                        .ok_or_else(|| HandError::MissingParent {
                            bone: b.name.clone(),
                            parent: p.clone(),
                        })?;
                    parent[i] = Some(pi);
                }
            }
        }
        for (i, b) in desc.bones.iter().enumerate() {
            let mut at = i;
            for _ in 0..=n {
                match parent[at] {
                    Some(p) if p == i => return Err(HandError::Cycle(b.name.clone())),
                    Some(p) => at = p,
                    None => break,
                }
            }
            if parent[at].is_some() {
                return Err(HandError::Cycle(b.name.clone()));
            }
        }
        if roots.len() != 1 {
            return Err(HandError::RootCount(roots));
        }
        let root = by_name[roots[0].as_str()];
        // Parents-first order by depth-first traversal from the root.
        let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (i, p) in parent.iter().enumerate() {
            if let Some(p) = *p {
                children[p].push(i);
            }
        }
        let mut order = Vec::with_capacity(n);
        let mut stack = vec![root];
        while let Some(i) = stack.pop() {
            order.push(i);
            stack.extend(children[i].iter().rev());
        }
        let mut new_index = vec![0; n];
        for (k, &i) in order.iter().enumerate() {
            new_index[i] = k;
        }
        // Rest frames in the hand frame.
        let mut frames = Vec::with_capacity(n);
        for &i in &order {
            let b = &desc.bones[i];
            let origin = Point3::from(b.origin);
            if i == root {
                frames.push(Transform::new(origin.coords, Vec3::zeros()));
                continue;
            }
            let end = match (children[i].as_slice(), b.tip) {
                ([], Some(tip)) => Point3::from(tip),
                ([], None) => return Err(HandError::MissingTip(b.name.clone())),
                ([_], Some(_)) => return Err(HandError::MisplacedTip(b.name.clone())),
                ([c], None) => Point3::from(desc.bones[*c].origin),
                (many, _) => {
                    return Err(HandError::Branching {
                        bone: b.name.clone(),
                        children: many.len(),
                    })
                }
            };
            let along = end - origin;
            let length = along.norm();
            if length < MIN_BONE_LENGTH {
                return Err(HandError::ZeroLength {
                    bone: b.name.clone(),
                    length,
                });
            }
            let z = along / length;
            let hint = Vec3::from(b.flexes_toward.unwrap_or([0.0, 1.0, 0.0]));
            let y = hint - z * hint.dot(&z);
            if y.norm() < 1e-6 * hint.norm().max(1e-300) {
                return Err(HandError::DegenerateFrame(b.name.clone()));
            }
            let y = y.normalize();
            let x = y.cross(&z);
            let m = nalgebra::Matrix3::from_columns(&[x, y, z]);
            let rot =
                Rotation::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(m));
            frames.push(Transform::from_parts(origin.coords.into(), rot));
        }
        let mut bones = Vec::with_capacity(n);
        let mut dof = 0;
        for (k, &i) in order.iter().enumerate() {
            let b = &desc.bones[i];
            let p = parent[i].map(|p| new_index[p]);
            let rest = match p {
                Some(p) => frames[p].inverse() * frames[k],
                None => frames[k],
            };
            let joint = joint_from(&b.joint);
            let dofs = joint.dofs();
            bones.push(Bone {
                name: b.name.clone(),
                parent: p,
                rest,
                joint,
                first_dof: dof,
                finger: None,
            });
            dof += dofs;
        }
        // Fingers: one chain per child of the root.
        let mut fingers = Vec::new();
        let mut chain_predecessor = vec![None; n];
        for &c in &children[root] {
            let mut chain = vec![new_index[c]];
            let mut at = c;
            while let [next] = children[at].as_slice() {
                chain_predecessor[new_index[*next]] = Some(new_index[at]);
                chain.push(new_index[*next]);
                at = *next;
            }
            let last = &desc.bones[at];
            let tip_hand = Point3::from(last.tip.expect("leaf tips checked above"));
            let tip = frames[new_index[at]].inverse_transform_point(&tip_hand);
            let name = desc.bones[c]
                .finger
                .clone()
                .unwrap_or_else(|| desc.bones[c].name.clone());
            if fingers.iter().any(|f: &Finger| f.name == name) {
                return Err(HandError::Invalid(format!(
                    "two fingers are named '{name}'; set a distinct `finger` on their first bones"
                )));
            }
            for &bi in &chain {
                bones[bi].finger = Some(fingers.len());
            }
            fingers.push(Finger {
                name,
                bones: chain,
                tip,
            });
        }
        if fingers.len() < 2 {
            return Err(HandError::TooFewFingers(fingers.len()));
        }
        // Capsules: the root gets one to each child's joint; every other bone one along itself.
        let mut capsules = Vec::new();
        for (k, bone) in bones.iter().enumerate() {
            let radius = desc.bones[order[k]].radius;
            if k == 0 {
                for &c in &children[root] {
                    let b = bones[new_index[c]].rest.translation.vector;
                    capsules.push(BoneCapsule {
                        bone: 0,
                        a: Point3::origin(),
                        b: Point3::from(b),
                        radius,
                    });
                }
            } else {
                let finger = &fingers[bone.finger.expect("non-root bones are in fingers")];
                let end = if *finger.bones.last().unwrap() == k {
                    finger.tip
                } else {
                    let next = finger.bones[finger.bones.iter().position(|&x| x == k).unwrap() + 1];
                    Point3::from(bones[next].rest.translation.vector)
                };
                capsules.push(BoneCapsule {
                    bone: k,
                    a: Point3::origin(),
                    b: end,
                    radius,
                });
            }
        }
        let mut capsule_ranges = vec![0..0; n];
        for (k, range) in capsule_ranges.iter_mut().enumerate() {
            let first = capsules.iter().position(|c| c.bone == k).unwrap_or(0);
            let count = capsules.iter().filter(|c| c.bone == k).count();
            *range = first..first + count;
        }
        let mut model = HandModel {
            name: desc.name.clone(),
            description: desc.description.clone(),
            bones,
            capsules,
            fingers,
            couplings: Vec::new(),
            movements: Vec::new(),
            dof_count: dof,
            chain_predecessor,
            capsule_ranges,
            dof_names: Vec::new(),
        };
        model.dof_names = model
            .bones
            .iter()
            .flat_map(|b| {
                let suffixes: &[&str] = match b.joint {
                    Joint::Fixed => &[],
                    Joint::Hinge(_) => &["flexion"],
                    Joint::TwoAxis { .. } => &["flexion", "abduction"],
                    Joint::Ball { .. } => &["x", "y", "z"],
                };
                suffixes.iter().map(move |s| format!("{}.{s}", b.name))
            })
            .collect();
        model.couplings = desc
            .couplings
            .iter()
            .map(|c| {
                let dof_of = |name: &str| -> Result<usize, HandError> {
                    let i = model.bone_index(name).ok_or_else(|| {
                        HandError::Invalid(format!("coupling names bone '{name}', which does not exist"))
                    })?;
                    let b = &model.bones[i];
                    if c.dof >= b.joint.dofs() {
                        return Err(HandError::Invalid(format!(
                            "coupling uses degree of freedom {} of bone '{name}', whose joint has {}",
                            c.dof,
                            b.joint.dofs()
                        )));
                    }
                    Ok(b.first_dof + c.dof)
                };
                if !c.ratio.is_finite() {
                    return Err(HandError::Invalid(format!(
                        "coupling of '{}' has a non-finite ratio",
                        c.follower
                    )));
                }
                Ok(Coupling {
                    follower: dof_of(&c.follower)?,
                    leader: dof_of(&c.leader)?,
                    ratio: c.ratio,
                })
            })
            .collect::<Result<_, _>>()?;
        let mut movements = Vec::new();
        for m in &desc.movements {
            movements.push(GraspMovement::from_description(&model, m)?);
        }
        if !movements
            .iter()
            .any(|m: &GraspMovement| m.name() == "close")
        {
            movements.push(GraspMovement::generic_close(&model));
        }
        model.movements = movements;
        Ok(model)
    }

    /// World transform of every bone for joint rotations `rotations` with the root at `root`.
    /// Allocates; hot loops use [`forward_kinematics`] with a workspace.
    pub fn pose_transforms(&self, root: &Transform, rotations: &[Rotation]) -> Vec<Transform> {
        let mut out = vec![Transform::identity(); self.bones.len()];
        forward_kinematics(self, root, rotations, &mut out);
        out
    }
}

fn joint_from(j: &JointDescription) -> Joint {
    let r = |l: [f64; 2]| l.map(f64::to_radians);
    match j {
        JointDescription::Fixed => Joint::Fixed,
        JointDescription::Hinge { flexion } => Joint::Hinge(Axis::new(-Vec3::x(), r(*flexion))),
        JointDescription::TwoAxis { flexion, abduction } => Joint::TwoAxis {
            flexion: Axis::new(-Vec3::x(), r(*flexion)),
            abduction: Axis::new(Vec3::y(), r(*abduction)),
        },
        JointDescription::Ball { limits } => Joint::Ball {
            limits: limits.map(r),
        },
    }
}

fn check_bone_numbers(b: &super::description::BoneDescription) -> Result<(), HandError> {
    let non_finite = |what: &str| HandError::NonFinite {
        bone: b.name.clone(),
        what: what.to_string(),
    };
    if !b.origin.iter().all(|c| c.is_finite()) {
        return Err(non_finite("origin"));
    }
    if let Some(t) = b.tip {
        if !t.iter().all(|c| c.is_finite()) {
            return Err(non_finite("tip"));
        }
    }
    if let Some(t) = b.flexes_toward {
        if !t.iter().all(|c| c.is_finite()) {
            return Err(non_finite("flexes_toward"));
        }
    }
    if !b.radius.is_finite() {
        return Err(non_finite("radius"));
    }
    if b.radius <= 0.0 {
        return Err(HandError::BadRadius {
            bone: b.name.clone(),
            radius: b.radius,
        });
    }
    let limits: Vec<[f64; 2]> = match &b.joint {
        JointDescription::Fixed => vec![],
        JointDescription::Hinge { flexion } => vec![*flexion],
        JointDescription::TwoAxis { flexion, abduction } => vec![*flexion, *abduction],
        JointDescription::Ball { limits } => limits.to_vec(),
    };
    for [min, max] in limits {
        if !min.is_finite() || !max.is_finite() {
            return Err(non_finite("joint limits"));
        }
        if min > max {
            return Err(HandError::UnorderedLimits {
                bone: b.name.clone(),
                min,
                max,
            });
        }
    }
    Ok(())
}
