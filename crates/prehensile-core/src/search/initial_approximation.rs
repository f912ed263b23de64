//! Initial approximation (§5.6.2.1): sample hook rotations over the wrist range, back the hand
//! off each with TranslateToFree in its start pose, and start from the one whose grasp center
//! stays closest to the hook (smallest gDist), without any finger closing.
//!
//! The samples are taken a few at a time ([`InitialApproximation::advance`]), so that a planner
//! restarted inside a game's frame (§6.5.6) keeps to its frame budget: all of them at once take
//! 40–100 ms.

use crate::math::Rotation;
use crate::workspace::Workspace;

use super::quality::EvaluationContext;
use super::translate_to_free::translate_to_free;

/// Samples per axis: about z (the widest range), x and y.
const SAMPLES: [usize; 3] = [7, 3, 3];
/// Rotations tried in all: the starting position, then the grid.
pub const SAMPLE_COUNT: usize = 1 + SAMPLES[0] * SAMPLES[1] * SAMPLES[2];

/// The sampling in progress: how many samples are done and the best so far.
#[derive(Debug, Clone, Default)]
pub struct InitialApproximation {
    done: usize,
    best: Option<(Rotation, f64)>,
}

impl InitialApproximation {
    /// Nothing sampled yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes up to `count` more samples; returns true once every sample is done.
    pub fn advance(&mut self, ctx: &EvaluationContext, ws: &mut Workspace, count: usize) -> bool {
        let end = (self.done + count).min(SAMPLE_COUNT);
        for k in self.done..end {
            let rotation = sample_rotation(ctx, k);
            let hook = ctx.hook_frame(&rotation);
            // Only a back-off smaller than the best so far matters: give up once the hand
            // still touches there.
            let freed = translate_to_free(
                ctx.hand,
                ctx.object,
                ctx.movement,
                &hook,
                ctx.translate,
                ctx.max_offset,
                self.best.map_or(f64::INFINITY, |(_, b)| b),
                ws,
            );
            // Strictly better only: ties keep the earlier sample (the starting position first).
            if let Some(offset) = freed.filter(|&o| self.best.is_none_or(|(_, b)| o < b)) {
                self.best = Some((rotation, offset));
            }
        }
        self.done = end;
        self.finished()
    }

    /// Has every sample been taken?
    pub fn finished(&self) -> bool {
        self.done == SAMPLE_COUNT
    }

    /// The sampled hook rotation with the smallest back-off so far, and that back-off; `None`
    /// if none could be freed.
    pub fn best(&self) -> Option<(Rotation, f64)> {
        self.best
    }
}

/// Sample `k` of [`SAMPLE_COUNT`]: the starting position for 0, else `start · Rz·Ry·Rx` on the
/// grid over the wrist range.
pub fn sample_rotation(ctx: &EvaluationContext, k: usize) -> Rotation {
    if k == 0 {
        return ctx.start;
    }
    let spread = |[lo, hi]: [f64; 2], n: usize, i: usize| {
        if n == 1 {
            0.5 * (lo + hi)
        } else {
            lo + (hi - lo) * i as f64 / (n - 1) as f64
        }
    };
    let k = k - 1;
    let (iz, ix, iy) = (
        k / (SAMPLES[1] * SAMPLES[2]),
        (k / SAMPLES[2]) % SAMPLES[1],
        k % SAMPLES[2],
    );
    let range = ctx.wrist_range;
    let relative = Rotation::from_euler_angles(
        spread(range.x, SAMPLES[1], ix),
        spread(range.y, SAMPLES[2], iy),
        spread(range.z, SAMPLES[0], iz),
    );
    ctx.start * relative
}
