//! A hand given directly as bones, as an importer reads it (MJCF, URDF, glTF), before
//! [`HandModel::from_parts`](super::HandModel::from_parts) checks and builds it.

use super::model::{Inertial, Joint};
use crate::math::{Point3, Transform};

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
    pub inertial: Option<Inertial>,
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
    /// moves without its leader (see [`super::Coupling::rigid`]). False for authored synergies.
    pub rigid_couplings: bool,
    /// End angles of the generic `close` movement by degree-of-freedom name (others stay at the
    /// open pose); empty: every flexion to its upper limit.
    pub close: Vec<(String, f64)>,
}
