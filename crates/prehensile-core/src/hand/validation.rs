//! The checks a hand passes before it is built: its bones form one tree, every number is finite
//! and hand-sized, joint limits are ordered, couplings form chains.

use std::collections::HashMap;

use super::error::HandError;
use super::limits::{MAX_BONES, MAX_HAND_EXTENT};
use super::model::{HandModel, Joint};
use crate::math::{is_finite_vec, Vec3};

/// Parents-first order, children and root of a bone tree, checked.
pub(super) struct Topology {
    /// Bones parents first.
    pub order: Vec<usize>,
    /// Each bone's children.
    pub children: Vec<Vec<usize>>,
    /// The root bone.
    pub root: usize,
}

/// The tree of bones `names` with `parents`: one root, no cycle, names unique.
pub(super) fn topology(names: &[&str], parents: &[Option<&str>]) -> Result<Topology, HandError> {
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

pub(super) fn check_extent(
    bone: &str,
    what: &'static str,
    points: &[Vec3],
) -> Result<(), HandError> {
    if points.iter().any(|p| p.norm() > MAX_HAND_EXTENT) {
        return Err(HandError::TooFar {
            bone: bone.to_string(),
            what,
        });
    }
    Ok(())
}

/// Couplings must form chains that end at a free degree of freedom: none follows itself, none
/// follows two leaders, and no cycle (a follows b follows a), or `constrain` could not satisfy
/// them all and would silently break one.
pub(super) fn check_couplings(model: &HandModel) -> Result<(), HandError> {
    let name = |k: usize| model.dof_names[k].clone();
    let mut leader_of: Vec<Option<usize>> = vec![None; model.dof_count];
    for c in &model.couplings {
        if c.follower == c.leader {
            return Err(HandError::SelfCoupled(name(c.follower)));
        }
        if leader_of[c.follower].replace(c.leader).is_some() {
            return Err(HandError::TwoLeaders(name(c.follower)));
        }
    }
    for start in 0..model.dof_count {
        let mut k = start;
        for _ in 0..=model.dof_count {
            match leader_of[k] {
                Some(l) if l == start => return Err(HandError::CouplingCycle(name(start))),
                Some(l) => k = l,
                None => break,
            }
        }
    }
    Ok(())
}

pub(super) fn check_limits(bone: &str, joint: &Joint) -> Result<(), HandError> {
    for k in 0..joint.dofs() {
        let [min, max] = joint.limits(k);
        if !min.is_finite() || !max.is_finite() {
            return Err(HandError::NonFinite {
                bone: bone.to_string(),
                what: "joint limits",
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
            what: "joint axis",
        });
    }
    Ok(())
}
