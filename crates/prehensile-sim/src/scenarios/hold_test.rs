//! The hold test: does a grasp found by the search hold the object against a load in every
//! direction? The hand closes on the object (held in place) with grip strength α, the paper's
//! squeeze past contact (Eq. 15–16); the object is let go with gravity along one of the six axis
//! directions, the arm kept still; after one second the object counts as held in that direction
//! if it moved less than [`HOLD_MOVE`] and turned less than [`HOLD_TURN_DEGREES`] in the hand.
//!
//! Each direction is its own run from the same start: the same arm path, controller and closing;
//! only gravity (and its compensation in the hand) differs, and it acts on the object only after
//! let-go, since the object is fixed until then.

use prehensile_control::GraspController;
use prehensile_core::math::Vec3;
use prehensile_core::stability::LOAD_DIRECTIONS;
use prehensile_core::{HandModel, ObjectModel};
use rayon::prelude::*;
use serde::Serialize;

use super::held_still::closing_on_fixed_object;
use super::PlannedGrasp;
use crate::error::SimError;
use crate::simulation::Simulation;
use crate::world::settings::Settings;

/// Largest move of the object in the hand that still counts as held, metres.
pub const HOLD_MOVE: f64 = 0.02;
/// Largest turn of the object in the hand that still counts as held, degrees.
pub const HOLD_TURN_DEGREES: f64 = 30.0;
/// How long each load is applied, seconds.
pub const HOLD_SECONDS: f64 = 1.0;
/// Default grip strength α of the hold test (the held-still scene's).
pub const HOLD_ALPHA: f64 = 0.5;

/// The outcome of one load direction.
#[derive(Debug, Clone, Serialize)]
pub struct HoldDirection {
    /// Direction of the load (gravity), object frame: `+x`, `-x`, … `-z`.
    pub direction: &'static str,
    /// Moved less than [`HOLD_MOVE`] and turned less than [`HOLD_TURN_DEGREES`].
    pub held: bool,
    /// How far the object moved in the hand, metres.
    pub moved_m: f64,
    /// How far it turned in the hand, degrees.
    pub turned_degrees: f64,
    /// Why the run stopped early, if it diverged.
    pub diverged: Option<String>,
}

/// The hold test of one grasp.
#[derive(Debug, Clone, Serialize)]
pub struct HoldReport {
    /// The engine that ran it.
    pub engine: crate::Engine,
    /// Grip strength α.
    pub alpha: f64,
    /// Object mass in the simulation, kg.
    pub object_mass_kg: f64,
    /// Time step, seconds.
    pub dt: f64,
    /// Each load direction.
    pub directions: Vec<HoldDirection>,
    /// How many directions held.
    pub held: usize,
    /// The hand as the first direction's object was let go: enough to rebuild the moment in
    /// another engine (`tools/mujoco/hold_third_opinion.py` does, in MuJoCo).
    pub let_go: LetGo,
}

/// The hand at the let-go: where its palm is and what its controller asks, as springs.
#[derive(Debug, Clone, Default, Serialize)]
pub struct LetGo {
    /// The palm (root bone) frame in the object's frame: position, metres.
    pub palm_position: [f64; 3],
    /// Its rotation as a unit quaternion, `[x, y, z, w]` (as every quaternion of a result).
    pub palm_rotation_xyzw: [f64; 4],
    /// Joint angles, per degree of freedom (the hand's order), radians.
    pub joint_angles: Vec<f64>,
    /// The controller's joint springs τP + τA, whose torque is stiffness·(target − q) +
    /// damping·(target_velocity − q̇): stiffness per degree of freedom, N·m/rad.
    pub stiffness: Vec<f64>,
    /// Damping per degree of freedom, N·m·s/rad.
    pub damping: Vec<f64>,
    /// Target angle per degree of freedom, rad.
    pub target: Vec<f64>,
    /// Target rate per degree of freedom, rad/s.
    pub target_velocity: Vec<f64>,
    /// Ball joints' cross torques, N·m per degree of freedom (0 for other joints).
    pub coupling: Vec<f64>,
}

impl LetGo {
    fn of(sim: &Simulation) -> Self {
        let palm = sim.palm_frame(0);
        let (springs, coupling) = sim.joint_springs(0);
        let r = palm.rotation;
        Self {
            palm_position: palm.translation.vector.into(),
            palm_rotation_xyzw: [r.i, r.j, r.k, r.w],
            joint_angles: sim.joint_angles(0).to_vec(),
            stiffness: springs.iter().map(|s| s.stiffness).collect(),
            damping: springs.iter().map(|s| s.damping).collect(),
            target: springs.iter().map(|s| s.target).collect(),
            target_velocity: springs.iter().map(|s| s.target_velocity).collect(),
            coupling: coupling.to_vec(),
        }
    }
}

/// Runs the hold test of `grasp` (from [`super::plan_grasp`] or
/// [`PlannedGrasp::from_result`]) with `settings` (its gravity's magnitude is used) and grip
/// strength `alpha`.
pub fn hold_test(
    hand: &HandModel,
    object: &ObjectModel,
    grasp: &PlannedGrasp,
    settings: Settings,
    alpha: f64,
) -> Result<HoldReport, SimError> {
    if !(alpha.is_finite() && (0.0..=1.0).contains(&alpha)) {
        return Err(SimError::OutOfRange {
            setting: "alpha",
            value: alpha,
            low: 0.0,
            high: 1.0,
        });
    }
    settings.check()?;
    let g = settings.gravity.norm();
    // The six loads are independent runs from the same start: they run side by side, each on
    // its own world, and are reported in the order of `LOAD_DIRECTIONS` whatever the threads.
    let outcomes = LOAD_DIRECTIONS
        .par_iter()
        .enumerate()
        .map(|(k, direction)| {
            let mut axis = Vec3::zeros();
            axis[k / 2] = if k % 2 == 0 { 1.0 } else { -1.0 };
            let gravity = axis * g;
            let mut controller = grasp.controller(hand, &gravity)?;
            controller.alpha = alpha;
            let settings = Settings {
                gravity,
                ..settings
            };
            hold_against(hand, object, grasp, controller, settings, direction)
        })
        .collect::<Result<Vec<_>, SimError>>()?;
    let mut report = HoldReport {
        engine: settings.engine,
        alpha,
        object_mass_kg: outcomes.last().map_or(0.0, |(_, mass, _)| *mass),
        dt: settings.dt,
        directions: Vec::with_capacity(6),
        held: 0,
        let_go: outcomes.first().map(|o| o.2.clone()).unwrap_or_default(),
    };
    for (outcome, ..) in outcomes {
        report.held += usize::from(outcome.held);
        report.directions.push(outcome);
    }
    Ok(report)
}

/// The hold test of a search result in the default world on `engine` with grip strength
/// [`HOLD_ALPHA`]: what `prehensile grasp --hold` and the Python package's
/// `grasp(..., hold=True)` run.
pub fn hold_test_of_result(
    hand: &HandModel,
    object: &ObjectModel,
    result: &prehensile_core::search::GraspResult,
    engine: crate::Engine,
) -> Result<HoldReport, SimError> {
    let grasp = PlannedGrasp::from_result(hand, result)?;
    let settings = Settings {
        engine,
        ..Settings::default()
    };
    hold_test(hand, object, &grasp, settings, HOLD_ALPHA)
}

/// One load direction of the hold test: `hand` under `controller` closes on `object` along
/// `grasp`'s arm path, the object is let go into `settings`' gravity and watched for
/// [`HOLD_SECONDS`] with the arm still. Returns the outcome, labelled `direction`, the
/// object's mass and the hand at the let-go.
pub(crate) fn hold_against(
    hand: &HandModel,
    object: &ObjectModel,
    grasp: &PlannedGrasp,
    controller: GraspController,
    settings: Settings,
    direction: &'static str,
) -> Result<(HoldDirection, f64, LetGo), SimError> {
    let (mut sim, times) = closing_on_fixed_object(hand, object, grasp, controller, settings)?;
    let mass = sim.object_mass().unwrap_or(0.0);
    let in_hand = |sim: &Simulation| {
        let o = sim.object_pose().expect("the test has an object");
        sim.root(0).inverse() * o
    };
    let mut outcome = HoldDirection {
        direction,
        held: false,
        moved_m: f64::INFINITY,
        turned_degrees: 180.0,
        diverged: None,
    };
    let mut start = None;
    let mut let_go = LetGo::default();
    let end = times.let_go + HOLD_SECONDS;
    while sim.time() < end {
        if start.is_none() && sim.time() >= times.let_go {
            let_go = LetGo::of(&sim);
            sim.let_go_object();
            start = Some(in_hand(&sim));
        }
        if let Err(e) = sim.step() {
            outcome.diverged = Some(e.to_string());
            break;
        }
    }
    if let (Some(a), None) = (start, &outcome.diverged) {
        let b = in_hand(&sim);
        outcome.moved_m = (b.translation.vector - a.translation.vector).norm();
        outcome.turned_degrees = b.rotation.angle_to(&a.rotation).to_degrees();
        outcome.held = outcome.moved_m < HOLD_MOVE && outcome.turned_degrees < HOLD_TURN_DEGREES;
    }
    Ok((outcome, mass, let_go))
}
