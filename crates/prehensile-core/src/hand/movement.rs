//! Grasp movements (§5.3, §6.3.2): a start pose and an end pose, interpolated per bone by slerp.
//! Beyond the thesis, a movement may pass through a via pose on the way (see [`Via`]). What a
//! movement is; [`GraspMovement::from_description`] and its siblings build one for a hand.

use crate::geometry::slerp_path::SlerpPath;
use crate::math::{Point3, Rotation};

/// A grasp movement of one hand: start and end joint rotations, its grasp center, and the
/// fingers that must touch for the grasp to count.
#[derive(Debug, Clone, PartialEq)]
pub struct GraspMovement {
    pub(super) name: String,
    pub(super) start_angles: Vec<f64>,
    pub(super) end_angles: Vec<f64>,
    pub(super) start: Vec<Rotation>,
    /// Every bone's slerp from start to end (kept with the via pose's too: finger closing
    /// interpolates tens of thousands of times per search).
    pub(super) paths: Vec<SlerpPath>,
    pub(super) grasp_center: Point3,
    pub(super) contact_fingers: Vec<usize>,
    pub(super) via: Option<Via>,
}

/// A pose a movement passes through at a fraction of its closing, beyond the thesis's straight
/// start → end interpolation: bones go by slerp from start to via, then from via to end. The
/// derived power movement uses it to swing the thumb wide out of the palm first and fold it in
/// after, so that it comes down on the near side of an object as wide as the hand and still
/// reaches one much narrower (docs/QUALITY.md).
#[derive(Debug, Clone, PartialEq)]
pub struct Via {
    pub(super) fraction: f64,
    pub(super) angles: Vec<f64>,
    /// Every bone's slerp from the movement's start to this pose.
    pub(super) paths_in: Vec<SlerpPath>,
    /// Every bone's slerp from this pose to the movement's end.
    pub(super) paths_out: Vec<SlerpPath>,
}

impl Via {
    /// Fraction of the closing (strictly between 0 and 1) at which the movement is at this pose.
    pub fn fraction(&self) -> f64 {
        self.fraction
    }

    /// Joint angles of the pose (radians, couplings applied).
    pub fn angles(&self) -> &[f64] {
        &self.angles
    }
}

impl GraspMovement {
    /// Name of the movement.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Grasp center in the hand (root bone) frame (§5.2.1).
    pub fn grasp_center(&self) -> Point3 {
        self.grasp_center
    }

    /// Fingers (indices) that must touch the object.
    pub fn contact_fingers(&self) -> &[usize] {
        &self.contact_fingers
    }

    /// Joint angles of the start pose (radians, couplings applied).
    pub fn start_angles(&self) -> &[f64] {
        &self.start_angles
    }

    /// Joint angles of the end pose.
    pub fn end_angles(&self) -> &[f64] {
        &self.end_angles
    }

    /// Start joint rotation of every bone.
    pub fn start_rotations(&self) -> &[Rotation] {
        &self.start
    }

    /// The pose the movement passes through on the way, if any.
    pub fn via(&self) -> Option<&Via> {
        self.via.as_ref()
    }

    /// Joint rotation of `bone` at fraction `f` ∈ [0, 1] of the movement.
    #[inline]
    pub fn rotation_at(&self, bone: usize, f: f64) -> Rotation {
        match &self.via {
            None => self.paths[bone].at(f),
            Some(v) if f <= v.fraction => v.paths_in[bone].at(f / v.fraction),
            Some(v) => v.paths_out[bone].at((f - v.fraction) / (1.0 - v.fraction)),
        }
    }

    /// The degrees of freedom the via pose turns off their straight start–end way, with their
    /// via angles (`None` for the others), and its fraction: what [`GraspMovement::through`]
    /// takes to give a movement with other start or end angles the same detour. `None` without
    /// a via pose.
    pub fn via_detour(&self) -> Option<(f64, Vec<Option<f64>>)> {
        let via = self.via.as_ref()?;
        let detour = via
            .angles
            .iter()
            .zip(self.start_angles.iter().zip(&self.end_angles))
            .map(|(&v, (s, e))| {
                let straight = s + via.fraction * (e - s);
                ((v - straight).abs() > 1e-12).then_some(v)
            })
            .collect();
        Some((via.fraction, detour))
    }
}
