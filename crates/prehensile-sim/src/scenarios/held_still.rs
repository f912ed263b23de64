//! A hand holding an object still: the grasp scenario run until just after the object is let
//! go, the arm then kept where it is and gravity pressing the object into the palm, so the scene
//! (and the cost of a step) stays the same however long it runs. The scene of the step
//! benchmarks and of the side-by-side timing with MuJoCo (`examples/step_timing.rs`).

use prehensile_core::math::Transform;
use prehensile_core::{HandModel, ObjectModel};

use prehensile_control::GraspController;

use prehensile_core::search::{SearchParams, ValidityRule};

use super::{grasp_arm, plan_grasp_with, GraspTimes, PlannedGrasp};
use crate::error::SimError;
use crate::simulation::{DistanceTo, HandSetup, Simulation};
use crate::world::settings::Settings;

/// `hand` gripping `object` with grip strength 0.5, stepped with `settings` (whose gravity is
/// replaced by one pressing the object into the palm), returned 50 ms after the object was let
/// go into the closed hand. The hand closes on the object as the search under the thesis's rule
/// finds it (§6.4.1): a timing scene needs fingers pressing on the object, not a grasp that holds
/// in every direction, and the thesis's rule finds one for any hand and object that the stability
/// rules may refuse.
pub fn held_still(
    hand: &HandModel,
    object: &ObjectModel,
    settings: Settings,
) -> Result<Simulation, SimError> {
    let params = SearchParams {
        validity: ValidityRule::Thesis,
        ..SearchParams::default()
    };
    let grasp = plan_grasp_with(hand, object, params)?;
    // Gravity presses the object into the palm (against the approach).
    let gravity = -9.81 * grasp.approach.normalize();
    let mut controller = grasp.controller(hand, &gravity)?;
    controller.alpha = 0.5;
    let (mut sim, times) = closing_on_fixed_object(
        hand,
        object,
        &grasp,
        controller,
        Settings {
            gravity,
            ..settings
        },
    )?;
    while sim.time() < times.let_go + 0.05 {
        if sim.time() >= times.let_go {
            sim.let_go_object();
        }
        sim.step()?;
    }
    Ok(sim)
}

/// The scene the held-still benchmark and the hold test start from: `object` fixed at the
/// origin, `hand` approaching and closing on it along `grasp`'s arm path under `controller`,
/// the lift never coming. Returns the world and its times (the object is let go at `let_go`).
pub(crate) fn closing_on_fixed_object(
    hand: &HandModel,
    object: &ObjectModel,
    grasp: &PlannedGrasp,
    controller: GraspController,
    settings: Settings,
) -> Result<(Simulation, GraspTimes), SimError> {
    let times = GraspTimes::without_lift();
    let mut sim = Simulation::new(settings)?;
    sim.add_object(object, &Transform::identity(), true)?;
    sim.add_hand(HandSetup {
        hand: hand.clone(),
        start: controller.setpoints.neutral.clone(),
        controller,
        arm: grasp_arm(grasp, &Transform::identity(), &times),
        distance: DistanceTo::GraspPlace(grasp.place()),
        release_at: None,
        compensate_gravity: true,
        compensate_arm: true,
        manual: Vec::new(),
    })?;
    Ok((sim, times))
}
