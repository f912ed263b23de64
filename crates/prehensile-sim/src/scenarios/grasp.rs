//! Grasps of several shapes from one example (Fig. 6): one controller, fitted to the synthetic
//! example of the first object's grasp, drives the hand to grasp, lift and release each object
//! along the arm path of that object's own grasp pose. The other objects' grasps are searched
//! along the closing this controller makes, so each object is placed where its fingers close.

use prehensile_control::GraspController;
use prehensile_core::math::Transform;
use prehensile_core::{GraspMovement, HandModel, ObjectModel};

use super::hold_test::hold_against;
use super::{
    case, grasp_arm, recording, side_by_side, step_until, CaseReport, GraspTimes, Options,
    PlannedGrasp, Recording, HOLD_MOVE, HOLD_TURN_DEGREES, LIFT,
};
use crate::error::SimError;
use crate::simulation::{DistanceTo, HandSetup, Simulation};
use crate::world::settings::Settings;

/// One grasp-lift-release run and its metrics.
#[allow(clippy::too_many_arguments)]
pub(crate) fn grasp_case(
    hand: &HandModel,
    object: &ObjectModel,
    grasp: &PlannedGrasp,
    controller: &GraspController,
    settings: Settings,
    (times, seconds): (GraspTimes, f64),
    manual: Vec<(f64, Option<prehensile_control::Setpoint>)>,
    label: String,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<(CaseReport, Recording), SimError> {
    let object_pose = Transform::identity();
    let mut sim = Simulation::new(settings)?;
    sim.add_object(object, &object_pose, true)?;
    sim.add_hand(HandSetup {
        hand: hand.clone(),
        controller: controller.clone(),
        arm: grasp_arm(grasp, &object_pose, &times),
        start: controller.setpoints.neutral.clone(),
        distance: DistanceTo::GraspPlace(grasp.place()),
        release_at: Some(times.release),
        compensate_gravity: true,
        compensate_arm: true,
        manual,
    })?;
    let in_hand = |sim: &Simulation| {
        let o = sim.object_pose().expect("the scenario has an object");
        (sim.root(0).inverse() * o).translation.vector
    };
    let mut let_go_at = None;
    let mut start_height = 0.0;
    let mut slip = None;
    let mut lifted_height = 0.0;
    let mut force = (0.0, 0usize);
    // The grip on the object while it is still held in place (the last 0.2 s before let-go):
    // the squeeze the controller produces, whether or not the grasp then holds.
    let mut grip = (0.0, 0usize);
    let mut bones_touching = 0;
    let mut each = |sim: &mut Simulation| {
        let t = sim.time();
        if t >= times.let_go - 0.2 && t < times.let_go {
            let contacts = sim.contacts(0);
            grip.0 += contacts.force;
            grip.1 += 1;
            bones_touching = contacts.bone_forces.iter().filter(|f| **f > 0.0).count();
        }
        if let_go_at.is_none() && t >= times.let_go {
            sim.let_go_object();
            let_go_at = Some(in_hand(sim));
            start_height = sim.object_pose().map_or(0.0, |o| o.translation.vector.z);
        }
        if t > times.lifted && t <= times.release {
            force.0 += sim.contacts(0).force;
            force.1 += 1;
        }
        if slip.is_none() && t >= times.release {
            if let Some(p0) = let_go_at {
                slip = Some((in_hand(sim) - p0).norm());
            }
            lifted_height =
                sim.object_pose().map_or(0.0, |o| o.translation.vector.z) - start_height;
        }
    };
    let (wall, diverged) = step_until(&mut sim, seconds, &label, progress, &mut each);
    let mut report = case(&sim, label, wall, diverged);
    if let Some(slip) = slip.filter(|_| report.finite) {
        report.object_slip_m = Some(slip);
        report.held = Some(lifted_height > 0.8 * LIFT && slip < 0.03);
        report.metrics.insert("object_rise_m".into(), lifted_height);
    }
    if force.1 > 0 {
        report.mean_contact_force_n = Some(force.0 / force.1 as f64);
    }
    if grip.1 > 0 {
        report
            .metrics
            .insert("grip_force_n".into(), grip.0 / grip.1 as f64);
        report
            .metrics
            .insert("bones_touching_at_let_go".into(), bones_touching as f64);
    }
    if let Some(mass) = sim.object_mass() {
        report.metrics.insert("object_mass_kg".into(), mass);
    }
    report.metrics.insert(
        "fingers_touching_planned".into(),
        grasp.fingers_touching as f64,
    );
    if let Some(friction) = grasp.search_friction {
        report.metrics.insert("search_friction".into(), friction);
    }
    let rec = recording(&sim, 1, Some(object));
    Ok((report, rec))
}

/// The example: the first object's grasp and the controller fitted to it, with α, and what
/// the hold check found.
pub(crate) struct Example {
    /// The controller every object is grasped with.
    pub controller: GraspController,
    /// The first object's grasp.
    pub grasp: PlannedGrasp,
    /// The hold check of that grasp.
    pub check: HoldCheck,
}

/// The example of the first object ([`checked_grasp`] over its power grasps).
pub(crate) fn example_controller(
    options: &Options,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<Example, SimError> {
    let first = options.objects.first().ok_or(SimError::NoObjects)?;
    let movement = super::grasp_movement(&options.hand)?;
    let fitted = |grasp: &PlannedGrasp| {
        let mut controller = grasp.controller(&options.hand, &options.settings.gravity)?;
        controller.alpha = options.alpha;
        Ok(controller)
    };
    let (grasp, controller, (), check) = checked_grasp(
        options,
        first,
        |turn| Ok((options.plan_grasp_along(first, movement, turn)?, ())),
        fitted,
        progress,
    )?;
    Ok(Example {
        controller,
        grasp,
        check,
    })
}

/// What the hold check of an object's grasp found ([`super::CANDIDATES`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct HoldCheck {
    /// Which candidate was taken (0: the default shoulder's; [`super::shoulder_turn_degrees`]).
    candidate: usize,
    /// How many grasps were checked (0: none, [`Options::candidates`] was 1).
    tried: usize,
    /// Whether the grasp taken passed.
    held: bool,
}

impl HoldCheck {
    /// Adds `hold_check_shoulder_turn_deg` (the candidate taken), `hold_check_tried` and, when
    /// a grasp was checked, `hold_check_held` to a case's metrics.
    pub(crate) fn add_to(&self, report: &mut CaseReport) {
        let metrics = &mut report.metrics;
        let turn = super::shoulder_turn_degrees(self.candidate);
        metrics.insert("hold_check_shoulder_turn_deg".into(), turn);
        metrics.insert("hold_check_tried".into(), self.tried as f64);
        if self.tried > 0 {
            metrics.insert("hold_check_held".into(), f64::from(u8::from(self.held)));
        }
    }
}

/// The grasp of `object` the scenario uses: of the grasps `search` finds from the shoulders of
/// [`Options::candidates`] (`search` is given each one's [`super::shoulder_turn_degrees`] in
/// radians), each driven by the controller `controller_of` gives it, the first that holds the
/// object against the scenario's gravity ([`hold_against`]); when none does, the one that came
/// nearest (the smallest share of the move or turn allowed). A shoulder from which no valid
/// grasp is found is skipped. `search` may return something to carry along.
///
/// Why: neither the search's quality nor ε predicts which of several valid grasps the
/// simulation holds (docs/QUALITY.md), and the controller that drives an object
/// after the first was fitted to another object's grasp; the check asks the simulation itself.
fn checked_grasp<T>(
    options: &Options,
    object: &ObjectModel,
    mut search: impl FnMut(f64) -> Result<(PlannedGrasp, T), SimError>,
    controller_of: impl Fn(&PlannedGrasp) -> Result<GraspController, SimError>,
    progress: &mut dyn FnMut(&str, f64),
) -> Result<(PlannedGrasp, GraspController, T, HoldCheck), SimError> {
    let mut nearest: Option<(f64, PlannedGrasp, GraspController, T, usize)> = None;
    let mut no_grasp = None;
    let mut tried = 0;
    let count = options.candidates.max(1);
    for candidate in 0..count {
        if count > 1 {
            let label = format!("{}: grasp {} of {count}", object.name(), candidate + 1);
            progress(&label, candidate as f64 / count as f64);
        }
        let (grasp, carried) = match search(super::shoulder_turn_degrees(candidate).to_radians()) {
            Ok(found) => found,
            Err(e @ SimError::NoGrasp { .. }) => {
                no_grasp.get_or_insert(e);
                continue;
            }
            Err(e) => return Err(e),
        };
        let controller = controller_of(&grasp)?;
        if options.candidates <= 1 {
            let check = HoldCheck {
                candidate,
                tried: 0,
                held: false,
            };
            return Ok((grasp, controller, carried, check));
        }
        tried += 1;
        let (outcome, ..) = hold_against(
            &options.hand,
            object,
            &grasp,
            controller.clone(),
            options.settings,
            "gravity",
        )?;
        if outcome.held {
            let check = HoldCheck {
                candidate,
                tried,
                held: true,
            };
            return Ok((grasp, controller, carried, check));
        }
        let miss = (outcome.moved_m / HOLD_MOVE).max(outcome.turned_degrees / HOLD_TURN_DEGREES);
        if nearest.as_ref().is_none_or(|n| miss < n.0) {
            nearest = Some((miss, grasp, controller, carried, candidate));
        }
    }
    let (_, grasp, controller, carried, candidate) = nearest.ok_or_else(|| {
        no_grasp.unwrap_or_else(|| SimError::NoGrasp {
            movement: String::new(),
            object: object.name().to_string(),
            hand: options.hand.name().to_string(),
            why: None,
        })
    })?;
    let check = HoldCheck {
        candidate,
        tried,
        held: false,
    };
    Ok((grasp, controller, carried, check))
}

/// The closing the controller makes: from the example's open pose to its grip target
/// (Eq. 15–16: the grip extrapolated by α away from the open pose), as a movement of the hand.
///
/// The other objects are searched along it, so that each is placed where the fingers this one
/// controller moves will close on it; a grasp searched along the hand's own movement sets the
/// fingers where that movement stops, which the controller's grip, fitted to the first object,
/// does not reach or presses past.
fn example_closing(
    options: &Options,
    controller: &GraspController,
    first: &PlannedGrasp,
) -> Result<GraspMovement, SimError> {
    let target: Vec<f64> = first
        .pressed()
        .iter()
        .zip(&first.open)
        .map(|(grip, open)| grip + controller.alpha * (grip - open))
        .collect();
    Ok(super::grasp_movement(&options.hand)?.between(&options.hand, first.open.clone(), target))
}

pub(crate) fn run(
    options: &Options,
    progress: &mut (dyn FnMut(&str, f64) + Send),
    add: &mut dyn FnMut((CaseReport, Recording)),
) -> Result<(), SimError> {
    let example = example_controller(options, progress)?;
    let seconds = options
        .seconds
        .unwrap_or(super::Scenario::Grasp.default_seconds());
    let closing = example_closing(options, &example.controller, &example.grasp)?;
    // The objects side by side: each searches and checks its own grasp and runs its own world.
    let cases = side_by_side(&options.objects, progress, |k, object, progress| {
        // Each object after the first is searched along the controller's closing; when that
        // finds no valid grasp, along the hand's own movement.
        let (grasp, along_example, check) = if k == 0 {
            (example.grasp.clone(), true, example.check)
        } else {
            let search = |turn| match options.plan_grasp_along(object, &closing, turn) {
                Err(SimError::NoGrasp { .. }) => Ok((
                    options.plan_grasp_along(
                        object,
                        super::grasp_movement(&options.hand)?,
                        turn,
                    )?,
                    false,
                )),
                found => Ok((found?, true)),
            };
            let (grasp, _, along_example, check) = checked_grasp(
                options,
                object,
                search,
                |_| Ok(example.controller.clone()),
                progress,
            )?;
            (grasp, along_example, check)
        };
        let (mut report, recording) = grasp_case(
            &options.hand,
            object,
            &grasp,
            &example.controller,
            options.settings,
            (GraspTimes::default(), seconds),
            Vec::new(),
            object.name().to_string(),
            progress,
        )?;
        report.metrics.insert(
            "searched_along_example_closing".into(),
            f64::from(u8::from(along_example)),
        );
        check.add_to(&mut report);
        Ok((report, recording))
    })?;
    cases.into_iter().for_each(add);
    Ok(())
}
