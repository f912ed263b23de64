//! Grasps of several shapes from one example (Fig. 6): one controller, fitted to the synthetic
//! example of the first object's grasp, drives the hand to grasp, lift and release each object
//! along the arm path of that object's own grasp pose. The other objects' grasps are searched
//! along the closing this controller makes, so each object is placed where its fingers close.

use prehensile_control::GraspController;
use prehensile_core::math::Transform;
use prehensile_core::{GraspMovement, HandModel, ObjectModel};

use super::{
    case, grasp_arm, recording, step_until, CaseReport, GraspTimes, Options, PlannedGrasp,
    Recording, LIFT,
};
use crate::simulation::{DistanceTo, HandSetup, Settings, Simulation};
use crate::SimError;

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
    if let Some(body) = sim.object() {
        report.metrics.insert("object_mass_kg".into(), body.mass);
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

/// The example's controller (fitted to the first object's grasp) with α.
pub(crate) fn example_controller(
    options: &Options,
) -> Result<(GraspController, PlannedGrasp), SimError> {
    let first = options
        .objects
        .first()
        .ok_or_else(|| SimError::Settings("give at least one object".into()))?;
    let grasp = options.plan_grasp(first)?;
    let mut controller = grasp.controller(&options.hand, &options.settings.gravity)?;
    controller.alpha = options.alpha;
    Ok((controller, grasp))
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
    progress: &mut dyn FnMut(&str, f64),
    add: &mut dyn FnMut((CaseReport, Recording)),
) -> Result<(), SimError> {
    let (controller, first_grasp) = example_controller(options)?;
    let seconds = options
        .seconds
        .unwrap_or(super::Scenario::Grasp.default_seconds());
    let closing = example_closing(options, &controller, &first_grasp)?;
    for (k, object) in options.objects.iter().enumerate() {
        // Each object after the first is searched along the controller's closing; when that
        // finds no valid grasp, along the hand's own movement.
        let (grasp, along_example) = if k == 0 {
            (first_grasp.clone(), true)
        } else {
            match options.plan_grasp_along(object, &closing) {
                Err(SimError::NoGrasp(_)) => (options.plan_grasp(object)?, false),
                found => (found?, true),
            }
        };
        let (mut report, recording) = grasp_case(
            &options.hand,
            object,
            &grasp,
            &controller,
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
        add((report, recording));
    }
    Ok(())
}
