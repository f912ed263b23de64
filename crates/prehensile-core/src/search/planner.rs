//! The anytime planner (§5.1, §5.6, §6.5.6): advance one step or for a time budget, resume later,
//! always hold the best valid pose so far, restart when the character turns, and try again when
//! a search gives no grasp pushing from every side: first with the hand hung a second time (the
//! hook moved into the object's material, or the hand nearer its palm or farther from it), then
//! once more from the same hang along other random angles.

use std::time::Duration;

// `std::time::Instant` panics in the browser (wasm32); web-time is the same API on every target.
use web_time::Instant;

use super::defaults::{MAX_THREADS, ONE_SIDED_PATIENCE};
use crate::collision::Capsule;
use crate::finger_closing::ClosingParams;
use crate::hand::movement::GraspMovement;
use crate::hand::HandModel;
use crate::math::{Point3, Rotation, Vec3};
use crate::object::ObjectModel;
use crate::parameter::{finite_point, in_range, ParameterError};
use crate::workspace::Workspace;

use super::initial_approximation::InitialApproximation;
use super::material_hook::material_hook;
use super::optimization_step::{step_candidates, StepKind};
use super::quality::{
    hook_depth, Evaluation, EvaluationContext, Invalid, QualityWeights, ValidityRule,
};
use super::start_position::{nearest_hook, start_rotation};
use super::translate_to_free::TranslateMode;
use super::wrist_range::WristRange;
use crate::random::SplitMix64;
use crate::stability::ContactModel;

/// When the planner considers itself converged.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum StopRule {
    /// No better pose for this many consecutive steps, once a valid grasp has been found.
    NoImprovement {
        /// Steps without improvement.
        steps: u32,
    },
    /// The thesis's rule (§5.6): stop at the first step whose best pose is the current one.
    ThesisLocalMaximum,
}

/// Everything the search can be told.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SearchParams {
    /// Seven-pose or unidirectional step.
    pub step: StepKind,
    /// When to stop.
    pub stop: StopRule,
    /// Seed of the random angles (§5.6.2.2).
    pub seed: u64,
    /// Largest random angle, radians (the thesis: 180°).
    pub max_angle: f64,
    /// Finger closing.
    #[serde(skip)]
    pub closing: ClosingParams,
    /// TranslateToFree mode.
    pub translate: TranslateMode,
    /// Quality weights; `None` picks Eq. 5.1 or 5.2 by movement.
    pub weights: Option<QualityWeights>,
    /// Wrist range (§6.5.4), a right hand's: a left hand ([`HandModel::is_left`]) is searched
    /// within its mirror image ([`WristRange::mirrored`]).
    pub wrist_range: WristRange,
    /// Start from the initial approximation (§5.6.2.1) rather than the starting position.
    pub initial_approximation: bool,
    /// Restart when the direction from hook to shoulder turns by more than this, radians.
    pub restart_angle: f64,
    /// The world's up direction (the hand approaches from above).
    pub up: Vec3,
    /// Most steps before giving up on convergence.
    pub max_steps: u32,
    /// Fingers that must touch for a movement without named contact fingers.
    pub min_fingers: usize,
    /// Threads evaluating a step's candidates, each with its own workspace, on rayon's pool (the
    /// global one, or the one the call runs in). 1 evaluates on the calling thread, as a game
    /// loop or the browser needs.
    pub threads: usize,
    /// Which grasps are valid: ones that hold (default), wraps whose contacts push from every
    /// side, or the thesis's rules.
    pub validity: ValidityRule,
    /// How contacts resist forces (friction, friction cone, soft pads).
    pub contact_model: ContactModel,
    /// Judge the stability of a step's candidates (contacts and force closure, the dearest part
    /// of an evaluation) only where it can change what the step does: best quality first, until
    /// one holds or none left could become the current or the best pose. The search takes the
    /// same path and finds the same grasps either way (tested); `false` judges every candidate.
    /// Only when the quality leaves stability out (its weight S is 0, the default).
    #[serde(default = "judge_lazily")]
    pub lazy_stability: bool,
    /// Steps a search goes on with a valid best grasp that pushes from one side only, looking
    /// for one that pushes from every side, before its stop rule may end it (under
    /// [`ValidityRule::Holds`]; see [`EvaluationContext::pushes_from_every_side`]). 0 stops as
    /// soon as the stop rule says: faster on objects where no such grasp
    /// is found (the Shadow hand's torus: 84 ms at 120, docs/QUALITY.md).
    #[serde(default = "one_sided_patience")]
    pub one_sided_patience: u32,
}

fn judge_lazily() -> bool {
    true
}

fn one_sided_patience() -> u32 {
    ONE_SIDED_PATIENCE
}

impl Default for SearchParams {
    fn default() -> Self {
        Self {
            step: StepKind::SevenPose,
            stop: StopRule::NoImprovement { steps: 12 },
            seed: 1,
            max_angle: std::f64::consts::PI,
            closing: ClosingParams::default(),
            translate: TranslateMode::default(),
            weights: None,
            wrist_range: WristRange::default(),
            initial_approximation: true,
            restart_angle: 10f64.to_radians(),
            up: Vec3::z(),
            max_steps: 500,
            min_fingers: 3,
            threads: 1,
            validity: ValidityRule::default(),
            contact_model: ContactModel::default(),
            lazy_stability: true,
            one_sided_patience: ONE_SIDED_PATIENCE,
        }
    }
}

/// Receives what the planner finds as it finds it (as ripgrep's `Sink` receives matches): the
/// search never prints; a caller shows progress or streams poses by implementing this.
pub trait SearchSink {
    /// After every step, with the counts so far and the current pose.
    fn step(&mut self, _stats: &SearchStats, _current: &Evaluation) {}
    /// When the best valid grasp improves.
    fn improved(&mut self, _best: &Evaluation) {}
    /// Before the events of each movement a request tries; again whenever the events switch
    /// movement (movements searched side by side interleave, see
    /// [`find_grasp`](fn@super::find_grasp)).
    fn movement_started(&mut self, _name: &str) {}
}

/// A sink that ignores everything.
impl SearchSink for () {}

/// Why a search cannot start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SearchError {
    /// The object has no hooks.
    #[error("the object has no hooks")]
    NoHooks,
    /// The shoulder coincides with the hook.
    #[error("the shoulder is on the hook ({0:?}); put the character somewhere else")]
    ShoulderOnHook([f64; 3]),
    /// The hook is far outside the object.
    #[error("the hook is {distance:.3} m outside the object, farther than the hand reaches ({reach:.3} m); put the hook in or on the object")]
    HookOutside {
        /// Distance from the hook to the surface, metres.
        distance: f64,
        /// The hand's reach, metres.
        reach: f64,
    },
    /// No part of the object is small enough for the hand (§3.2).
    #[error("the object is at least {width:.3} m wide in every direction, more than twice the hand's mean finger length ({finger:.3} m); it cannot be grasped with one hand (§3.2). Is its scale right?")]
    TooBig {
        /// Smallest width found, metres.
        width: f64,
        /// Mean finger length, metres.
        finger: f64,
    },
    /// A parameter is NaN, negative or otherwise unusable.
    #[error(transparent)]
    BadParameter(#[from] ParameterError),
    /// The hand has no movement of the requested name.
    #[error("hand '{hand}' has no movement '{movement}'; it has {}{}", known.join(", "), if *auto_allowed { ", or use auto" } else { " (a planner runs one movement)" })]
    UnknownMovement {
        /// The hand.
        hand: String,
        /// The movement asked for.
        movement: String,
        /// The hand's movements.
        known: Vec<String>,
        /// Whether `auto` would have been taken (by a whole request, not by one planner).
        auto_allowed: bool,
    },
}

/// Whether the planner has more to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PlannerStatus {
    /// More steps may improve the pose.
    Searching,
    /// The stop rule holds.
    Converged,
    /// `max_steps` reached without convergence.
    StepLimit,
}

/// Counts and time spent.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct SearchStats {
    /// Optimization steps taken.
    pub steps: u32,
    /// Poses evaluated (TranslateToFree + finger closing + quality).
    pub evaluations: u64,
    /// Capsule queries.
    pub collision_queries: u64,
    /// Queries answered by the exact path.
    pub exact_fallbacks: u64,
    /// Hand placements checked by TranslateToFree.
    pub placements: u64,
    /// Poses whose contacts were found and tested for force closure.
    pub stability_tests: u64,
    /// Restarts after the character turned.
    pub restarts: u32,
    /// Searches begun again from a hook in the object's material, the first hook lying
    /// outside it, for want of a grasp pushing from every side ([`GraspPlanner`]; 0 or 1).
    pub hook_moves: u32,
    /// Searches begun again with the hand hung nearer its palm or farther from it, the hook
    /// lying in the material ([`GraspPlanner`]; 0 or 1; the result's `terms.gdist` less its
    /// `offset` is how much nearer, negative for farther).
    pub hung_again: u32,
    /// Searches begun once more from the same hang along other random angles, the second hang
    /// having found no grasp that pushes from every side either ([`GraspPlanner`]; 0 or 1).
    pub searched_again: u32,
    /// Time spent searching, seconds.
    pub seconds: f64,
}

/// Would a slice of work as long as the `last` one end past `deadline`? Never before the first
/// slice (`last` zero): a time budget, a game frame's or a whole request's, is overrun by a
/// single slice at most, and every search takes one.
pub(crate) fn would_overrun(deadline: Instant, last: Duration) -> bool {
    !last.is_zero() && Instant::now() + last > deadline
}

/// An anytime grasp search for one hand, object and movement.
#[derive(Debug)]
pub struct GraspPlanner<'a> {
    ctx: EvaluationContext<'a>,
    params: SearchParams,
    rng: SplitMix64,
    reach_direction: Vec3,
    current: Evaluation,
    best_valid: Option<Evaluation>,
    status: PlannerStatus,
    since_improvement: u32,
    /// Steps ended with a valid best pose that pushes from one side only.
    one_sided_steps: u32,
    /// The hook nearest the shoulder, which the search starts from after every restart.
    first_hook: Point3,
    /// How often the search has begun again for want of a grasp that pushes from every side
    /// ([`GraspPlanner::retry`]), and the step it last began (or restarted) at.
    retries: u32,
    retried_at_step: u32,
    /// The context (hook and hang) the best valid pose was found in, when the search has since
    /// hung the hand again.
    best_found_at: Option<EvaluationContext<'a>>,
    axis: usize,
    stats: SearchStats,
    workspaces: Vec<Workspace>,
    candidates: [Rotation; 6],
    results: Vec<Option<Evaluation>>,
    /// World capsules of each candidate whose stability waits to be judged.
    candidate_capsules: Vec<Vec<Capsule>>,
    /// Candidates of the step in progress whose contacts showed they cannot push from every
    /// side, where only that could let them count: left unjudged.
    ruled_out: [bool; 6],
    /// The sink has heard of the current best valid pose.
    best_told: bool,
    /// A restart's work not done yet: it runs in slices.
    restarting: Option<Restart>,
    /// Candidates of the step in progress (0: none in progress).
    step_size: usize,
    /// How many of them are evaluated.
    evaluated: usize,
}

/// What a restart still has to do before optimization steps begin.
#[derive(Debug, Clone)]
enum Restart {
    /// Sampling hook rotations (§5.6.2.1).
    Sampling(InitialApproximation),
    /// Evaluating the rotation to start from.
    Evaluating(Rotation),
}

/// Initial-approximation samples per slice: each is one TranslateToFree, less than one candidate
/// of a step costs. One a slice (rather than six) keeps a 4 ms frame in wasm on the mug
/// (frames at most 4.8 ms where six a slice took 13 ms each; `docs/PERFORMANCE.md`).
pub const SAMPLES_PER_SLICE: usize = 1;

/// The fraction of its grasp center's height out of the palm by which a search's second hang
/// brings the hand nearer an object its first found no grasp pushing from every side of. The
/// Shadow hand's power grasps of the 4.5 cm lemon: hung at its derived grasp center, 4.8 cm out
/// of the palm, it caged the lemon between its fingertips (one-sided, or nothing valid, on every
/// seed); hung 2.4 to 2.8 cm out, it closed on it from every side with the thumb on it, hung 3.3
/// cm or more, nothing valid (docs/QUALITY.md). Hung that near from the first, the
/// hand gripped the torus by its tube where MuJoCo let it turn under gravity: the nearer hang is
/// a second try, not the first.
pub const SECOND_HANG_NEARER: f64 = 0.45;

/// The fraction of its grasp center's height out of the palm by which a search's second hang
/// takes the hand farther from an object that had already pushed the open hand back off the
/// hook (hung nearer, it would back off to where it was). The human hand's power grasps of the
/// 3 cm thick cereal box from a shoulder turned 60°: the box's top edge against the palm, the
/// fingers over it, every contact pushing one way (seeds 1–6); hung twice as far out, the edge
/// sits in the fingers and they close round it from every side (docs/QUALITY.md).
pub const SECOND_HANG_FARTHER: f64 = 1.0;

/// How many times a search may begin again for want of a grasp that pushes from every side
/// ([`GraspPlanner::retry`]): hung a second time, then along other random angles. The human
/// hand's power grasp of the cereal box from a shoulder turned 60°, seed 3, found only a
/// one-sided grasp from its second hang, farther out (and, tried, from the nearer one); searched
/// again from the farther one it found one that pushes from every side, as seeds 1, 2 and 4–6
/// had (docs/QUALITY.md). Where no such grasp exists (a claw under a ball's
/// equator) the search takes half as long again before it returns its one-sided best.
const MOST_RETRIES: u32 = 2;

impl<'a> GraspPlanner<'a> {
    /// Sets up the search: nearest hook, starting position (or the initial approximation), and
    /// evaluates it.
    pub fn new(
        hand: &'a HandModel,
        object: &'a ObjectModel,
        movement: &'a GraspMovement,
        shoulder: Point3,
        params: SearchParams,
    ) -> Result<Self, SearchError> {
        check_params(&params, &shoulder)?;
        let hook = nearest_hook(object.hooks(), &shoulder).ok_or(SearchError::NoHooks)?;
        let start =
            start_rotation(&hook, &shoulder, &params.up).ok_or(SearchError::ShoulderOnHook([
                shoulder.x, shoulder.y, shoulder.z,
            ]))?;
        let reach = hand_reach(hand);
        let outside = object.collider().exact().signed_distance(&hook);
        if outside > reach {
            return Err(SearchError::HookOutside {
                distance: outside,
                reach,
            });
        }
        let finger = mean_finger_length(hand);
        let width = smallest_width(object);
        if width > 2.0 * finger {
            return Err(SearchError::TooBig { width, finger });
        }
        let size = object.report().size;
        let diagonal = (size[0] * size[0] + size[1] * size[1] + size[2] * size[2]).sqrt();
        let mut weights = params
            .weights
            .unwrap_or_else(|| QualityWeights::for_movement(movement));
        if !params.validity.judges_contacts() {
            weights.stability = 0.0;
        }
        let center = object.center_of_mass();
        let torque_scale = object
            .mesh()
            .vertices
            .iter()
            .map(|v| (v - center).norm())
            .fold(0.0, f64::max);
        let ctx = EvaluationContext {
            hand,
            object,
            movement,
            hook,
            hook_depth: hook_depth(object, &hook),
            hang_shift: 0.0,
            shoulder,
            start,
            wrist_range: if hand.is_left() {
                params.wrist_range.mirrored()
            } else {
                params.wrist_range
            },
            weights,
            translate: params.translate,
            max_offset: diagonal + reach,
            closing: params.closing,
            min_fingers: params.min_fingers,
            validity: params.validity,
            contact_model: params.contact_model,
            torque_scale,
        };
        let threads = params.threads.clamp(1, 6);
        let mut planner = Self {
            ctx,
            rng: SplitMix64::new(params.seed),
            reach_direction: horizontal(&(hook - shoulder), &params.up),
            current: placeholder(start),
            best_valid: None,
            status: PlannerStatus::Searching,
            since_improvement: 0,
            one_sided_steps: 0,
            first_hook: hook,
            retries: 0,
            retried_at_step: 0,
            best_found_at: None,
            axis: 0,
            stats: SearchStats::default(),
            workspaces: (0..threads).map(|_| Workspace::new(hand)).collect(),
            candidates: [Rotation::identity(); 6],
            results: vec![None; 6],
            candidate_capsules: (0..6)
                .map(|_| Vec::with_capacity(hand.capsules().len()))
                .collect(),
            ruled_out: [false; 6],
            best_told: false,
            restarting: None,
            step_size: 0,
            evaluated: 0,
            params,
        };
        planner.restart();
        Ok(planner)
    }

    /// Starts again from the starting position of the current shoulder. The work (sampling,
    /// then evaluating the start) is done by the next step calls, a slice each.
    fn restart(&mut self) {
        self.restarting = Some(if self.params.initial_approximation {
            Restart::Sampling(InitialApproximation::new())
        } else {
            Restart::Evaluating(self.ctx.start)
        });
        self.current = placeholder(self.ctx.start);
        self.best_valid = None;
        self.best_found_at = None;
        self.status = PlannerStatus::Searching;
        self.since_improvement = 0;
        self.one_sided_steps = 0;
        // A step in progress was around the old start: drop it.
        self.step_size = 0;
        self.results.iter_mut().for_each(|r| *r = None);
    }

    /// One slice of a restart's work.
    fn continue_restart(&mut self, restart: Restart) {
        self.restarting = match restart {
            Restart::Sampling(mut sampling) => {
                let done = sampling.advance(&self.ctx, &mut self.workspaces[0], SAMPLES_PER_SLICE);
                Some(if done {
                    Restart::Evaluating(sampling.best().map_or(self.ctx.start, |(r, _)| r))
                } else {
                    Restart::Sampling(sampling)
                })
            }
            Restart::Evaluating(rotation) => {
                self.current = self.ctx.evaluate(&rotation, &mut self.workspaces[0]);
                self.stats.evaluations += 1;
                self.consider_best(&self.current.clone());
                None
            }
        };
    }

    /// Is a restart's work (the initial approximation, the first evaluation) still running?
    pub fn restarting(&self) -> bool {
        self.restarting.is_some()
    }

    fn consider_best(&mut self, e: &Evaluation) {
        // A search begun again looks for a grasp that pushes from every side: a one-sided one
        // it finds does not displace one found before it began again (docs/QUALITY.md), but may displace another it found itself.
        let may_replace = |b: &Evaluation| {
            self.ctx.rank(e) > self.ctx.rank(b)
                && (self.best_found_at.is_none() || self.ctx.pushes_from_every_side(e))
        };
        if e.validity.is_ok() && self.best_valid.as_ref().is_none_or(may_replace) {
            self.best_valid = Some(e.clone());
            self.best_found_at = None;
            self.best_told = false;
        }
    }

    /// Should the search begin again? At most [`MOST_RETRIES`] times, under a rule that judges
    /// contacts, when it has no valid grasp that pushes from every side and is about to stop,
    /// or has none valid [`SearchParams::one_sided_patience`] steps (at least the stop rule's)
    /// after it began, last began again or restarted.
    fn should_retry(&self) -> bool {
        if self.retries >= MOST_RETRIES || !self.ctx.validity.judges_contacts() {
            return false;
        }
        let every_side = self
            .best_valid
            .as_ref()
            .is_some_and(|b| self.ctx.pushes_from_every_side(b));
        let stop_steps = match self.params.stop {
            StopRule::NoImprovement { steps } => steps,
            StopRule::ThesisLocalMaximum => 0,
        };
        let patience = self.params.one_sided_patience.max(stop_steps);
        !every_side
            && (self.status != PlannerStatus::Searching
                || (self.best_valid.is_none()
                    && self.stats.steps - self.retried_at_step >= patience))
    }

    /// Begins the search again, keeping the best valid pose (with the context it was found in)
    /// for the new search to beat — by a grasp that pushes from every side, or by any valid one
    /// when none was found before ([`GraspPlanner::consider_best`]): the first time with the
    /// hand hung differently ([`GraspPlanner::hang_again`]), the second from the same hang, the
    /// random angles going on where they were, so that the search takes another path.
    fn retry(&mut self) {
        self.retries += 1;
        self.retried_at_step = self.stats.steps;
        let best = self.best_valid.take();
        let found_at = best
            .as_ref()
            .map(|_| self.best_found_at.unwrap_or(self.ctx));
        if self.retries == 1 {
            self.hang_again(best.as_ref());
        } else {
            self.stats.searched_again += 1;
        }
        self.restart();
        self.best_valid = best;
        self.best_found_at = found_at;
    }

    /// Hangs the hand differently: from the middle of the material nearest the hook
    /// ([`material_hook`]) when the hook lies outside the object (a ring's hole); else
    /// [`SECOND_HANG_NEARER`] of the grasp center's height nearer the palm, so that an object
    /// that sat between the curling fingertips sits against the palm, or, when the object
    /// already pushed the open hand back that far (`best`, else the current pose),
    /// [`SECOND_HANG_FARTHER`] of it farther, so that its edge sits in the fingers.
    fn hang_again(&mut self, best: Option<&Evaluation>) {
        let material = material_hook(
            self.ctx.object.collider().exact(),
            &self.ctx.hook,
            &-self.reach_direction,
            &self.params.up,
            hand_reach(self.ctx.hand),
        )
        .and_then(|hook| {
            start_rotation(&hook, &self.ctx.shoulder, &self.params.up).map(|start| (hook, start))
        });
        let height = self.ctx.movement.grasp_center().y;
        let nearer = SECOND_HANG_NEARER * height;
        if let Some((hook, start)) = material {
            self.ctx.set_hook(hook);
            self.ctx.start = start;
            self.reach_direction = horizontal(&(hook - self.ctx.shoulder), &self.params.up);
            self.stats.hook_moves += 1;
        } else if nearer.is_finite() && nearer > 0.0 {
            // An object that pushed the open hand back off the hook by `nearer` or more already
            // sits against the palm: hung nearer, the hand would back off to where it was.
            let pose = best.unwrap_or(&self.current);
            self.ctx.hang_shift = if pose.offset >= nearer {
                -SECOND_HANG_FARTHER * height
            } else {
                nearer
            };
            self.stats.hung_again += 1;
        }
    }

    fn collect_counters(&mut self) {
        for ws in &mut self.workspaces {
            self.stats.collision_queries += ws.counters.queries;
            self.stats.exact_fallbacks += ws.counters.exact_fallbacks;
            self.stats.placements += ws.counters.placements;
            self.stats.stability_tests += ws.counters.stability_tests;
            ws.counters = Default::default();
        }
    }

    /// One optimization step: a random angle, the step's candidates, move to the best.
    pub fn step(&mut self) -> PlannerStatus {
        self.step_into(&mut ())
    }

    /// One optimization step, telling `sink` what happened: first any restart's remaining work,
    /// then the rest of the step in progress or a whole new one.
    pub fn step_into(&mut self, sink: &mut dyn SearchSink) -> PlannerStatus {
        let steps = self.stats.steps;
        while self.status == PlannerStatus::Searching && self.stats.steps == steps {
            self.slice_into(sink);
        }
        self.status
    }

    /// The smallest unit of work, for game loops with a frame budget: one slice of a restart
    /// (six initial-approximation samples, or the start's evaluation), or one candidate of the
    /// step in progress (all of them when the planner has several threads), and with
    /// [`SearchParams::lazy_stability`] the stability test of at most one of them. `sink` hears
    /// of a step when its outcome is decided.
    pub fn slice(&mut self) -> PlannerStatus {
        self.slice_into(&mut ())
    }

    /// [`GraspPlanner::slice`], telling `sink`.
    pub fn slice_into(&mut self, sink: &mut dyn SearchSink) -> PlannerStatus {
        if self.status != PlannerStatus::Searching {
            return self.status;
        }
        let began = Instant::now();
        let mut step_done = false;
        if let Some(restart) = self.restarting.take() {
            self.continue_restart(restart);
        } else {
            if self.step_size == 0 {
                let angle = self.rng.uniform(0.0, self.params.max_angle);
                self.step_size = step_candidates(
                    self.params.step,
                    &self.current.rotation,
                    angle,
                    self.axis,
                    &mut self.candidates,
                );
                self.axis = (self.axis + 1) % 3;
                self.evaluated = 0;
                self.ruled_out = [false; 6];
            }
            let whole_steps = self.workspaces.len() > 1;
            if self.evaluated < self.step_size {
                let until = if whole_steps {
                    self.step_size
                } else {
                    self.evaluated + 1
                };
                self.evaluate_candidates(self.evaluated, until);
                self.evaluated = until;
            }
            // On one thread a slice judges the stability of one candidate, after the last
            // candidate's own evaluation or in a slice of its own.
            if self.evaluated == self.step_size
                && (!self.defers_stability()
                    || self.judge_deferred_stability(if whole_steps { 6 } else { 1 }))
            {
                self.finish_step();
                step_done = true;
            }
        }
        self.collect_counters();
        self.stats.seconds += began.elapsed().as_secs_f64();
        if let Some(best) = self.best_valid.as_ref().filter(|_| !self.best_told) {
            sink.improved(best);
            self.best_told = true;
        }
        if step_done {
            sink.step(&self.stats, &self.current);
        }
        self.status
    }

    /// Ends the step whose candidates are all evaluated: move to the best, apply the stop rule.
    fn finish_step(&mut self) {
        let n = std::mem::take(&mut self.step_size);
        self.stats.evaluations += n as u64;
        self.stats.steps += 1;
        let mut improved = false;
        for k in 0..n {
            let e = self.results[k]
                .take()
                .expect("every candidate was evaluated");
            // A candidate whose stability was left unjudged could not have been chosen.
            if self.ctx.stability_pending(&e) {
                continue;
            }
            self.consider_best(&e);
            // Beyond the thesis: a valid grasp beats an invalid one whatever their qualities,
            // and one that pushes from every side a one-sided one (`EvaluationContext::rank`).
            if self.ctx.walk_rank(&e) > self.ctx.walk_rank(&self.current) {
                self.current = e;
                improved = true;
            }
        }
        self.since_improvement = if improved {
            0
        } else {
            self.since_improvement + 1
        };
        if self
            .best_valid
            .as_ref()
            .is_some_and(|b| !self.ctx.pushes_from_every_side(b))
        {
            self.one_sided_steps += 1;
        }
        self.status = match self.params.stop {
            StopRule::ThesisLocalMaximum if !improved => PlannerStatus::Converged,
            // Without a valid grasp yet, keep exploring up to the step limit; with only one
            // that pushes from one side, for `one_sided_patience` steps more.
            StopRule::NoImprovement { steps }
                if self.since_improvement >= steps
                    && self.best_valid.as_ref().is_some_and(|b| {
                        self.ctx.pushes_from_every_side(b)
                            || self.one_sided_steps >= self.params.one_sided_patience
                    }) =>
            {
                PlannerStatus::Converged
            }
            _ if self.stats.steps >= self.params.max_steps => PlannerStatus::StepLimit,
            _ => PlannerStatus::Searching,
        };
        if self.stats.steps < self.params.max_steps && self.should_retry() {
            self.retry();
        }
    }

    /// Does the planner judge its candidates' stability lazily
    /// ([`SearchParams::lazy_stability`])?
    fn defers_stability(&self) -> bool {
        self.params.lazy_stability
            && self.ctx.validity.judges_contacts()
            && self.ctx.quality_ignores_stability()
    }

    /// Judges the stability of at most `most` more of the step's candidates that need it, best
    /// quality first (ties in candidate order, as the move compares them), until one holds and
    /// pushes from every side: no candidate of lower quality can then become the current or the
    /// best pose. It stops sooner at a quality that can beat neither the valid current pose nor
    /// the best, when those push from every side (a one-sided pose any candidate that turns out
    /// to push from every side beats, whatever its quality). A candidate below the quality of a
    /// one-sided current pose and best could only count by pushing from every side: its contacts
    /// are found first, and if they push from one side its force closure is not judged. Returns
    /// whether the step's outcome is decided; called again, it goes on where it stopped.
    fn judge_deferred_stability(&mut self, mut most: usize) -> bool {
        let n = self.step_size;
        let mut order = [0, 1, 2, 3, 4, 5];
        let quality = |k: usize| {
            self.results[k]
                .as_ref()
                .map_or(f64::NEG_INFINITY, |e| e.quality)
        };
        order[..n].sort_by(|&a, &b| quality(b).total_cmp(&quality(a)).then(a.cmp(&b)));
        for &k in &order[..n] {
            let Some(e) = self.results[k].as_mut() else {
                continue;
            };
            if !self.ctx.stability_pending(e) || self.ruled_out[k] {
                continue;
            }
            // A pending pose may yet push from every side: it can beat a one-sided pose of
            // any quality.
            let can_beat = |other: &Evaluation| {
                other.validity.is_err()
                    || !self.ctx.pushes_from_every_side(other)
                    || e.quality > other.quality
            };
            let beats_current = can_beat(&self.current);
            let beats_best = self.best_valid.as_ref().is_none_or(can_beat);
            if !beats_current && !beats_best {
                return true;
            }
            // Below the quality of a valid one-sided current pose and best, it can beat them
            // only by pushing from every side: its contacts say whether it could, before the
            // force-closure program is solved.
            let one_sided_above = |other: &Evaluation| {
                other.validity.is_ok()
                    && !self.ctx.pushes_from_every_side(other)
                    && e.quality <= other.quality
            };
            let only_from_every_side = one_sided_above(&self.current)
                && self.best_valid.as_ref().is_some_and(one_sided_above);
            if most == 0 {
                return false;
            }
            most -= 1;
            let ws = &mut self.workspaces[0];
            ws.capsules.clone_from(&self.candidate_capsules[k]);
            self.ctx.find_contacts(ws);
            if only_from_every_side && !self.ctx.contacts_push_from_every_side(ws) {
                // It stays unjudged: it cannot become the current or the best pose.
                self.ruled_out[k] = true;
                continue;
            }
            self.ctx.judge_found_contacts(e, ws);
            if e.validity.is_ok() && self.ctx.pushes_from_every_side(e) {
                return true;
            }
        }
        true
    }

    /// The quality a candidate of this step must exceed to change anything, for
    /// [`EvaluationContext::evaluate_pose_to_beat`]: when the current pose and the best are
    /// valid and rank first by validity ([`EvaluationContext::walk_rank`] and
    /// [`EvaluationContext::rank`]), a candidate replaces either only with a higher quality, so
    /// one at most the lower of theirs changes nothing; else −∞.
    fn bar_to_beat(&self) -> f64 {
        let first = |e: &Evaluation| e.validity.is_ok() && self.ctx.pushes_from_every_side(e);
        match &self.best_valid {
            Some(best) if first(&self.current) && first(best) => {
                self.current.quality.min(best.quality)
            }
            _ => f64::NEG_INFINITY,
        }
    }

    /// Evaluates candidates `from..to` of the step in progress into `results`.
    fn evaluate_candidates(&mut self, from: usize, to: usize) {
        let lazy = self.defers_stability();
        let bar = self.bar_to_beat();
        let ctx = &self.ctx;
        let evaluate = |r: &Rotation, ws: &mut Workspace, capsules: &mut Vec<Capsule>| {
            let mut e = ctx.evaluate_pose_to_beat(r, ws, bar);
            if !lazy {
                if ctx.stability_pending(&e) {
                    ctx.judge_stability(&mut e, ws);
                }
                return e;
            }
            if ctx.stability_pending(&e) {
                capsules.clone_from(&ws.capsules);
            }
            e
        };
        let candidates = &self.candidates[from..to];
        let results = &mut self.results[from..to];
        let capsules = &mut self.candidate_capsules[from..to];
        let n = to - from;
        let threads = self.workspaces.len().min(n);
        if threads <= 1 {
            let ws = &mut self.workspaces[0];
            for ((slot, r), c) in results.iter_mut().zip(candidates).zip(capsules) {
                *slot = Some(evaluate(r, ws, c));
            }
            return;
        }
        // Each workspace takes the next candidate nobody has taken yet: candidates differ in
        // cost several times over, and fixed shares left one thread waiting for the other.
        // This thread starts at once with the first workspace; the others go to rayon's pool
        // (its threads live between steps instead of being started for each), whose sleeping
        // threads took up to half a millisecond to wake on a virtual machine: handing it the
        // whole step made every step wait for one before its first candidate. Results land by
        // index, so the outcome does not depend on the thread count.
        let work = std::sync::Mutex::new(results.iter_mut().zip(candidates).zip(capsules));
        let take_and_evaluate = |ws: &mut Workspace| loop {
            let next = work
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .next();
            let Some(((slot, r), c)) = next else {
                break;
            };
            *slot = Some(evaluate(r, ws, c));
        };
        let (here, helpers) = self.workspaces[..threads]
            .split_first_mut()
            .expect("at least two workspaces");
        rayon::in_place_scope(|scope| {
            for ws in helpers {
                scope.spawn(|_| take_and_evaluate(ws));
            }
            take_and_evaluate(here);
        });
    }

    /// Steps until the time budget is spent or the search stops.
    pub fn run_for(&mut self, budget: Duration) -> PlannerStatus {
        self.run_for_into(budget, &mut ())
    }

    /// Works in [slices](GraspPlanner::slice) until the time budget is spent or the search
    /// stops, telling `sink`. At least one slice is done; another only when, judged by the last
    /// one's duration, it should end within the budget — so a game frame's budget is overrun
    /// only by a single slice longer than it.
    pub fn run_for_into(&mut self, budget: Duration, sink: &mut dyn SearchSink) -> PlannerStatus {
        let deadline = Instant::now() + budget;
        let mut last = Duration::ZERO;
        while self.status == PlannerStatus::Searching && !would_overrun(deadline, last) {
            let began = Instant::now();
            self.slice_into(sink);
            last = began.elapsed();
        }
        self.status
    }

    /// Steps until the stop rule or the step limit.
    pub fn run_to_end(&mut self) -> PlannerStatus {
        self.run_to_end_into(&mut ())
    }

    /// Steps until the stop rule or the step limit, telling `sink`.
    pub fn run_to_end_into(&mut self, sink: &mut dyn SearchSink) -> PlannerStatus {
        while self.status == PlannerStatus::Searching {
            self.step_into(sink);
        }
        self.status
    }

    /// Tells the planner where the shoulder is now. If the direction from the shoulder to the
    /// hook, seen from above, turned by more than the restart angle, the search restarts from the
    /// new starting position (§6.5.6) and returns true; otherwise only wDist changes.
    /// A search that had hung the hand again restarts from its first hook and hang.
    pub fn set_shoulder(&mut self, shoulder: Point3) -> Result<bool, SearchError> {
        check_params(&self.params, &shoulder)?;
        start_rotation(&self.ctx.hook, &shoulder, &self.params.up).ok_or(
            SearchError::ShoulderOnHook([shoulder.x, shoulder.y, shoulder.z]),
        )?;
        let first_start = start_rotation(&self.first_hook, &shoulder, &self.params.up).ok_or(
            SearchError::ShoulderOnHook([shoulder.x, shoulder.y, shoulder.z]),
        )?;
        self.ctx.shoulder = shoulder;
        let direction = horizontal(&(self.ctx.hook - shoulder), &self.params.up);
        let pending = self.restarting.is_some();
        let turned = direction.dot(&self.reach_direction).clamp(-1.0, 1.0).acos();
        if turned > self.params.restart_angle {
            self.ctx.set_hook(self.first_hook);
            self.ctx.start = first_start;
            self.reach_direction = horizontal(&(self.first_hook - shoulder), &self.params.up);
            self.ctx.hang_shift = 0.0;
            self.retries = 0;
            self.retried_at_step = self.stats.steps;
            self.stats.restarts += 1;
            self.restart();
            return Ok(true);
        }
        if pending {
            // The restart in progress evaluates with the new shoulder.
            return Ok(false);
        }
        // Candidates of a step in progress were partly scored with the old shoulder: drop it.
        self.step_size = 0;
        self.current = self
            .ctx
            .evaluate(&self.current.rotation, &mut self.workspaces[0]);
        self.best_valid = None;
        self.best_found_at = None;
        self.consider_best(&self.current.clone());
        self.status = PlannerStatus::Searching;
        self.since_improvement = 0;
        self.one_sided_steps = 0;
        Ok(false)
    }

    /// Status.
    pub fn status(&self) -> PlannerStatus {
        self.status
    }

    /// The best valid pose so far.
    pub fn best(&self) -> Option<&Evaluation> {
        self.best_valid.as_ref()
    }

    /// The current pose of the search (valid or not).
    pub fn current(&self) -> &Evaluation {
        &self.current
    }

    /// Counts and time.
    pub fn stats(&self) -> SearchStats {
        self.stats
    }

    /// The evaluation context (hand, object, hook, shoulder, start...).
    pub fn context(&self) -> &EvaluationContext<'a> {
        &self.ctx
    }

    /// The pose a result reports, the best valid pose or else the current one, with the
    /// context it was evaluated in (its hook may be one the search has since moved from).
    pub fn chosen(&self) -> (&Evaluation, &EvaluationContext<'a>) {
        match &self.best_valid {
            Some(best) => (best, self.best_found_at.as_ref().unwrap_or(&self.ctx)),
            None => (&self.current, &self.ctx),
        }
    }

    /// Re-creates [`GraspPlanner::chosen`]'s pose in `ws` (deterministic) and returns it again
    /// with its context.
    pub fn chosen_pose(&self, ws: &mut Workspace) -> (Evaluation, &EvaluationContext<'a>) {
        let (e, ctx) = self.chosen();
        (ctx.evaluate(&e.rotation, ws), ctx)
    }
}

/// The current pose before a (re)start has evaluated one.
fn placeholder(rotation: Rotation) -> Evaluation {
    Evaluation {
        rotation,
        quality: f64::NEG_INFINITY,
        terms: Default::default(),
        offset: 0.0,
        fingers_touching: 0,
        validity: Err(Invalid::NotEvaluated),
        closure_margin: None,
        normal_cap: None,
    }
}

fn check_params(p: &SearchParams, shoulder: &Point3) -> Result<(), ParameterError> {
    finite_point("shoulder", [shoulder.x, shoulder.y, shoulder.z])?;
    in_range(
        "max_angle",
        p.max_angle,
        1e-9,
        2.0 * std::f64::consts::PI,
        "radians",
    )?;
    in_range("restart_angle", p.restart_angle, 0.0, 1e3, "radians")?;
    if !p.up.iter().all(|c| c.is_finite()) || p.up.norm() < 1e-9 {
        return Err(ParameterError::Up);
    }
    in_range(
        "interpolations",
        p.closing.interpolations as f64,
        1.0,
        10_000.0,
        "",
    )?;
    if let Some(t) = p.closing.contact_tolerance {
        in_range("contact_tolerance", t, 1e-9, 1.0, "metres")?;
    }
    let steps_ok = match p.translate {
        TranslateMode::Steps { step } => step.is_finite() && step > 1e-6,
        TranslateMode::Bisection { coarse, precision }
        | TranslateMode::DistanceBound { coarse, precision } => {
            coarse.is_finite()
                && precision.is_finite()
                && coarse > 1e-6
                && precision > 1e-7
                && precision <= coarse
        }
    };
    if !steps_ok {
        return Err(ParameterError::TranslateSteps);
    }
    if let Some(w) = p.weights {
        w.check()?;
    }
    p.contact_model.check()?;
    in_range("max_steps", f64::from(p.max_steps), 1.0, 1e6, "")?;
    in_range("threads", p.threads as f64, 1.0, MAX_THREADS as f64, "")?;
    Ok(())
}

/// Direction projected on the plane across `up`, normalized (zero if vertical).
fn horizontal(d: &Vec3, up: &Vec3) -> Vec3 {
    let u = up.normalize();
    let h = d - u * d.dot(&u);
    if h.norm() < 1e-12 {
        Vec3::zeros()
    } else {
        h.normalize()
    }
}

/// Farthest capsule point from the root in the rest pose, metres.
fn hand_reach(hand: &HandModel) -> f64 {
    let rest = vec![Rotation::identity(); hand.bones().len()];
    let world = hand.pose_transforms(&crate::math::Transform::identity(), &rest);
    hand.capsules()
        .iter()
        .map(|c| {
            let w = world[c.bone];
            (w * c.a).coords.norm().max((w * c.b).coords.norm()) + c.radius
        })
        .fold(0.0, f64::max)
}

/// Mean over fingers of the chain's length from its first joint to its tip.
fn mean_finger_length(hand: &HandModel) -> f64 {
    let total: f64 = hand
        .fingers()
        .iter()
        .map(|f| {
            f.bones
                .iter()
                .flat_map(|&b| hand.bone_capsules(b))
                .map(|c| (c.b - c.a).norm())
                .sum::<f64>()
        })
        .sum();
    total / hand.fingers().len() as f64
}

/// Smallest extent of the object's vertices along 13 directions (axes, face and body diagonals).
/// One pass over the vertices with plain comparisons: every planner asks it (three with `auto`),
/// and thirteen passes with `f64::min`/`max` cost 2.6 M instructions each on a 15k-triangle scan.
fn smallest_width(object: &ObjectModel) -> f64 {
    let mut directions = [Vec3::zeros(); 13];
    let mut count = 0;
    for x in -1i32..=1 {
        for y in -1i32..=1 {
            for z in -1i32..=1 {
                // One of each ± pair.
                if (x, y, z) > (0, 0, 0) {
                    directions[count] = Vec3::new(x as f64, y as f64, z as f64).normalize();
                    count += 1;
                }
            }
        }
    }
    let mut lo = [f64::INFINITY; 13];
    let mut hi = [f64::NEG_INFINITY; 13];
    for p in &object.mesh().vertices {
        for (k, d) in directions.iter().enumerate() {
            let s = p.coords.dot(d);
            if s < lo[k] {
                lo[k] = s;
            }
            if s > hi[k] {
                hi[k] = s;
            }
        }
    }
    (0..13).map(|k| hi[k] - lo[k]).fold(f64::INFINITY, f64::min)
}
