//! A handshake (Fig. 5): two hands, each with its own controller (Table 1's handshake gains),
//! palms facing, approach each other, close on each other's hand, hold, release and part. Each
//! controller's distance is the distance between the hands' roots beyond their meeting
//! distance.

use prehensile_control::{Gains, Setpoint};
use prehensile_core::math::{Rotation, Transform, Vec3};
use prehensile_core::HandModel;

use super::{case, recording, step_until, CaseReport, Options, PlannedGrasp, Recording, Scenario};
use crate::error::SimError;
use crate::simulation::{DistanceTo, HandSetup, Simulation};
use crate::world::arm_trajectory::{ArmTrajectory, Waypoint};

/// Root offset along the fingers, metres, so each palm lies over the other.
const ALONG: f64 = 0.09;
/// Palms apart at the start, metres.
const START: f64 = 0.3;
/// Clearance between the palms' surfaces when the hands meet, metres.
const GAP: f64 = 0.003;

/// How far the palm's surface stands in front of the hand frame's origin (along +y, the palm
/// side in our convention), metres: the root bone's capsules at their widest. Two hands meet
/// with their roots twice this (plus [`GAP`]) apart, so the kinematic palms, which nothing can
/// push apart, never overlap.
fn palm_front(hand: &HandModel) -> f64 {
    let root = &hand.bones()[0];
    hand.bone_capsules(0)
        .iter()
        .flat_map(|c| [c.a, c.b].map(|p| (root.rest * p).y + c.radius))
        .fold(0.0, f64::max)
}

pub(crate) fn run(
    options: &Options,
    progress: &mut dyn FnMut(&str, f64),
    add: &mut dyn FnMut((CaseReport, Recording)),
) -> Result<(), SimError> {
    let hand = &options.hand;
    let poses = PlannedGrasp::without_object(hand)?;
    let seconds = options
        .seconds
        .unwrap_or(Scenario::Handshake.default_seconds());
    // Hand A: fingers to +x, palm to +y; hand B turned half round the vertical.
    let a = Rotation::from_axis_angle(&Vec3::y_axis(), std::f64::consts::FRAC_PI_2);
    let b = Rotation::from_axis_angle(&Vec3::z_axis(), std::f64::consts::PI) * a;
    let meet = 2.0 * palm_front(hand) + GAP;
    let place = |r: Rotation, x: f64, y: f64| Transform::from_parts(Vec3::new(x, y, 0.0).into(), r);
    let path = |r: Rotation, x: f64, side: f64| {
        ArmTrajectory::new(vec![
            Waypoint {
                time: 0.0,
                root: place(r, x, side * START / 2.0),
            },
            Waypoint {
                time: 1.2,
                root: place(r, x, side * meet / 2.0),
            },
            Waypoint {
                time: 2.4,
                root: place(r, x, side * meet / 2.0),
            },
            Waypoint {
                time: 3.4,
                root: place(r, x, side * START / 2.0),
            },
        ])
    };
    let contact = (ALONG * ALONG + meet * meet).sqrt();
    let mut sim = Simulation::new(options.settings)?;
    for (k, (rotation, x, side)) in [(a, 0.0, -1.0), (b, ALONG, 1.0)].into_iter().enumerate() {
        let mut controller = poses.controller(hand, &options.settings.gravity)?;
        let g = Gains::handshake();
        controller.gains = g;
        controller.open_while_closing = false;
        controller.alpha = options.alpha;
        sim.add_hand(HandSetup {
            hand: hand.clone(),
            start: controller.setpoints.positions[Setpoint::Neutral].clone(),
            controller,
            arm: path(rotation, x, side),
            distance: DistanceTo::OtherHand {
                other: 1 - k,
                contact,
            },
            release_at: Some(2.2),
            compensate_gravity: true,
            compensate_arm: true,
            manual: Vec::new(),
        })?;
    }
    let mut force = (0.0, 0usize);
    let mut each = |sim: &mut Simulation| {
        if (1.4..2.2).contains(&sim.time()) {
            force.0 += sim.contacts(0).force;
            force.1 += 1;
        }
    };
    let (wall, diverged) = step_until(&mut sim, seconds, "handshake", progress, &mut each);
    let mut report = case(&sim, "two hands".into(), wall, diverged);
    if force.1 > 0 {
        report.mean_contact_force_n = Some(force.0 / force.1 as f64);
    }
    add((report, recording(&sim, 2, None)));
    Ok(())
}
