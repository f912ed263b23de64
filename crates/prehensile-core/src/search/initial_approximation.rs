//! Initial approximation (§5.6.2.1): sample hook rotations over the wrist range, back the hand
//! off each with TranslateToFree in its start pose, and start from the one whose grasp center
//! stays closest to the hook (smallest gDist), without any finger closing.

use crate::math::Rotation;
use crate::workspace::Workspace;

use super::quality::EvaluationContext;
use super::translate_to_free::translate_to_free;

/// Samples per axis: about z (the widest range), x and y.
const SAMPLES: [usize; 3] = [7, 3, 3];

/// The sampled hook rotation with the smallest back-off, or `None` if none could be freed.
/// Samples are relative to the starting position, `start · Rz·Ry·Rx`, within the wrist range.
pub fn initial_approximation(
    ctx: &EvaluationContext,
    ws: &mut Workspace,
) -> Option<(Rotation, f64)> {
    let range = ctx.wrist_range;
    let spread = |[lo, hi]: [f64; 2], n: usize, k: usize| {
        if n == 1 {
            0.5 * (lo + hi)
        } else {
            lo + (hi - lo) * k as f64 / (n - 1) as f64
        }
    };
    let mut best: Option<(Rotation, f64)> = None;
    // The starting position itself first, so ties keep it.
    let mut consider = |rotation: Rotation, ws: &mut Workspace| {
        let hook = ctx.hook_frame(&rotation);
        if let Some(offset) = translate_to_free(
            ctx.hand,
            ctx.object,
            ctx.movement,
            &hook,
            ctx.translate,
            ctx.max_offset,
            ws,
        ) {
            if best.is_none_or(|(_, b)| offset < b) {
                best = Some((rotation, offset));
            }
        }
    };
    consider(ctx.start, ws);
    for iz in 0..SAMPLES[0] {
        for ix in 0..SAMPLES[1] {
            for iy in 0..SAMPLES[2] {
                let relative = Rotation::from_euler_angles(
                    spread(range.x, SAMPLES[1], ix),
                    spread(range.y, SAMPLES[2], iy),
                    spread(range.z, SAMPLES[0], iz),
                );
                consider(ctx.start * relative, ws);
            }
        }
    }
    best
}
