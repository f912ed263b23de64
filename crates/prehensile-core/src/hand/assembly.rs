//! Building a [`HandModel`] from bones given directly (importers of MJCF, URDF, glTF): each
//! stage checks what it builds and names the bone or degree of freedom that is wrong.

use std::collections::HashSet;
use std::ops::Range;

use super::error::HandError;
use super::limits::MAX_HAND_EXTENT;
use super::model::{Bone, BoneCapsule, Coupling, Finger, HandModel};
use super::movement::GraspMovement;
use super::parts::{BonePart, HandParts};
use super::validation::{check_couplings, check_extent, check_limits, topology, Topology};
use crate::math::is_finite_vec;

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
                end[dof_index(&model, "the close movement", name)?] = *angle;
            }
            GraspMovement::close_to(&model, end)
        };
        model.movements = vec![close];
        Ok(model)
    }

    /// The model of `parts`, without movements: the bones parents first, their degrees of
    /// freedom, fingers, capsules and couplings, and the facts every search asks for.
    pub(super) fn assemble(parts: &HandParts) -> Result<Self, HandError> {
        let names: Vec<&str> = parts.bones.iter().map(|b| b.name.as_str()).collect();
        let parents: Vec<Option<&str>> = parts.bones.iter().map(|b| b.parent.as_deref()).collect();
        let topo = topology(&names, &parents)?;
        parts.bones.iter().try_for_each(check_part)?;
        check_chains(parts, &topo)?;
        let new_index = new_indices(&topo);
        let (mut bones, dof_names) = ordered_bones(parts, &topo, &new_index, &names);
        let mut seen = HashSet::new();
        if let Some(dup) = dof_names.iter().find(|d| !seen.insert(d.as_str())) {
            return Err(HandError::DuplicateDof(dup.clone()));
        }
        let (fingers, chain_predecessor) = fingers(parts, &topo, &new_index, &mut bones)?;
        let (capsules, capsule_ranges) = capsules(parts, &topo);
        let mut model = HandModel {
            name: parts.name.clone(),
            description: parts.description.clone(),
            dof_count: dof_names.len(),
            dof_bones: bones
                .iter()
                .enumerate()
                .flat_map(|(b, bone)| std::iter::repeat_n(b, bone.joint.dofs()))
                .collect(),
            bones,
            capsules,
            fingers,
            couplings: Vec::new(),
            movements: Vec::new(),
            chain_predecessor,
            capsule_ranges,
            dof_names,
            fingers_close_apart: false,
            finger_floor_radii: Vec::new(),
        };
        model.couplings = couplings(parts, &model)?;
        check_couplings(&model)?;
        // Facts of the finished hand that every search evaluation asks for.
        model.fingers_close_apart = super::closing_facts::fingers_close_apart(&model);
        model.finger_floor_radii = (0..model.fingers.len())
            .map(|f| super::closing_facts::finger_floor_radius(&model, f))
            .collect();
        Ok(model)
    }
}

/// The index of degree of freedom `name`, which `what` names.
fn dof_index(model: &HandModel, what: &'static str, name: &str) -> Result<usize, HandError> {
    model
        .dof_names
        .iter()
        .position(|d| d == name)
        .ok_or_else(|| HandError::UnknownDof {
            what,
            name: name.to_string(),
        })
}

/// One bone's numbers: finite, hand-sized, limits ordered, a name per degree of freedom.
fn check_part(b: &BonePart) -> Result<(), HandError> {
    let non_finite = |what: &'static str| HandError::NonFinite {
        bone: b.name.clone(),
        what,
    };
    if !b.rest.to_homogeneous().iter().all(|c| c.is_finite()) {
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
        return Err(HandError::DofNameCount {
            bone: b.name.clone(),
            named: b.dof_names.len(),
            joint: b.joint.dofs(),
        });
    }
    Ok(())
}

/// Fingers are chains: only the root branches, and a tip ends every chain and nothing else.
fn check_chains(parts: &HandParts, topo: &Topology) -> Result<(), HandError> {
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
    Ok(())
}

/// Each given bone's index parents first.
fn new_indices(topo: &Topology) -> Vec<usize> {
    let mut new_index = vec![0; topo.order.len()];
    for (k, &i) in topo.order.iter().enumerate() {
        new_index[i] = k;
    }
    new_index
}

/// The bones parents first, each with its first degree of freedom, and every degree of
/// freedom's name in that order.
fn ordered_bones(
    parts: &HandParts,
    topo: &Topology,
    new_index: &[usize],
    names: &[&str],
) -> (Vec<Bone>, Vec<String>) {
    let mut bones = Vec::with_capacity(topo.order.len());
    let mut dof_names = Vec::new();
    for &i in &topo.order {
        let b = &parts.bones[i];
        let parent = b
            .parent
            .as_ref()
            .map(|p| new_index[names.iter().position(|x| x == p).expect("parents checked")]);
        bones.push(Bone {
            name: b.name.clone(),
            parent,
            rest: b.rest,
            joint: b.joint.clone(),
            first_dof: dof_names.len(),
            finger: None,
            inertial: b.inertial,
        });
        dof_names.extend(b.dof_names.iter().cloned());
    }
    (bones, dof_names)
}

/// One finger per child of the root, a chain to its tip; marks each bone with its finger and
/// returns each bone's predecessor along its chain.
fn fingers(
    parts: &HandParts,
    topo: &Topology,
    new_index: &[usize],
    bones: &mut [Bone],
) -> Result<(Vec<Finger>, Vec<Option<usize>>), HandError> {
    let mut fingers: Vec<Finger> = Vec::new();
    let mut chain_predecessor = vec![None; bones.len()];
    for &c in &topo.children[topo.root] {
        let mut chain = vec![new_index[c]];
        let mut at = c;
        while let [next] = topo.children[at].as_slice() {
            chain_predecessor[new_index[*next]] = Some(new_index[at]);
            chain.push(new_index[*next]);
            at = *next;
        }
        let tip = parts.bones[at].tip.expect("leaf tips checked");
        let name = parts.bones[c]
            .finger
            .clone()
            .unwrap_or_else(|| parts.bones[c].name.clone());
        if fingers.iter().any(|f| f.name == name) {
            return Err(HandError::DuplicateFinger(name));
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
    Ok((fingers, chain_predecessor))
}

/// Every capsule, bones parents first, and each bone's range of them.
fn capsules(parts: &HandParts, topo: &Topology) -> (Vec<BoneCapsule>, Vec<Range<usize>>) {
    let mut capsules = Vec::new();
    let mut ranges = vec![0..0; topo.order.len()];
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
        ranges[k] = first..capsules.len();
    }
    (capsules, ranges)
}

/// The couplings by degree-of-freedom index.
fn couplings(parts: &HandParts, model: &HandModel) -> Result<Vec<Coupling>, HandError> {
    parts
        .couplings
        .iter()
        .map(|(follower, leader, ratio)| {
            if !ratio.is_finite() {
                return Err(HandError::CouplingRatio(follower.clone()));
            }
            Ok(Coupling {
                follower: dof_index(model, "a coupling", follower)?,
                leader: dof_index(model, "a coupling", leader)?,
                ratio: *ratio,
                rigid: parts.rigid_couplings,
            })
        })
        .collect()
}
