//! A hand holding an object still: the grasp scenario run until just after the object is let
//! go, the arm then kept where it is and gravity pressing the object into the palm, so the scene
//! (and the cost of a step) stays the same however long it runs. The scene of the step
//! benchmarks and of the side-by-side timing with MuJoCo (`examples/step_timing.rs`).

use prehensile_core::math::Transform;
use prehensile_core::{HandModel, ObjectModel};

use super::{grasp_arm, plan_grasp, GraspTimes};
use crate::simulation::{DistanceTo, HandSetup, Settings, Simulation};
use crate::SimError;

/// `hand` gripping `object` with grip strength 0.5, stepped with `settings` (whose gravity is
/// replaced by one pressing the object into the palm), returned 50 ms after the object was let
/// go into the closed hand.
pub fn held_still(
    hand: &HandModel,
    object: &ObjectModel,
    settings: Settings,
) -> Result<Simulation, SimError> {
    let grasp = plan_grasp(hand, object)?;
    // Gravity presses the object into the palm (against the approach).
    let gravity = -9.81 * grasp.approach.normalize();
    let mut controller = grasp.controller(hand, &gravity)?;
    controller.alpha = 0.5;
    // The lift never comes.
    let times = GraspTimes {
        lift: 1e6,
        lifted: 1e6 + 1.0,
        release: 1e6 + 2.0,
        end: 1e6 + 3.0,
        ..GraspTimes::default()
    };
    let mut sim = Simulation::new(Settings {
        gravity,
        ..settings
    })?;
    sim.add_object(object, &Transform::identity(), true)?;
    sim.add_hand(HandSetup {
        hand: hand.clone(),
        start: controller.setpoints.neutral.clone(),
        controller,
        arm: grasp_arm(&grasp, &Transform::identity(), &times),
        distance: DistanceTo::GraspPlace(grasp.place()),
        release_at: None,
        compensate_gravity: true,
        compensate_arm: true,
        manual: Vec::new(),
    })?;
    while sim.time() < times.let_go + 0.05 {
        if sim.time() >= times.let_go {
            sim.let_go_object();
        }
        sim.step()?;
    }
    Ok(sim)
}
