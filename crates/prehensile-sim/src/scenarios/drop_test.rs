//! The drop test (Fig. 2): the passive hand (τP only, no compensation), palm down and held by
//! the wrist, starts open and lets gravity pull its fingers; it settles where the neutral-pose
//! springs balance gravity. Run with and without the joint-limit springs.

use prehensile_core::math::{Rotation, Transform, Vec3};

use super::{
    case, recording, side_by_side, step_until, CaseReport, Options, PlannedGrasp, Recording,
    Scenario,
};
use crate::error::SimError;
use crate::simulation::{DistanceTo, HandSetup, Simulation};
use crate::world::arm_trajectory::{ArmTrajectory, Waypoint};

/// Palm down: the hand's +y (palm normal) to world −z, fingers (+z) to world +y.
pub(crate) fn palm_down() -> Transform {
    Transform::from_parts(
        Default::default(),
        Rotation::from_axis_angle(&Vec3::x_axis(), -std::f64::consts::FRAC_PI_2),
    )
}

/// The drop with and without the joint-limit springs, side by side.
pub(crate) fn run(
    options: &Options,
    progress: &mut (dyn FnMut(&str, f64) + Send),
    add: &mut dyn FnMut((CaseReport, Recording)),
) -> Result<(), SimError> {
    let hand = &options.hand;
    let poses = PlannedGrasp::without_object(hand)?;
    let seconds = options.seconds.unwrap_or(Scenario::Drop.default_seconds());
    let cases = side_by_side(&[true, false], progress, |_, &limits, progress| {
        let mut controller = poses.controller(hand, &options.settings.gravity)?;
        controller.active = false;
        if !limits {
            controller.gains.k_jl = 0.0;
        }
        let model_limits = controller.setpoints.limits.clone();
        let neutral = controller.setpoints.neutral.clone();
        let mut sim = Simulation::new(options.settings)?;
        sim.add_hand(HandSetup {
            hand: hand.clone(),
            controller,
            arm: ArmTrajectory::new(vec![Waypoint {
                time: 0.0,
                root: palm_down(),
            }]),
            start: poses.open.clone(),
            distance: DistanceTo::Constant(1.0),
            release_at: None,
            compensate_gravity: false,
            compensate_arm: false,
            manual: Vec::new(),
        })?;
        let (mut violation, mut settled_at, mut previous) = (0.0f64, 0.0, poses.open.clone());
        let mut each = |sim: &mut Simulation| {
            let q = sim.joint_angles(0);
            for (k, v) in q.iter().enumerate() {
                let [lo, hi] = model_limits[k];
                violation = violation.max(lo - v).max(v - hi);
            }
            let moving = q
                .iter()
                .zip(&previous)
                .any(|(a, b)| (a - b).abs() / sim.settings().dt > 0.1);
            if moving {
                settled_at = sim.time();
            }
            previous.copy_from_slice(q);
        };
        let label = if limits {
            "with joint limits"
        } else {
            "without joint limits"
        };
        let (wall, diverged) = step_until(&mut sim, seconds, label, progress, &mut each);
        let mut report = case(&sim, label.into(), wall, diverged);
        let sag = sim
            .joint_angles(0)
            .iter()
            .zip(&neutral)
            .map(|(q, n)| (q - n).abs())
            .fold(0.0, f64::max);
        report
            .metrics
            .insert("max_limit_violation_rad".into(), violation.max(0.0));
        report.metrics.insert("settle_time_s".into(), settled_at);
        report
            .metrics
            .insert("final_max_deviation_from_neutral_rad".into(), sag);
        Ok((report, recording(&sim, 1, None)))
    })?;
    cases.into_iter().for_each(add);
    Ok(())
}
