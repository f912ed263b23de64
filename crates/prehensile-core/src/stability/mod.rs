//! Whether a grasp holds: contacts with friction, the grasp wrench space and its measures (force
//! closure, Ferrari–Canny ε, the load held along each axis), and thumb opposition.
//!
//! Beyond the thesis, which checks only that fingers touch (its §2.4.2 and §7.2 name stability
//! as the missing piece); the measures are those of GraspIt! (Miller & Allen 2004).

pub mod contacts;
pub mod force_closure;
pub mod grasp_wrench_space;
pub mod normal_cap;

pub use contacts::{find_contacts, Contact};
pub use force_closure::{force_closure_margin, ForceClosure};
pub use grasp_wrench_space::{
    ContactModel, GraspWrenchSpace, Stability, FORCE_CLOSURE_EPSILON, LOAD_DIRECTIONS,
};
pub use normal_cap::narrowest_normal_cap;

use crate::hand::HandModel;
use crate::math::Vec3;

/// The pad normal of `finger`: the normal of its contact nearest the fingertip (on its most
/// distal touching bone), or `None` if the finger does not touch.
pub fn pad_normal(hand: &HandModel, finger: usize, contacts: &[Contact]) -> Option<Vec3> {
    let bones = &hand.fingers()[finger].bones;
    bones.iter().rev().find_map(|&b| {
        contacts
            .iter()
            .filter(|c| c.bone == b)
            .max_by(|x, y| x.capsule.cmp(&y.capsule))
            .map(|c| c.normal)
    })
}

/// Angle between two pad normals, radians: π when the pads push straight at each other.
pub fn opposition_angle(a: &Vec3, b: &Vec3) -> f64 {
    a.dot(b).clamp(-1.0, 1.0).acos()
}
