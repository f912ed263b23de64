//! From a grasp pose found by the search to a simulated grasp: the poses of the example motion
//! (relaxed, open, closed), a controller fitted to that example, and the arm's path (approach
//! along the grasp's approach direction, hold, lift, release, retreat).

use prehensile_control::{fit_controller, BaseMotion, Gains, GraspController, Motion};
use prehensile_core::math::{Point3, Transform, Vec3};
use prehensile_core::search::translate_to_free::hand_root;
use prehensile_core::search::{default_shoulder, GraspPlanner, GraspResult, SearchParams};
use prehensile_core::{GraspMovement, HandModel, ObjectModel, Workspace};

use crate::error::SimError;
use crate::world::arm_trajectory::{ArmTrajectory, Waypoint};

/// A grasp found by the search, as the simulation needs it.
#[derive(Debug, Clone)]
pub struct PlannedGrasp {
    /// The hand's root placement in the grasp, object frame.
    pub root: Transform,
    /// Direction the hand approaches along (unit, object frame).
    pub approach: Vec3,
    /// Joint angles of the movement's start (the open hand).
    pub open: Vec<f64>,
    /// Joint angles of the grasp (fingers at the object).
    pub closed: Vec<f64>,
    /// How far the example's grip presses past [`PlannedGrasp::closed`], per degree of freedom:
    /// [`EXAMPLE_PRESS`] of the movement's closing, zero where there is no object to press.
    pub press: Vec<f64>,
    /// Fingers touching in the found pose.
    pub fingers_touching: usize,
    /// The friction coefficient the search judged the grasp with (`None`: no search).
    pub search_friction: Option<f64>,
}

/// Searches a power grasp (or the hand's first movement) of `object` from the default shoulder
/// ([`default_shoulder`]: 35 cm behind, 20 cm aside and 35 cm above the centre of mass, z up), as
/// `prehensile grasp --movement power` does.
pub fn plan_grasp(hand: &HandModel, object: &ObjectModel) -> Result<PlannedGrasp, SimError> {
    plan_grasp_with(hand, object, SearchParams::default())
}

/// [`plan_grasp`] with the search's parameters (e.g. its validity rule).
pub fn plan_grasp_with(
    hand: &HandModel,
    object: &ObjectModel,
    params: SearchParams,
) -> Result<PlannedGrasp, SimError> {
    plan_grasp_along(hand, object, grasp_movement(hand)?, 0.0, params)
}

/// The movement the grasp scenarios search with: the hand's `power`, else its first.
pub fn grasp_movement(hand: &HandModel) -> Result<&GraspMovement, SimError> {
    Ok(prehensile_core::search::default_movement(hand)?)
}

/// [`plan_grasp_with`] along a given movement, from the default shoulder turned by
/// `shoulder_turn` radians about the vertical through the centre of mass (0: not turned).
pub fn plan_grasp_along(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &GraspMovement,
    shoulder_turn: f64,
    params: SearchParams,
) -> Result<PlannedGrasp, SimError> {
    let hook = object.center_of_mass();
    let turn = nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), shoulder_turn);
    let shoulder = hook + turn * (default_shoulder(hand, &hook, &Vec3::z()) - hook);
    let friction = params.contact_model.friction;
    let mut planner = GraspPlanner::new(hand, object, movement, shoulder, params)?;
    planner.run_to_end();
    planner.best().ok_or_else(|| SimError::NoGrasp {
        movement: movement.name().to_string(),
        object: object.name().to_string(),
        hand: hand.name().to_string(),
        why: planner.current().validity.clone().err(),
    })?;
    let mut ws = Workspace::new(hand);
    let (found, ctx) = planner.chosen_pose(&mut ws);
    let root = hand_root(&ctx.hook_frame(&found.rotation), movement, found.offset);
    Ok(PlannedGrasp {
        root,
        approach: found.rotation * Vec3::y(),
        open: joint_angles(hand, movement.start_rotations()),
        closed: joint_angles(hand, &ws.rotations),
        press: press(movement),
        fingers_touching: found.fingers_touching,
        search_friction: Some(friction),
    })
}

impl PlannedGrasp {
    /// The grasp of a search result (`prehensile grasp`'s output), for the same hand.
    pub fn from_result(hand: &HandModel, result: &GraspResult) -> Result<Self, SimError> {
        let foreign = || SimError::ForeignResult {
            movement: result.movement.clone(),
            angles: result.joints.len(),
            hand: hand.name().to_string(),
            dofs: hand.dof_count(),
            movements: hand
                .movements()
                .iter()
                .map(|m| m.name().to_string())
                .collect(),
        };
        let movement = hand.movement(&result.movement).ok_or_else(foreign)?;
        if result.joints.len() != hand.dof_count() {
            return Err(foreign());
        }
        let [x, y, z, w] = result.hook_rotation_xyzw;
        let rotation =
            prehensile_core::math::Rotation::from_quaternion(nalgebra::Quaternion::new(w, x, y, z));
        let hook_frame = Transform::from_parts(Point3::from(result.hook).coords.into(), rotation);
        Ok(Self {
            root: hand_root(&hook_frame, movement, result.offset),
            approach: rotation * Vec3::y(),
            open: joint_angles(hand, movement.start_rotations()),
            closed: result.joints.iter().map(|j| j.angle).collect(),
            press: press(movement),
            fingers_touching: result.fingers_touching.len(),
            search_friction: Some(result.friction),
        })
    }

    /// The relaxed pose of the example: 30% of the way from open to closed.
    pub fn relaxed(&self) -> Vec<f64> {
        self.open
            .iter()
            .zip(&self.closed)
            .map(|(o, c)| o + 0.3 * (c - o))
            .collect()
    }

    /// The example's grip: the grasp pressed further into the object by
    /// [`PlannedGrasp::press`].
    pub fn pressed(&self) -> Vec<f64> {
        self.closed
            .iter()
            .zip(&self.press)
            .map(|(closed, press)| closed + press)
            .collect()
    }

    /// The synthetic example motion of this grasp: relaxed, open, then the pressed grip.
    pub fn example(&self, hand: &HandModel, gains: &Gains) -> Motion {
        Motion::synthetic_grasp(
            hand.dof_names(),
            &self.relaxed(),
            &self.open,
            &self.pressed(),
            gains,
        )
    }

    /// A controller fitted to [`PlannedGrasp::example`], held open through CLOSING (§7).
    pub fn controller(
        &self,
        hand: &HandModel,
        gravity: &Vec3,
    ) -> Result<GraspController, SimError> {
        let gains = Gains::grasp();
        let palm = self.root * hand.bones()[0].rest;
        let base = BaseMotion::at_rest(palm.rotation.inverse() * gravity);
        fit_controller(hand, &self.example(hand, &gains), gains, true, &base)
            .map_err(SimError::from)
    }

    /// The root's place in the grasp, object frame.
    pub fn place(&self) -> Point3 {
        self.root.translation.vector.into()
    }
}

/// Times of the grasp scenario's phases, seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GraspTimes {
    /// Arrival at the grasp.
    pub arrive: f64,
    /// The object is let go (the hand has closed).
    pub let_go: f64,
    /// Lift starts.
    pub lift: f64,
    /// Lift ends; holding.
    pub lifted: f64,
    /// End of the hold: held and slip are measured here; release is commanded.
    pub release: f64,
    /// End of the retreat.
    pub end: f64,
}

impl Default for GraspTimes {
    fn default() -> Self {
        Self {
            arrive: 1.2,
            let_go: 1.8,
            lift: 2.0,
            lifted: 3.0,
            release: 3.5,
            end: 4.5,
        }
    }
}

impl GraspTimes {
    /// The approach and closing as by default, and a lift that never comes (the hand stays).
    pub fn without_lift() -> Self {
        Self {
            lift: 1e6,
            lifted: 1e6 + 1.0,
            release: 1e6 + 2.0,
            end: 1e6 + 3.0,
            ..Self::default()
        }
    }
}

/// How far past the found grasp the example's grip presses, as a share of the movement's whole
/// closing, on every joint whether or not it moved in the search.
///
/// The grip's squeeze (Eq. 15–16) extrapolates each joint by α times how far it moved from the
/// open pose in the example. A recorded example, as the paper's, moves every joint; a searched
/// grasp often does not: a finger whose first phalanx touches the object at the start of the
/// closing keeps that joint at its start, and the squeeze then presses with nothing there. The
/// human hand's own grasp of the built-in cylinder has the index's two lower joints so, and
/// dropped the cylinder. Pressed by a tenth of the closing, the default `simulate` of seven
/// hands on sphere, box and cylinder (each alone, and the three with one controller) holds 32
/// of 42 objects instead of 23 (docs/QUALITY.md).
pub const EXAMPLE_PRESS: f64 = 0.1;

/// Height of the lift, metres.
pub const LIFT: f64 = 0.10;
/// How far back the approach starts, metres.
pub const APPROACH: f64 = 0.40;

/// The arm: approach from [`APPROACH`] back to the grasp, hold, lift by [`LIFT`] (+z),
/// hold, then retreat along the approach direction.
pub fn grasp_arm(
    grasp: &PlannedGrasp,
    object_pose: &Transform,
    times: &GraspTimes,
) -> ArmTrajectory {
    let at = |back: f64, up: f64| {
        let mut root = *object_pose * grasp.root;
        root.translation.vector +=
            object_pose.rotation * (-grasp.approach * back) + Vec3::new(0.0, 0.0, up);
        root
    };
    ArmTrajectory::new(vec![
        Waypoint {
            time: 0.0,
            root: at(APPROACH, 0.0),
        },
        Waypoint {
            time: times.arrive,
            root: at(0.0, 0.0),
        },
        Waypoint {
            time: times.lift,
            root: at(0.0, 0.0),
        },
        Waypoint {
            time: times.lifted,
            root: at(0.0, LIFT),
        },
        Waypoint {
            time: times.release + 0.2,
            root: at(0.0, LIFT),
        },
        Waypoint {
            time: times.end,
            root: at(APPROACH, LIFT),
        },
    ])
}

impl PlannedGrasp {
    /// Poses without an object: open = the movement's start, closed = 70% of its closing; the
    /// root at the origin. For scenarios without an object (drop, shake, handshake).
    pub fn without_object(hand: &HandModel) -> Result<Self, SimError> {
        let movement = grasp_movement(hand)?;
        let rotations: Vec<_> = (0..hand.bones().len())
            .map(|b| movement.rotation_at(b, 0.7))
            .collect();
        Ok(Self {
            root: Transform::identity(),
            approach: Vec3::y(),
            open: joint_angles(hand, movement.start_rotations()),
            closed: joint_angles(hand, &rotations),
            press: press(movement),
            fingers_touching: 0,
            search_friction: None,
        })
    }
}

/// [`EXAMPLE_PRESS`] of the movement's end minus start joint angles, per degree of freedom.
fn press(movement: &GraspMovement) -> Vec<f64> {
    movement
        .end_angles()
        .iter()
        .zip(movement.start_angles())
        .map(|(end, start)| EXAMPLE_PRESS * (end - start))
        .collect()
}

/// Joint angles (one per degree of freedom) of per-bone joint rotations.
fn joint_angles(hand: &HandModel, rotations: &[prehensile_core::math::Rotation]) -> Vec<f64> {
    let mut q = vec![0.0; hand.dof_count()];
    for (k, bone) in hand.bones().iter().enumerate() {
        let n = bone.joint.dofs();
        bone.joint
            .angles(&rotations[k], &mut q[bone.first_dof..bone.first_dof + n]);
    }
    q
}
