//! Interactive open/close (Fig. 7): the hand grasps and lifts the object, then the user
//! switches between the open and grip setpoints: short openings let the object shift in the
//! hand, closings catch it again.

use super::grasp::{example_controller, grasp_case};
use super::{CaseReport, GraspTimes, Options, Recording, Scenario};
use crate::error::SimError;
use prehensile_control::Setpoint;

pub(crate) fn run(
    options: &Options,
    progress: &mut dyn FnMut(&str, f64),
    add: &mut dyn FnMut((CaseReport, Recording)),
) -> Result<(), SimError> {
    let example = example_controller(options, progress)?;
    let (controller, grasp) = (example.controller, example.grasp);
    let seconds = options
        .seconds
        .unwrap_or(Scenario::OpenClose.default_seconds());
    let times = GraspTimes::default();
    // After the lift: open for 30 ms, grip for 470 ms, three times; then the state machine.
    // (Longer openings drop a light object from the paper's soft hand: 50 ms did.)
    let mut manual = Vec::new();
    for k in 0..3 {
        let t = times.lifted + 0.1 + 0.5 * k as f64;
        manual.push((t, Some(Setpoint::Open)));
        manual.push((t + 0.03, Some(Setpoint::Grip)));
    }
    manual.push((times.lifted + 1.6, None));
    let mut hold = times;
    hold.release = times.lifted + 1.8;
    hold.end = hold.release + 1.0;
    let (mut report, rec) = grasp_case(
        &options.hand,
        &options.objects[0],
        &grasp,
        &controller,
        options.settings,
        (hold, seconds),
        manual,
        format!("{} open/close", options.objects[0].name()),
        progress,
    )?;
    report.metrics.insert("switches".into(), 6.0);
    example.check.add_to(&mut report);
    add((report, rec));
    Ok(())
}
