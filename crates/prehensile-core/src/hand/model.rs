//! The validated, immutable hand model.

use crate::hand::movement::GraspMovement;
use crate::math::{Point3, Rotation, Transform, Vec3};

/// A rotation axis fixed in a bone's frame, with the limits of its angle in radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    /// Unit axis in the bone frame.
    pub axis: nalgebra::Unit<Vec3>,
    /// `[min, max]` angle.
    pub limits: [f64; 2],
}

impl Axis {
    /// An axis from a direction and limits.
    pub fn new(axis: Vec3, limits: [f64; 2]) -> Self {
        Self {
            axis: nalgebra::Unit::new_normalize(axis),
            limits,
        }
    }
}

/// A joint: how a bone may rotate relative to its parent.
#[derive(Debug, Clone, PartialEq)]
pub enum Joint {
    /// No motion.
    Fixed,
    /// One axis (for hands written in TOML: flexion about the bone's −x).
    Hinge(Axis),
    /// Two axes: `flexion` turns first (inner), `abduction` after it (outer):
    /// R = R(abduction)·R(flexion). Degree of freedom 0 is flexion, 1 abduction.
    TwoAxis {
        /// Inner axis (degree of freedom 0).
        flexion: Axis,
        /// Outer axis (degree of freedom 1).
        abduction: Axis,
    },
    /// A rotation vector in the bone frame, each component limited.
    Ball {
        /// Per-component `[min, max]`.
        limits: [[f64; 2]; 3],
    },
}

impl Joint {
    /// Number of degrees of freedom.
    pub fn dofs(&self) -> usize {
        match self {
            Joint::Fixed => 0,
            Joint::Hinge(_) => 1,
            Joint::TwoAxis { .. } => 2,
            Joint::Ball { .. } => 3,
        }
    }

    /// Limits of degree of freedom `k`.
    pub fn limits(&self, k: usize) -> [f64; 2] {
        match (self, k) {
            (Joint::Hinge(a), 0) | (Joint::TwoAxis { flexion: a, .. }, 0) => a.limits,
            (Joint::TwoAxis { abduction, .. }, 1) => abduction.limits,
            (Joint::Ball { limits }, k) if k < 3 => limits[k],
            _ => [0.0, 0.0],
        }
    }

    /// The joint rotation for the given angles (one per degree of freedom).
    pub fn rotation(&self, angles: &[f64]) -> Rotation {
        match self {
            Joint::Fixed => Rotation::identity(),
            Joint::Hinge(a) => Rotation::from_axis_angle(&a.axis, angles[0]),
            Joint::TwoAxis { flexion, abduction } => {
                Rotation::from_axis_angle(&abduction.axis, angles[1])
                    * Rotation::from_axis_angle(&flexion.axis, angles[0])
            }
            Joint::Ball { .. } => {
                Rotation::from_scaled_axis(Vec3::new(angles[0], angles[1], angles[2]))
            }
        }
    }

    /// The angles of a joint rotation (the inverse of [`Joint::rotation`] for rotations the joint
    /// can make; the nearest decomposition otherwise), written into `out`.
    pub fn angles(&self, r: &Rotation, out: &mut [f64]) {
        match self {
            Joint::Fixed => {}
            Joint::Hinge(a) => out[0] = r.scaled_axis().dot(&a.axis),
            Joint::TwoAxis { flexion, abduction } => {
                // R·i = R(o, b)·i for the inner axis i: b is i's turn about the outer axis o.
                let (i, o) = (flexion.axis.into_inner(), abduction.axis.into_inner());
                let turned = r * i;
                let b = o
                    .cross(&i)
                    .dot(&turned)
                    .atan2(i.dot(&turned) - o.dot(&i) * o.dot(&turned));
                let rest = Rotation::from_axis_angle(&abduction.axis, -b) * r;
                out[0] = rest.scaled_axis().dot(&i);
                out[1] = b;
            }
            Joint::Ball { .. } => out[..3].copy_from_slice(r.scaled_axis().as_slice()),
        }
    }
}

/// One bone of the hand.
#[derive(Debug, Clone, PartialEq)]
pub struct Bone {
    /// Unique name.
    pub name: String,
    /// Index of the parent bone (always smaller than this bone's index), `None` for the root.
    pub parent: Option<usize>,
    /// Bone frame relative to the parent's frame when all joint angles are zero.
    pub rest: Transform,
    /// The joint that rotates this bone.
    pub joint: Joint,
    /// Index of the first degree of freedom of this bone in a joint-angle vector.
    pub first_dof: usize,
    /// Finger this bone belongs to, `None` for the root.
    pub finger: Option<usize>,
    /// Mass properties, when the source file gives them (URDF, MJCF).
    pub inertial: Option<Inertial>,
}

/// A bone's mass, centre of mass and rotational inertia about the centre of mass, in the bone
/// frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertial {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass, bone frame, metres.
    pub center_of_mass: Point3,
    /// Inertia tensor about the centre of mass, bone frame axes, kg·m².
    pub inertia: nalgebra::Matrix3<f64>,
}

/// A capsule attached to a bone, endpoints in the bone frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoneCapsule {
    /// Bone it moves with.
    pub bone: usize,
    /// First end, bone frame.
    pub a: Point3,
    /// Second end, bone frame.
    pub b: Point3,
    /// Radius in metres.
    pub radius: f64,
}

/// A finger: a chain of bones from a child of the root to a fingertip. A finger's bones have
/// consecutive indices, parents first.
#[derive(Debug, Clone, PartialEq)]
pub struct Finger {
    /// Name (e.g. `thumb`, `index`).
    pub name: String,
    /// Bones from the chain's first bone to its last.
    pub bones: Vec<usize>,
    /// Fingertip in the last bone's frame.
    pub tip: Point3,
}

/// `angles[follower] = ratio * angles[leader]`, indices into a joint-angle vector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coupling {
    /// Derived degree of freedom.
    pub follower: usize,
    /// Driving degree of freedom.
    pub leader: usize,
    /// Ratio.
    pub ratio: f64,
    /// Mechanical (a tendon, a mimic joint): closing stops the follower when its leader stops,
    /// and a pose holds the leader where the follower reaches a limit. An authored synergy (the
    /// human hand's distal ≈ ⅔ middle, §4.1.2.2) is soft: the follower takes `ratio × leader`,
    /// then its limits, and a blocked middle phalanx does not stop the distal one.
    pub rigid: bool,
}

/// An immutable, validated hand. Build it with [`HandModel::from_description`].
#[derive(Debug, Clone, PartialEq)]
pub struct HandModel {
    pub(crate) name: String,
    pub(crate) description: String,
    pub(crate) bones: Vec<Bone>,
    pub(crate) capsules: Vec<BoneCapsule>,
    pub(crate) fingers: Vec<Finger>,
    pub(crate) couplings: Vec<Coupling>,
    pub(crate) movements: Vec<GraspMovement>,
    pub(crate) dof_count: usize,
    pub(crate) chain_predecessor: Vec<Option<usize>>,
    pub(crate) capsule_ranges: Vec<std::ops::Range<usize>>,
    pub(crate) dof_names: Vec<String>,
    /// [`super::closing_facts::fingers_close_apart`], worked out once when the hand is built.
    pub(crate) fingers_close_apart: bool,
    /// Per finger, [`super::closing_facts::finger_floor_radius`], worked out once when the hand is
    /// built.
    pub(crate) finger_floor_radii: Vec<Option<f64>>,
    /// The bone of each degree of freedom, worked out once when the hand is built.
    pub(crate) dof_bones: Vec<usize>,
}

impl HandModel {
    /// Name of the hand.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// One-line description.
    pub fn description(&self) -> &str {
        &self.description
    }

    /// Bones, parents first (`parent < index`); bone 0 is the root.
    pub fn bones(&self) -> &[Bone] {
        &self.bones
    }

    /// Every capsule, in bone order.
    pub fn capsules(&self) -> &[BoneCapsule] {
        &self.capsules
    }

    /// Fingers.
    pub fn fingers(&self) -> &[Finger] {
        &self.fingers
    }

    /// Coupling rules.
    pub fn couplings(&self) -> &[Coupling] {
        &self.couplings
    }

    /// Grasp movements; the last is always the generic `close`.
    pub fn movements(&self) -> &[GraspMovement] {
        &self.movements
    }

    /// The movement with this name.
    pub fn movement(&self, name: &str) -> Option<&GraspMovement> {
        self.movements.iter().find(|m| m.name() == name)
    }

    /// Adds `movement`, replacing the one of the same name if there is one.
    pub fn set_movement(&mut self, movement: GraspMovement) {
        match self
            .movements
            .iter_mut()
            .find(|m| m.name() == movement.name())
        {
            Some(m) => *m = movement,
            None => self.movements.push(movement),
        }
    }

    /// Name of every degree of freedom: the source file's joint names for imported hands,
    /// `bone.flexion`, `bone.abduction` or `bone.x|y|z` for hands written in TOML.
    pub fn dof_names(&self) -> &[String] {
        &self.dof_names
    }

    /// The `[min, max]` limits of every degree of freedom, in [`HandModel::dof_names`] order.
    pub fn dof_limits(&self) -> Vec<[f64; 2]> {
        self.bones
            .iter()
            .flat_map(|bone| (0..bone.joint.dofs()).map(|k| bone.joint.limits(k)))
            .collect()
    }

    /// Total degrees of freedom.
    pub fn dof_count(&self) -> usize {
        self.dof_count
    }

    /// True for a left hand: the thumb's (else the first finger's) base lies on the +x side of
    /// the hand frame, where a right hand has its little finger (x runs across the knuckles from
    /// the index at −x).
    pub fn is_left(&self) -> bool {
        let finger = self
            .fingers
            .iter()
            .find(|f| f.name.to_lowercase().contains("thumb"))
            .or(self.fingers.first());
        let Some(&base) = finger.and_then(|f| f.bones.first()) else {
            return false;
        };
        // Bone frames chain from the root's frame; the root's rest turns it into the hand frame
        // (an imported hand's root frame is its file's).
        let mut t = Transform::identity();
        let mut b = Some(base);
        while let Some(i) = b.filter(|&i| i != 0) {
            t = self.bones[i].rest * t;
            b = self.bones[i].parent;
        }
        (self.bones[0].rest.rotation * t.translation.vector).x > 0.0
    }

    /// Index of the bone with this name.
    pub fn bone_index(&self, name: &str) -> Option<usize> {
        self.bones.iter().position(|b| b.name == name)
    }

    /// Index of the finger with this name.
    pub fn finger_index(&self, name: &str) -> Option<usize> {
        self.fingers.iter().position(|f| f.name == name)
    }

    /// The previous bone in the same finger chain, `None` for a chain's first bone and the root.
    pub fn chain_predecessor(&self, bone: usize) -> Option<usize> {
        self.chain_predecessor[bone]
    }

    /// Can the fingers close one after another with the same outcome as together
    /// ([`super::closing_facts::fingers_close_apart`], kept from when the hand was built)?
    pub fn fingers_close_apart(&self) -> bool {
        self.fingers_close_apart
    }

    /// The radius finger `finger` adds to a hook's depth in its fDist floor, `None` for a finger
    /// that adds no floor ([`super::closing_facts::finger_floor_radius`], kept from when the hand was
    /// built).
    pub fn finger_floor_radius(&self, finger: usize) -> Option<f64> {
        self.finger_floor_radii[finger]
    }

    /// The capsules attached to `bone`.
    pub fn bone_capsules(&self, bone: usize) -> &[BoneCapsule] {
        &self.capsules[self.capsule_range(bone)]
    }

    /// Indices into [`HandModel::capsules`] of the capsules attached to `bone`.
    pub fn capsule_range(&self, bone: usize) -> std::ops::Range<usize> {
        self.capsule_ranges[bone].clone()
    }

    /// The bone whose joint has degree of freedom `dof` (less than [`HandModel::dof_count`]).
    pub fn bone_of_dof(&self, dof: usize) -> usize {
        self.dof_bones[dof]
    }

    /// Joint angles with limits applied and coupling rules enforced. For a [rigid](Coupling::rigid)
    /// coupling the leader is held where its follower reaches a limit (`follower = ratio ×
    /// leader` exactly), so a pose interpolated linearly between two constrained poses obeys it
    /// too.
    pub fn constrain(&self, angles: &mut [f64]) {
        let limits = |dof: usize| {
            let bone = &self.bones[self.bone_of_dof(dof)];
            bone.joint.limits(dof - bone.first_dof)
        };
        for c in &self.couplings {
            if c.rigid && c.ratio != 0.0 {
                let [lo, hi] = limits(c.leader);
                let [flo, fhi] = limits(c.follower);
                let (a, b) = (flo / c.ratio, fhi / c.ratio);
                angles[c.leader] = angles[c.leader].clamp(lo, hi).clamp(a.min(b), a.max(b));
            }
            angles[c.follower] = c.ratio * angles[c.leader];
        }
        for bone in &self.bones {
            for k in 0..bone.joint.dofs() {
                let [lo, hi] = bone.joint.limits(k);
                let a = &mut angles[bone.first_dof + k];
                *a = a.clamp(lo, hi);
            }
        }
    }

    /// Local joint rotation of every bone for a joint-angle vector.
    pub fn joint_rotations(&self, angles: &[f64], out: &mut [Rotation]) {
        for (i, bone) in self.bones.iter().enumerate() {
            let n = bone.joint.dofs();
            out[i] = bone
                .joint
                .rotation(&angles[bone.first_dof..bone.first_dof + n]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_axis_angles_round_trip_for_any_orthogonal_axes() {
        for (i, o) in [
            (-Vec3::x(), Vec3::y()),
            (Vec3::x(), Vec3::y()),
            (Vec3::new(1.0, 1.0, 0.0), Vec3::new(-1.0, 1.0, 0.3)),
        ] {
            let o = o - i * (o.dot(&i) / i.norm_squared());
            let joint = Joint::TwoAxis {
                flexion: Axis::new(i, [-2.0, 2.0]),
                abduction: Axis::new(o, [-1.0, 1.0]),
            };
            for (a, b) in [(0.3, -0.2), (1.4, 0.5), (-0.7, 0.9)] {
                let r = joint.rotation(&[a, b]);
                let mut out = [0.0; 2];
                joint.angles(&r, &mut out);
                assert!(
                    (out[0] - a).abs() < 1e-9 && (out[1] - b).abs() < 1e-9,
                    "{out:?} vs {a}, {b}"
                );
            }
        }
        let hinge = Joint::Hinge(Axis::new(Vec3::new(0.0, 0.0, 2.0), [-1.0, 1.0]));
        let mut out = [0.0];
        hinge.angles(&hinge.rotation(&[-0.4]), &mut out);
        assert!((out[0] + 0.4).abs() < 1e-12);
    }
}
