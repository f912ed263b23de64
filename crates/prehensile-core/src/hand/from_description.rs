//! Building a [`HandModel`] from a [`HandDescription`] (the TOML hand format): bone frames from
//! origins and tips, one capsule per bone, masses from the capsules, then
//! [`HandModel::from_parts`]'s checks and the file's movements.

use super::description::{BoneDescription, HandDescription, JointDescription};
use super::error::HandError;
use super::kinematics::forward_kinematics;
use super::limits::{MAX_HAND_EXTENT, MIN_BONE_LENGTH};
use super::model::{Axis, HandModel, Joint};
use super::movement::GraspMovement;
use super::parts::{BonePart, HandParts};
use super::validation::{check_extent, topology, Topology};
use crate::math::{Point3, Rotation, Transform, Vec3};

impl HandModel {
    /// Validates a description and builds the model.
    pub fn from_description(desc: &HandDescription) -> Result<Self, HandError> {
        for b in &desc.bones {
            check_bone_numbers(b)?;
        }
        let names: Vec<&str> = desc.bones.iter().map(|b| b.name.as_str()).collect();
        let parents: Vec<Option<&str>> = desc.bones.iter().map(|b| b.parent.as_deref()).collect();
        let topo = topology(&names, &parents)?;
        let frames = bone_frames(desc, &topo)?;
        let parts = HandParts {
            name: desc.name.clone(),
            description: desc.description.clone(),
            bones: bone_parts(desc, &topo, &frames, &names),
            couplings: coupling_names(desc)?,
            rigid_couplings: false,
            close: Vec::new(),
        };
        let mut model = Self::assemble(&parts)?;
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

/// Every bone's frame in the hand frame: at its origin, z along the bone to its child or tip,
/// y toward `flexes_toward`.
fn bone_frames(desc: &HandDescription, topo: &Topology) -> Result<Vec<Transform>, HandError> {
    let mut frames = vec![Transform::identity(); desc.bones.len()];
    for &i in &topo.order {
        let b = &desc.bones[i];
        let origin = Point3::from(b.origin);
        if i == topo.root {
            frames[i] = Transform::new(origin.coords, Vec3::zeros());
            continue;
        }
        let end = match (topo.children[i].as_slice(), b.tip) {
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
        let m = nalgebra::Matrix3::from_columns(&[y.cross(&z), y, z]);
        let rot = Rotation::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(m));
        frames[i] = Transform::from_parts(origin.coords.into(), rot);
    }
    Ok(frames)
}

/// Each bone as parts: its rest transform from its parent's frame, its joint, and one capsule
/// along it (the root's reach to each finger's first joint).
fn bone_parts(
    desc: &HandDescription,
    topo: &Topology,
    frames: &[Transform],
    names: &[&str],
) -> Vec<BonePart> {
    desc.bones
        .iter()
        .enumerate()
        .map(|(i, b)| {
            let rest = match topo_parent(names, &b.parent) {
                Some(p) => frames[p].inverse() * frames[i],
                None => frames[i],
            };
            let joint = joint_from(&b.joint);
            let suffixes = dof_suffixes(&joint);
            // The root reaches to each finger's first joint; every other bone along itself.
            let capsules = if i == topo.root {
                topo.children[i]
                    .iter()
                    .map(|&c| {
                        (
                            Point3::origin(),
                            frames[i].inverse_transform_point(&Point3::from(desc.bones[c].origin)),
                            b.radius,
                        )
                    })
                    .collect()
            } else {
                let end = match topo.children[i].as_slice() {
                    [c] => Point3::from(desc.bones[*c].origin),
                    _ => Point3::from(b.tip.expect("checked above")),
                };
                vec![(
                    Point3::origin(),
                    frames[i].inverse_transform_point(&end),
                    b.radius,
                )]
            };
            BonePart {
                name: b.name.clone(),
                parent: b.parent.clone(),
                rest,
                joint,
                dof_names: suffixes.iter().map(|s| format!("{}.{s}", b.name)).collect(),
                capsules: capsules.clone(),
                tip: b
                    .tip
                    .map(|t| frames[i].inverse_transform_point(&Point3::from(t))),
                finger: b.finger.clone(),
                inertial: super::capsule_inertia::capsules_inertial(
                    &capsules,
                    super::capsule_inertia::TISSUE_DENSITY,
                ),
            }
        })
        .collect()
}

/// The couplings by degree-of-freedom name.
fn coupling_names(desc: &HandDescription) -> Result<Vec<(String, String, f64)>, HandError> {
    desc.couplings
        .iter()
        .map(|c| {
            let dof_name = |bone: &str| -> Result<String, HandError> {
                let b = desc
                    .bones
                    .iter()
                    .find(|b| b.name == bone)
                    .ok_or_else(|| HandError::CouplingBone(bone.to_string()))?;
                let suffixes = dof_suffixes(&joint_from(&b.joint));
                let suffix = suffixes.get(c.dof).ok_or_else(|| HandError::CouplingDof {
                    bone: bone.to_string(),
                    index: c.dof,
                    dofs: suffixes.len(),
                })?;
                Ok(format!("{bone}.{suffix}"))
            };
            Ok((dof_name(&c.follower)?, dof_name(&c.leader)?, c.ratio))
        })
        .collect()
}

/// Names of a TOML joint's degrees of freedom after the bone's name.
fn dof_suffixes(joint: &Joint) -> &'static [&'static str] {
    match joint {
        Joint::Fixed => &[],
        Joint::Hinge(_) => &["flexion"],
        Joint::TwoAxis { .. } => &["flexion", "abduction"],
        Joint::Ball { .. } => &["x", "y", "z"],
    }
}

/// Index of the parent named `parent`.
fn topo_parent(names: &[&str], parent: &Option<String>) -> Option<usize> {
    parent
        .as_ref()
        .and_then(|p| names.iter().position(|n| n == p))
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

fn check_bone_numbers(b: &BoneDescription) -> Result<(), HandError> {
    let non_finite = |what: &'static str| HandError::NonFinite {
        bone: b.name.clone(),
        what,
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
    check_extent(&b.name, "origin", &[Vec3::from(b.origin)])?;
    if let Some(t) = b.tip {
        check_extent(&b.name, "tip", &[Vec3::from(t)])?;
    }
    if b.radius <= 0.0 || b.radius > MAX_HAND_EXTENT {
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
