//! Building a [`HandModel`]: from parts given directly (importers of MJCF, URDF, glTF) or from a
//! [`HandDescription`] (TOML). Every error names the bone (or movement) and says how to fix it.

use std::collections::HashMap;

use super::description::{HandDescription, JointDescription};
use super::model::{Axis, Bone, BoneCapsule, Coupling, Finger, HandModel, Joint};
use crate::hand::kinematics::forward_kinematics;
use crate::hand::movement::GraspMovement;
use crate::math::is_finite_vec;
use crate::math::{Point3, Rotation, Transform, Vec3};

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
    #[error("bone '{bone}' has radius {radius:?}; radii must be positive metres, at most {MAX_HAND_EXTENT} m")]
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

/// One bone given directly, as an importer reads it.
#[derive(Debug, Clone, PartialEq)]
pub struct BonePart {
    /// Unique name.
    pub name: String,
    /// Parent bone's name; `None` for the root.
    pub parent: Option<String>,
    /// Bone frame relative to the parent's frame when all joint angles are zero (the root's:
    /// relative to the hand frame).
    pub rest: Transform,
    /// The joint that moves the bone.
    pub joint: Joint,
    /// One name per degree of freedom of the joint (the source file's joint names).
    pub dof_names: Vec<String>,
    /// Collision capsules `(a, b, radius)` in the bone frame; may be empty.
    pub capsules: Vec<(Point3, Point3, f64)>,
    /// Fingertip in the bone frame: required on the last bone of every finger, only there.
    pub tip: Option<Point3>,
    /// Name of the finger this bone starts (only read on a child of the root).
    pub finger: Option<String>,
    /// Mass properties, if known.
    pub inertial: Option<super::model::Inertial>,
}

/// A hand given directly as bones with rest transforms, joints and capsules.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct HandParts {
    /// Name of the hand.
    pub name: String,
    /// One line about it.
    pub description: String,
    /// Bones in any order.
    pub bones: Vec<BonePart>,
    /// `(follower, leader, ratio)` by degree-of-freedom name.
    pub couplings: Vec<(String, String, f64)>,
    /// The couplings are mechanical (MJCF fixed tendons, URDF mimic joints): a follower never
    /// moves without its leader (see [`Coupling::rigid`]). False for authored synergies.
    pub rigid_couplings: bool,
    /// End angles of the generic `close` movement by degree-of-freedom name (others stay at the
    /// open pose); empty: every flexion to its upper limit.
    pub close: Vec<(String, f64)>,
}

/// Parents-first order, children and root of a bone tree, checked.
struct Topology {
    order: Vec<usize>,
    children: Vec<Vec<usize>>,
    root: usize,
}

fn topology(names: &[&str], parents: &[Option<&str>]) -> Result<Topology, HandError> {
    let n = names.len();
    if !(3..=MAX_BONES).contains(&n) {
        return Err(HandError::BoneCount(n));
    }
    let mut by_name = HashMap::new();
    for (i, name) in names.iter().enumerate() {
        if by_name.insert(*name, i).is_some() {
            return Err(HandError::DuplicateBone(name.to_string()));
        }
    }
    let mut parent = vec![None; n];
    let mut roots = Vec::new();
    for (i, p) in parents.iter().enumerate() {
        match p {
            None => roots.push(names[i].to_string()),
            Some(p) => {
                parent[i] = Some(*by_name.get(p).ok_or_else(|| HandError::MissingParent {
                    bone: names[i].to_string(),
                    parent: p.to_string(),
                })?)
            }
        }
    }
    for (i, name) in names.iter().enumerate() {
        let mut at = i;
        for _ in 0..=n {
            match parent[at] {
                Some(p) if p == i => return Err(HandError::Cycle(name.to_string())),
                Some(p) => at = p,
                None => break,
            }
        }
        if parent[at].is_some() {
            return Err(HandError::Cycle(name.to_string()));
        }
    }
    if roots.len() != 1 {
        return Err(HandError::RootCount(roots));
    }
    let root = by_name[roots[0].as_str()];
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
    Ok(Topology {
        order,
        children,
        root,
    })
}

/// Largest distance of any bone position, tip or capsule from its frame, and largest capsule
/// radius, metres: no hand is bigger, and absurd sizes (1e300) made the search spin forever.
pub const MAX_HAND_EXTENT: f64 = 2.0;

fn check_extent(bone: &str, what: &str, points: &[Vec3]) -> Result<(), HandError> {
    if points.iter().any(|p| p.norm() > MAX_HAND_EXTENT) {
        return Err(HandError::Invalid(format!(
            "bone '{bone}': its {what} lies more than {MAX_HAND_EXTENT} m away; hands are metres-scale at most, so check the units (metres)"
        )));
    }
    Ok(())
}

/// Couplings must form chains that end at a free degree of freedom: none follows itself, none
/// follows two leaders, and no cycle (a follows b follows a), or `constrain` could not satisfy
/// them all and would silently break one.
fn check_couplings(model: &HandModel) -> Result<(), HandError> {
    let name = |k: usize| model.dof_names[k].clone();
    let mut leader_of: Vec<Option<usize>> = vec![None; model.dof_count];
    for c in &model.couplings {
        if c.follower == c.leader {
            return Err(HandError::Invalid(format!(
                "'{}' is coupled to itself; couple it to another degree of freedom or drop the coupling",
                name(c.follower)
            )));
        }
        if leader_of[c.follower].replace(c.leader).is_some() {
            return Err(HandError::Invalid(format!(
                "'{}' follows two leaders; give it one",
                name(c.follower)
            )));
        }
    }
    for start in 0..model.dof_count {
        let mut k = start;
        for _ in 0..=model.dof_count {
            match leader_of[k] {
                Some(l) if l == start => {
                    return Err(HandError::Invalid(format!(
                        "the couplings through '{}' form a cycle; one degree of freedom of the cycle must lead freely",
                        name(start)
                    )))
                }
                Some(l) => k = l,
                None => break,
            }
        }
    }
    Ok(())
}

fn check_limits(bone: &str, joint: &Joint) -> Result<(), HandError> {
    for k in 0..joint.dofs() {
        let [min, max] = joint.limits(k);
        if !min.is_finite() || !max.is_finite() {
            return Err(HandError::NonFinite {
                bone: bone.to_string(),
                what: "joint limits".into(),
            });
        }
        if min > max {
            return Err(HandError::UnorderedLimits {
                bone: bone.to_string(),
                min: min.to_degrees(),
                max: max.to_degrees(),
            });
        }
    }
    // A unit axis: an axis too large to normalize (1e308) or zero would give a joint that never
    // turns.
    let unit = |a: &Vec3| is_finite_vec(a) && (a.norm() - 1.0).abs() < 1e-6;
    let axes_ok = match joint {
        Joint::Hinge(a) => unit(&a.axis),
        Joint::TwoAxis { flexion, abduction } => unit(&flexion.axis) && unit(&abduction.axis),
        _ => true,
    };
    if !axes_ok {
        return Err(HandError::NonFinite {
            bone: bone.to_string(),
            what: "joint axis".into(),
        });
    }
    Ok(())
}

impl HandModel {
    /// Validates bones given directly and builds the model, with the generic `close` movement.
    pub fn from_parts(parts: HandParts) -> Result<Self, HandError> {
        let mut model = Self::assemble(&parts)?;
        let close = if parts.close.is_empty() {
            GraspMovement::generic_close(&model)
        } else {
            let mut end = vec![0.0; model.dof_count];
            model.constrain(&mut end);
            for (name, angle) in &parts.close {
                let k = model.dof_names.iter().position(|d| d == name).ok_or_else(|| {
                    HandError::Invalid(format!("the close movement names '{name}', which is no degree of freedom of this hand"))
                })?;
                end[k] = *angle;
            }
            GraspMovement::close_to(&model, end)
        };
        model.movements = vec![close];
        Ok(model)
    }

    fn assemble(parts: &HandParts) -> Result<Self, HandError> {
        let names: Vec<&str> = parts.bones.iter().map(|b| b.name.as_str()).collect();
        let parents: Vec<Option<&str>> = parts.bones.iter().map(|b| b.parent.as_deref()).collect();
        let topo = topology(&names, &parents)?;
        for b in &parts.bones {
            let non_finite = |what: &str| HandError::NonFinite {
                bone: b.name.clone(),
                what: what.to_string(),
            };
            let m = b.rest.to_homogeneous();
            if !m.iter().all(|c| c.is_finite()) {
                return Err(non_finite("rest transform"));
            }
            if b.tip.is_some_and(|t| !is_finite_vec(&t.coords)) {
                return Err(non_finite("tip"));
            }
            for (a, c, r) in &b.capsules {
                if !is_finite_vec(&a.coords) || !is_finite_vec(&c.coords) || !r.is_finite() {
                    return Err(non_finite("capsule"));
                }
                if *r <= 0.0 || *r > MAX_HAND_EXTENT {
                    return Err(HandError::BadRadius {
                        bone: b.name.clone(),
                        radius: *r,
                    });
                }
                check_extent(&b.name, "capsule end", &[a.coords, c.coords])?;
            }
            // The root may sit anywhere in its file's world; its children are near it.
            if b.parent.is_some() {
                check_extent(&b.name, "position", &[b.rest.translation.vector])?;
            }
            if let Some(t) = b.tip {
                check_extent(&b.name, "tip", &[t.coords])?;
            }
            check_limits(&b.name, &b.joint)?;
            if b.dof_names.len() != b.joint.dofs() {
                return Err(HandError::Invalid(format!(
                    "bone '{}' names {} degree(s) of freedom but its joint has {}",
                    b.name,
                    b.dof_names.len(),
                    b.joint.dofs()
                )));
            }
        }
        let n = parts.bones.len();
        let mut new_index = vec![0; n];
        for (k, &i) in topo.order.iter().enumerate() {
            new_index[i] = k;
        }
        for (i, kids) in topo.children.iter().enumerate() {
            let b = &parts.bones[i];
            if i != topo.root && kids.len() > 1 {
                return Err(HandError::Branching {
                    bone: b.name.clone(),
                    children: kids.len(),
                });
            }
            if i != topo.root && kids.is_empty() && b.tip.is_none() {
                return Err(HandError::MissingTip(b.name.clone()));
            }
            if !kids.is_empty() && b.tip.is_some() {
                return Err(HandError::MisplacedTip(b.name.clone()));
            }
        }
        let mut bones = Vec::with_capacity(n);
        let mut dof = 0;
        let mut dof_names = Vec::new();
        for &i in &topo.order {
            let b = &parts.bones[i];
            let parent = parts.bones[i]
                .parent
                .as_ref()
                .map(|p| new_index[names.iter().position(|x| x == p).expect("parents checked")]);
            bones.push(Bone {
                name: b.name.clone(),
                parent,
                rest: b.rest,
                joint: b.joint.clone(),
                first_dof: dof,
                finger: None,
                inertial: b.inertial,
            });
            dof += b.joint.dofs();
            dof_names.extend(b.dof_names.iter().cloned());
        }
        let mut seen = std::collections::HashSet::new();
        if let Some(dup) = dof_names.iter().find(|d| !seen.insert(d.as_str())) {
            return Err(HandError::Invalid(format!(
                "two degrees of freedom are named '{dup}'; names must be unique"
            )));
        }
        // Fingers: one chain per child of the root.
        let mut fingers = Vec::new();
        let mut chain_predecessor = vec![None; n];
        for &c in &topo.children[topo.root] {
            let mut chain = vec![new_index[c]];
            let mut at = c;
            while let [next] = topo.children[at].as_slice() {
                chain_predecessor[new_index[*next]] = Some(new_index[at]);
                chain.push(new_index[*next]);
                at = *next;
            }
            let tip = parts.bones[at].tip.expect("leaf tips checked above");
            let name = parts.bones[c]
                .finger
                .clone()
                .unwrap_or_else(|| parts.bones[c].name.clone());
            if fingers.iter().any(|f: &Finger| f.name == name) {
                return Err(HandError::Invalid(format!(
                    "two fingers are named '{name}'; set a distinct finger name on their first bones"
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
        let mut capsules = Vec::new();
        let mut capsule_ranges = vec![0..0; n];
        for (k, &i) in topo.order.iter().enumerate() {
            let first = capsules.len();
            for &(a, b, radius) in &parts.bones[i].capsules {
                capsules.push(BoneCapsule {
                    bone: k,
                    a,
                    b,
                    radius,
                });
            }
            capsule_ranges[k] = first..capsules.len();
        }
        let mut model = HandModel {
            name: parts.name.clone(),
            description: parts.description.clone(),
            bones,
            capsules,
            fingers,
            couplings: Vec::new(),
            movements: Vec::new(),
            dof_count: dof,
            chain_predecessor,
            capsule_ranges,
            dof_names,
            fingers_close_apart: false,
            finger_floor_radii: Vec::new(),
            dof_bones: Vec::new(),
        };
        model.dof_bones = model
            .bones
            .iter()
            .enumerate()
            .flat_map(|(b, bone)| std::iter::repeat_n(b, bone.joint.dofs()))
            .collect();
        model.couplings = parts
            .couplings
            .iter()
            .map(|(follower, leader, ratio)| {
                let find = |name: &str| {
                    model.dof_names.iter().position(|d| d == name).ok_or_else(|| {
                        HandError::Invalid(format!("coupling names '{name}', which is no degree of freedom of this hand"))
                    })
                };
                if !ratio.is_finite() {
                    return Err(HandError::Invalid(format!("coupling of '{follower}' has a non-finite ratio")));
                }
                Ok(Coupling {
                    follower: find(follower)?,
                    leader: find(leader)?,
                    ratio: *ratio,
                    rigid: parts.rigid_couplings,
                })
            })
            .collect::<Result<_, _>>()?;
        check_couplings(&model)?;
        // Facts of the finished hand that every search evaluation asks for.
        model.fingers_close_apart = super::closing_facts::fingers_close_apart(&model);
        model.finger_floor_radii = (0..model.fingers.len())
            .map(|f| super::closing_facts::finger_floor_radius(&model, f))
            .collect();
        Ok(model)
    }

    /// Validates a description and builds the model.
    pub fn from_description(desc: &HandDescription) -> Result<Self, HandError> {
        for b in &desc.bones {
            check_bone_numbers(b)?;
        }
        let names: Vec<&str> = desc.bones.iter().map(|b| b.name.as_str()).collect();
        let parents: Vec<Option<&str>> = desc.bones.iter().map(|b| b.parent.as_deref()).collect();
        let topo = topology(&names, &parents)?;
        // Bone frames in the hand frame: z along the bone, y toward `flexes_toward`.
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
            let rot =
                Rotation::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(m));
            frames[i] = Transform::from_parts(origin.coords.into(), rot);
        }
        let bones = desc
            .bones
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let rest = match topo_parent(&names, &b.parent) {
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
                                frames[i]
                                    .inverse_transform_point(&Point3::from(desc.bones[c].origin)),
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
            .collect();
        let couplings = desc
            .couplings
            .iter()
            .map(|c| {
                let dof_name = |bone: &str| -> Result<String, HandError> {
                    let b = desc.bones.iter().find(|b| b.name == bone).ok_or_else(|| {
                        HandError::Invalid(format!("coupling names bone '{bone}', which does not exist"))
                    })?;
                    let suffixes = dof_suffixes(&joint_from(&b.joint));
                    let suffix = suffixes.get(c.dof).ok_or_else(|| {
                        HandError::Invalid(format!(
                            "coupling uses degree of freedom {} of bone '{bone}', whose joint has {}",
                            c.dof,
                            suffixes.len()
                        ))
                    })?;
                    Ok(format!("{bone}.{suffix}"))
                };
                Ok((dof_name(&c.follower)?, dof_name(&c.leader)?, c.ratio))
            })
            .collect::<Result<_, HandError>>()?;
        let parts = HandParts {
            name: desc.name.clone(),
            description: desc.description.clone(),
            bones,
            couplings,
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
