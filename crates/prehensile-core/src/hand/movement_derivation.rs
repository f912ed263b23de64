//! Power and precision movements derived for any hand (beyond the thesis, whose movements are
//! authored per hand, §5.3): the end pose brings the fingertips to targets in front of the palm,
//! each finger's joints chosen within their limits by coordinate descent on the distance from
//! its tip to its target. Every joint of a finger takes part, whatever its axis, so a thumb whose
//! joints turn about unusual axes still comes across to oppose the fingers.
//!
//! In the hand frame (z along the fingers, y out of the palm, x across the knuckles), with K the
//! centroid of the non-thumb fingers' first joints and L their mean length:
//! - **power**: the grasp center C = K + 0.45·L·y; each finger's tip goes to C shifted across by
//!   the finger's own x offset (the fingers curl side by side around an object at C), the thumb's
//!   tip first toward a point far out of the palm beyond C (`POWER_THUMB_AIM`, reached half-way
//!   through the closing: the movement's via pose), then folding in toward C itself, so that it
//!   opposes the fingers from the near side of an object as wide as the hand, past its equator,
//!   and still comes onto one much narrower than the hand;
//! - **precision**: the pinch point P = (index's first joint) + 0.5·L·y + 0.45·L·z; the thumb's
//!   and the index's tips both go to P (their pads meet, so an object between them is squeezed
//!   from opposite sides), the other fingers follow the index side by side. Contact fingers:
//!   thumb, then index.
//!
//! Fingers other than the thumb keep out of each other: each is solved with a penalty on its
//! capsules' overlap with its neighbours beyond what they overlap at rest.
//!
//! The movements start from the open pose (every angle zero, clamped into its limits) and end at
//! the targets; finger closing stops each bone at its first contact on the way.

use crate::geometry::distance_squared_segment_segment;
use crate::hand::kinematics::forward_kinematics_of;
use crate::hand::movement::GraspMovement;
use crate::hand::HandModel;
use crate::math::{Point3, Rotation, Transform, Vec3};

/// Metres of tip distance one metre of finger–finger capsule overlap costs.
const OVERLAP_WEIGHT: f64 = 10.0;
/// Smallest coordinate-descent step, radians.
const MIN_STEP: f64 = 1e-4;
/// Largest number of sweeps over a finger's joints.
const MAX_SWEEPS: usize = 400;
/// Where the power movement's thumb tip aims, from the grasp center, in mean finger lengths:
/// across toward the fingers' middle line, out of the palm, along the fingers (negative: toward
/// the wrist). Far out of the palm, so the thumb swings out of the palm plane and comes down the
/// near side of an object, past the equator of one as wide as the hand, opposite the fingers
/// curled over its far side. Aimed at the grasp center itself, as the fingers are, the thumb
/// folded under the knuckles and met such an object at its equator: the Shadow hand's sphere
/// grasps then had every contact normal within 69–73° of one direction (docs/QUALITY.md).
const POWER_THUMB_AIM: [f64; 3] = [0.15, 1.5, -0.3];
/// Fraction of the power closing at which the thumb is at `POWER_THUMB_AIM`; after it, the thumb
/// folds in toward the grasp center. Aimed only out of the palm, the thumb passed
/// beside objects narrower than the hand: the Shadow hand's power grasps of the 4.5 cm lemon and
/// the 6.6 cm can touched with the four fingers alone in 3 of 38 (docs/QUALITY.md).
const POWER_THUMB_VIA_FRACTION: f64 = 0.5;

/// The thumb: the finger whose name contains "thumb" (or is "th"); `None` if there is none.
pub fn thumb(hand: &HandModel) -> Option<usize> {
    hand.fingers().iter().position(|f| {
        let n = f.name.to_lowercase();
        n.contains("thumb") || n == "th"
    })
}

/// The index finger: the one named "index" (or "ff"), else the non-thumb finger whose first joint
/// is nearest the thumb's.
pub fn index(hand: &HandModel, thumb: usize) -> Option<usize> {
    if let Some(i) = hand.fingers().iter().position(|f| {
        let n = f.name.to_lowercase();
        n.contains("index") || n == "ff"
    }) {
        return Some(i);
    }
    let rest = rest_pose(hand);
    let base = |f: usize| rest[hand.fingers()[f].bones[0]].translation.vector;
    (0..hand.fingers().len())
        .filter(|&f| f != thumb)
        .min_by(|&a, &b| {
            (base(a) - base(thumb))
                .norm()
                .total_cmp(&(base(b) - base(thumb)).norm())
        })
}

/// Adds the derived `power` and `precision` movements to a hand that has no movement of that
/// name (an imported hand has only `close`); a hand without a thumb gets neither.
pub fn add_derived_movements(hand: &mut HandModel) {
    type Derivation = fn(&HandModel) -> Option<GraspMovement>;
    let derivations: [(&str, Derivation); 2] =
        [("power", derive_power), ("precision", derive_precision)];
    for (name, derive) in derivations {
        // Derived only when missing: each derivation is a descent over every finger's joints.
        if hand.movement(name).is_none() {
            if let Some(m) = derive(hand) {
                hand.movements.push(m);
            }
        }
    }
}

/// The derived power movement, or `None` for a hand without a thumb or other fingers.
pub fn derive_power(hand: &HandModel) -> Option<GraspMovement> {
    let frame = PalmFrame::new(hand)?;
    let center = frame.knuckles + Vec3::y() * (0.45 * frame.length);
    let [across, out, along] = POWER_THUMB_AIM;
    let toward_middle = (frame.knuckles.x - frame.base(frame.thumb).x).signum();
    let thumb_aim = center
        + (Vec3::x() * (toward_middle * across) + Vec3::y() * out + Vec3::z() * along)
            * frame.length;
    let targets: Vec<Point3> = (0..hand.fingers().len())
        .map(|f| {
            if f == frame.thumb {
                thumb_aim
            } else {
                center + Vec3::x() * frame.base(f).x - Vec3::x() * frame.knuckles.x
            }
        })
        .collect();
    let wide = reach_targets(hand, &targets);
    let mut end = wide.clone();
    reach_target(hand, &mut end, frame.thumb, &center);
    let thumb_dofs = finger_dofs(hand, frame.thumb);
    let via: Vec<Option<f64>> = (0..hand.dof_count())
        .map(|k| thumb_dofs.contains(&k).then_some(wide[k]))
        .collect();
    GraspMovement::to_end_pose(hand, "power", end, center, Vec::new())
        .through(hand, POWER_THUMB_VIA_FRACTION, &via)
        .ok()
}

/// The derived precision movement (thumb and index pinch), or `None` for a hand without a
/// thumb or other fingers.
pub fn derive_precision(hand: &HandModel) -> Option<GraspMovement> {
    let frame = PalmFrame::new(hand)?;
    let index = index(hand, frame.thumb)?;
    let pinch = frame.base(index) + (Vec3::y() * 0.5 + Vec3::z() * 0.45) * frame.length;
    let targets: Vec<Point3> = (0..hand.fingers().len())
        .map(|f| {
            if f == frame.thumb || f == index {
                pinch
            } else {
                pinch + Vec3::x() * (frame.base(f).x - frame.base(index).x)
            }
        })
        .collect();
    let end = reach_targets(hand, &targets);
    Some(GraspMovement::to_end_pose(
        hand,
        "precision",
        end,
        pinch,
        vec![frame.thumb, index],
    ))
}

/// Where the palm is, at rest.
struct PalmFrame {
    bases: Vec<Point3>,
    thumb: usize,
    knuckles: Point3,
    length: f64,
}

impl PalmFrame {
    fn new(hand: &HandModel) -> Option<Self> {
        let thumb = thumb(hand)?;
        let rest = rest_pose(hand);
        let fingers = hand.fingers();
        let bases: Vec<Point3> = fingers
            .iter()
            .map(|f| rest[f.bones[0]].translation.vector.into())
            .collect();
        let others: Vec<usize> = (0..fingers.len()).filter(|&f| f != thumb).collect();
        if others.is_empty() {
            return None;
        }
        let knuckles = Point3::from(
            others
                .iter()
                .fold(Vec3::zeros(), |s, &f| s + bases[f].coords)
                / others.len() as f64,
        );
        let length = others
            .iter()
            .map(|&f| (tip(hand, &rest, f) - bases[f]).norm())
            .sum::<f64>()
            / others.len() as f64;
        Some(Self {
            bases,
            thumb,
            knuckles,
            length,
        })
    }

    fn base(&self, finger: usize) -> Point3 {
        self.bases[finger]
    }
}

/// Bone transforms of the open pose (angles zero, constrained), root at the origin.
fn rest_pose(hand: &HandModel) -> Vec<Transform> {
    hand.pose_transforms(&Transform::identity(), &rotations(hand, &open_angles(hand)))
}

fn open_angles(hand: &HandModel) -> Vec<f64> {
    let mut q = vec![0.0; hand.dof_count()];
    hand.constrain(&mut q);
    q
}

fn rotations(hand: &HandModel, q: &[f64]) -> Vec<Rotation> {
    let mut r = vec![Rotation::identity(); hand.bones().len()];
    hand.joint_rotations(q, &mut r);
    r
}

/// A capsule placed in the hand frame: its ends and radius.
type PlacedCapsule = (Point3, Point3, f64);

/// Summed overlap depth (metres) of finger `f`'s capsules with those of fingers `others`, all
/// placed by `world`.
fn finger_overlap(hand: &HandModel, world: &[Transform], f: usize, others: &[usize]) -> f64 {
    let (mut own, mut placed_others) = (Vec::new(), Vec::new());
    place_capsules(hand, world, f, &mut own);
    for &g in others {
        place_capsules(hand, world, g, &mut placed_others);
    }
    overlap_between(&own, &placed_others)
}

/// Appends finger `finger`'s capsules, placed by `world`, to `placed`.
fn place_capsules(
    hand: &HandModel,
    world: &[Transform],
    finger: usize,
    placed: &mut Vec<PlacedCapsule>,
) {
    for &b in &hand.fingers()[finger].bones {
        for c in hand.bone_capsules(b) {
            placed.push((world[b] * c.a, world[b] * c.b, c.radius));
        }
    }
}

/// Summed overlap depth of every capsule of `own` with every capsule of `others`, metres.
fn overlap_between(own: &[PlacedCapsule], others: &[PlacedCapsule]) -> f64 {
    let mut sum = 0.0;
    for one in own {
        for other in others {
            sum += capsule_overlap(one, other);
        }
    }
    sum
}

/// How deep two capsules (ends and radius) overlap, metres: 0 when they are apart.
fn capsule_overlap((a1, b1, r1): &PlacedCapsule, (a2, b2, r2): &PlacedCapsule) -> f64 {
    // Capsules whose bounding spheres keep them more than the radii apart are exactly 0, as the
    // distance below would find (the 1 nm covers its rounding); most pairs are such.
    let reach = 0.5 * ((b1 - a1).norm() + (b2 - a2).norm()) + r1 + r2 + 1e-9;
    if (nalgebra::center(a1, b1) - nalgebra::center(a2, b2)).norm_squared() > reach * reach {
        return 0.0;
    }
    let d = distance_squared_segment_segment(a1, b1, a2, b2).sqrt();
    (r1 + r2 - d).max(0.0)
}

fn tip(hand: &HandModel, world: &[Transform], finger: usize) -> Point3 {
    let f = &hand.fingers()[finger];
    world[*f.bones.last().expect("fingers have bones")] * f.tip
}

/// Joint angles bringing each finger's tip as near its target as the limits allow, from the
/// open pose ([`reach_target`] finger by finger).
fn reach_targets(hand: &HandModel, targets: &[Point3]) -> Vec<f64> {
    let mut q = open_angles(hand);
    for (f, target) in targets.iter().enumerate() {
        reach_target(hand, &mut q, f, target);
    }
    q
}

/// The degrees of freedom of finger `f`'s joints.
fn finger_dofs(hand: &HandModel, f: usize) -> Vec<usize> {
    hand.fingers()[f]
        .bones
        .iter()
        .flat_map(|&b| {
            let bone = &hand.bones()[b];
            bone.first_dof..bone.first_dof + bone.joint.dofs()
        })
        .collect()
}

/// Moves finger `f`'s joints in `q` to bring its tip as near `target` as the limits allow
/// (coordinate descent with a halving step; couplings applied after every move).
///
/// A finger other than the thumb must not sink into its neighbours beyond what they overlap at
/// rest: a penalty on the summed capsule overlap keeps side-by-side fingers from converging on
/// one target (in an engine that collides fingers with each other, as MuJoCo does, they would
/// push each other and the object aside). The thumb is meant to meet the fingers and is exempt.
fn reach_target(hand: &HandModel, q: &mut [f64], f: usize, target: &Point3) {
    let rest = rest_pose(hand);
    let thumb_finger = thumb(hand);
    let dofs = finger_dofs(hand, f);
    let neighbours: Vec<usize> = if Some(f) == thumb_finger {
        Vec::new()
    } else {
        (0..hand.fingers().len())
            .filter(|&g| g != f && Some(g) != thumb_finger)
            .collect()
    };
    let rest_overlap = finger_overlap(hand, &rest, f, &neighbours);
    // Buffers for the thousands of poses the descent tries, which place only the bones it reads:
    // the root's, the finger's and its neighbours'. The root and the neighbours move only when
    // a coupling moves them with the finger, so their capsules are placed again only then.
    let mut posed: Vec<usize> = std::iter::once(f)
        .chain(neighbours.iter().copied())
        .flat_map(|g| hand.fingers()[g].bones.iter().copied())
        .chain([0])
        .collect();
    posed.sort_unstable();
    let own_bones = &hand.fingers()[f].bones;
    let held_dofs: Vec<usize> = std::iter::once(0)
        .chain(
            neighbours
                .iter()
                .flat_map(|&g| hand.fingers()[g].bones.iter().copied()),
        )
        .flat_map(|b| {
            let bone = &hand.bones()[b];
            bone.first_dof..bone.first_dof + bone.joint.dofs()
        })
        .collect();
    // The held angles' bits when the neighbours' capsules were placed.
    let mut held_at: Option<Vec<u64>> = None;
    let mut rotations = vec![Rotation::identity(); hand.bones().len()];
    let mut world = vec![Transform::identity(); hand.bones().len()];
    let (mut own, mut others) = (Vec::new(), Vec::new());
    let mut distance = |q: &[f64]| {
        let held = held_at
            .as_ref()
            .is_some_and(|at| held_dofs.iter().zip(at).all(|(&k, &v)| q[k].to_bits() == v));
        let bones = if held { own_bones } else { &posed };
        for &b in bones {
            let bone = &hand.bones()[b];
            rotations[b] = bone
                .joint
                .rotation(&q[bone.first_dof..bone.first_dof + bone.joint.dofs()]);
        }
        forward_kinematics_of(hand, &Transform::identity(), &rotations, bones, &mut world);
        if !held {
            others.clear();
            for &g in &neighbours {
                place_capsules(hand, &world, g, &mut others);
            }
            held_at = Some(held_dofs.iter().map(|&k| q[k].to_bits()).collect());
        }
        own.clear();
        place_capsules(hand, &world, f, &mut own);
        let overlap = overlap_between(&own, &others);
        (tip(hand, &world, f) - target).norm() + OVERLAP_WEIGHT * (overlap - rest_overlap).max(0.0)
    };
    let mut best = distance(q);
    let mut trial = q.to_vec();
    let mut step = 0.25;
    let mut sweeps = 0;
    while step > MIN_STEP && sweeps < MAX_SWEEPS {
        sweeps += 1;
        let mut moved = false;
        for &k in &dofs {
            for sign in [1.0, -1.0] {
                trial.copy_from_slice(q);
                trial[k] += sign * step;
                hand.constrain(&mut trial);
                if trial[k] == q[k] {
                    continue;
                }
                let d = distance(&trial);
                if d < best - 1e-12 {
                    best = d;
                    q.copy_from_slice(&trial);
                    moved = true;
                    break;
                }
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The bounding-sphere shortcut changes no overlap, to the last bit, also for capsules
        /// placed just apart, just touching and crossing.
        #[test]
        fn the_overlap_shortcut_changes_nothing(
            a1 in prop::array::uniform3(-0.05f64..0.05),
            along1 in prop::array::uniform3(-0.04f64..0.04),
            along2 in prop::array::uniform3(-0.04f64..0.04),
            gap in -0.01f64..0.01,
            side in prop::array::uniform3(-1.0f64..1.0),
            r1 in 0.001f64..0.015,
            r2 in 0.001f64..0.015,
        ) {
            let a1 = Point3::from(a1);
            let b1 = a1 + Vec3::from(along1);
            // The second capsule's near end `r1 + r2 + gap` from the first's axis, sideways.
            let side = Vec3::from(side).try_normalize(1e-9).unwrap_or_else(Vec3::x);
            let a2 = b1 + side * (r1 + r2 + gap);
            let b2 = a2 + Vec3::from(along2);
            let d = distance_squared_segment_segment(&a1, &b1, &a2, &b2).sqrt();
            let plain = (r1 + r2 - d).max(0.0);
            let shortcut = capsule_overlap(&(a1, b1, r1), &(a2, b2, r2));
            prop_assert_eq!(shortcut.to_bits(), plain.to_bits());
        }
    }
}
