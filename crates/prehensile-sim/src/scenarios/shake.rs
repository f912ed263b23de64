//! Arm shaking: the hand, palm down in its neutral state, is shaken up and down (3 cm, 3 Hz)
//! with and without the arm-motion compensation τARM; the fingers' lag behind the arm is their
//! deviation from where they were before the shake.

use prehensile_control::Setpoint;
use prehensile_core::math::Vec3;

use super::drop_test::palm_down;
use super::{
    case, recording, side_by_side, step_until, CaseReport, Options, PlannedGrasp, Recording,
    Scenario,
};
use crate::error::SimError;
use crate::simulation::{DistanceTo, HandSetup, Simulation};
use crate::world::arm_trajectory::{ArmTrajectory, Shake, Waypoint};

/// The shake starts here, seconds (the hand settles before).
const SHAKE_FROM: f64 = 0.5;

/// The shake with and without τARM, side by side.
pub(crate) fn run(
    options: &Options,
    progress: &mut (dyn FnMut(&str, f64) + Send),
    add: &mut dyn FnMut((CaseReport, Recording)),
) -> Result<(), SimError> {
    let hand = &options.hand;
    let poses = PlannedGrasp::without_object(hand)?;
    let seconds = options.seconds.unwrap_or(Scenario::Shake.default_seconds());
    let cases = side_by_side(&[true, false], progress, |_, &compensate_arm, progress| {
        let controller = poses.controller(hand, &options.settings.gravity)?;
        let start = controller.setpoints.positions[Setpoint::Neutral].clone();
        let arm = ArmTrajectory::new(vec![Waypoint {
            time: 0.0,
            root: palm_down(),
        }])
        .with_shake(Shake {
            direction: Vec3::z(),
            amplitude: 0.03,
            frequency: 3.0,
            during: [SHAKE_FROM, seconds.max(SHAKE_FROM + 1.0)],
        });
        let mut sim = Simulation::new(options.settings)?;
        sim.add_hand(HandSetup {
            hand: hand.clone(),
            controller,
            arm,
            start,
            distance: DistanceTo::Constant(1.0),
            release_at: None,
            compensate_gravity: true,
            compensate_arm,
            manual: Vec::new(),
        })?;
        let mut before: Option<Vec<f64>> = None;
        let (mut sum, mut count, mut max) = (0.0, 0usize, 0.0f64);
        let mut each = |sim: &mut Simulation| {
            let q = sim.joint_angles(0);
            if sim.time() < SHAKE_FROM {
                before = Some(q.to_vec());
                return;
            }
            if let Some(b) = &before {
                for (a, b) in q.iter().zip(b) {
                    sum += (a - b).powi(2);
                    max = max.max((a - b).abs());
                }
                count += q.len();
            }
        };
        let label = if compensate_arm {
            "with arm compensation"
        } else {
            "without arm compensation"
        };
        let (wall, diverged) = step_until(&mut sim, seconds, label, progress, &mut each);
        let mut report = case(&sim, label.into(), wall, diverged);
        let rms = if count > 0 {
            (sum / count as f64).sqrt()
        } else {
            0.0
        };
        report.metrics.insert("finger_lag_rms_rad".into(), rms);
        report.metrics.insert("finger_lag_max_rad".into(), max);
        Ok((report, recording(&sim, 1, None)))
    })?;
    cases.into_iter().for_each(add);
    Ok(())
}
