//! Grip strength (§6, Eq. 15–16): the same grasp at α = 0, 0.1, …, 0.5. The grip setpoint moves
//! further along the closing line as α grows, so the grip force on the object (`grip_force_n`,
//! measured while the object is still held in place) grows with it.

use super::grasp::{example_controller, grasp_case};
use super::{side_by_side, CaseReport, Options, Recording, Scenario};
use crate::error::SimError;

/// The swept grip strengths.
pub const ALPHAS: [f64; 6] = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5];

/// The example's grasp at every α of [`ALPHAS`], side by side.
pub(crate) fn run(
    options: &Options,
    progress: &mut (dyn FnMut(&str, f64) + Send),
    add: &mut dyn FnMut((CaseReport, Recording)),
) -> Result<(), SimError> {
    let example = example_controller(options, progress)?;
    let seconds = options
        .seconds
        .unwrap_or(Scenario::GripSweep.default_seconds());
    let cases = side_by_side(&ALPHAS, progress, |_, &alpha, progress| {
        let mut controller = example.controller.clone();
        controller.alpha = alpha;
        let (mut report, rec) = grasp_case(
            &options.hand,
            &options.objects[0],
            &example.grasp,
            &controller,
            options.settings,
            (super::GraspTimes::default(), seconds),
            Vec::new(),
            format!("alpha {alpha:.1}"),
            progress,
        )?;
        report.metrics.insert("alpha".into(), alpha);
        example.check.add_to(&mut report);
        Ok((report, rec))
    })?;
    cases.into_iter().for_each(add);
    Ok(())
}
