//! One grasp request end to end, the decisions every front end shares (the CLI, the batch and
//! the Python package): which movements `auto` tries, a planner per movement, and which result
//! wins.

use std::time::Duration;

// `std::time::Instant` panics in the browser (wasm32); web-time is the same API on every target.
use web_time::Instant;

use crate::hand::movement::GraspMovement;
use crate::hand::HandModel;
use crate::math::Point3;
use crate::object::ObjectModel;
use crate::workspace::Workspace;

use std::sync::mpsc::Sender;
use std::sync::{Condvar, Mutex, MutexGuard, PoisonError};

use rayon::prelude::*;

use super::defaults::AUTO_MOVEMENT;
use super::planner::would_overrun;
use super::{
    Evaluation, GraspPlanner, GraspResult, PlannerStatus, SearchError, SearchParams, SearchSink,
    SearchStats,
};

/// What to search for.
#[derive(Debug, Clone)]
pub struct GraspRequest {
    /// A movement of the hand, or [`AUTO_MOVEMENT`].
    pub movement: String,
    /// Shoulder position, object frame.
    pub shoulder: Point3,
    /// Search parameters (the seed among them).
    pub params: SearchParams,
    /// Wall-time budget of the whole request, every movement's search within it (side by side
    /// on threads they run at once; in turn they take a [slice](GraspPlanner::slice) of work
    /// each until it is spent). No search begins a slice that its last slice's duration says
    /// would end past it, and each takes one at least, so the budget is overrun by about one
    /// slice at most. `None` runs each search to its stop rule, which makes the result depend
    /// on the inputs and the seed only.
    pub budget: Option<Duration>,
}

/// The movements a request tries: the named one, or for `auto` the hand's authored (or derived)
/// movements, the generic `close` only when there is no other.
pub fn movements_to_try<'h>(
    hand: &'h HandModel,
    movement: &str,
) -> Result<Vec<&'h GraspMovement>, SearchError> {
    if movement == AUTO_MOVEMENT {
        let chosen: Vec<&GraspMovement> = hand
            .movements()
            .iter()
            .filter(|m| m.name() != "close")
            .collect();
        if !chosen.is_empty() {
            return Ok(chosen);
        }
        return hand
            .movement("close")
            .map(|m| vec![m])
            .ok_or_else(|| unknown_movement(hand, "close"));
    }
    hand.movement(movement)
        .map(|m| vec![m])
        .ok_or_else(|| unknown_movement(hand, movement))
}

/// The movement a single-movement search (a planner, a simulated grasp) uses when none is
/// named: the hand's `power`, else its first movement.
pub fn default_movement(hand: &HandModel) -> Result<&GraspMovement, SearchError> {
    hand.movement("power")
        .or_else(|| hand.movements().first())
        .ok_or_else(|| unknown_movement(hand, "power"))
}

fn unknown_movement(hand: &HandModel, movement: &str) -> SearchError {
    SearchError::UnknownMovement {
        hand: hand.name().to_string(),
        movement: movement.to_string(),
        known: hand
            .movements()
            .iter()
            .map(|m| m.name().to_string())
            .collect(),
        auto_allowed: true,
    }
}

/// Whether result `a` beats `b`: valid first, then the larger Ferrari–Canny ε (the grasp that
/// resists the largest disturbance), then the smaller gDist. Qualities of different movements
/// use different formulas (Eq. 5.1 and 5.2) and are not compared.
pub fn better_grasp(a: &GraspResult, b: &GraspResult) -> bool {
    (a.valid, a.stability.epsilon, -a.terms.gdist) > (b.valid, b.stability.epsilon, -b.terms.gdist)
}

/// How many steps `auto` lets a movement's search go on without a valid pose once another
/// movement's search has ended with a valid grasp. Such a search cannot win unless it finds a
/// valid pose with a larger ε later, and it used to run to the step limit (500 steps, most of
/// the time of `prehensile grasp` on the built-in sphere, torus and mug, whose precision grasps
/// the human hand does not find). Measured by `examples/first_valid.rs` (human, Shadow and
/// cartoon4 hands; the built-in objects and `assets/objects`; seeds 1–3): of 194 searches that
/// found a valid pose, the median found it at step 4, 95% by step 42, and 4 past step 100. On its
/// 117 requests of two movements, stopping at 100 saves 44% of all steps and changes one winner
/// (the Shadow hand's mug, seed 1: its precision grasp, first valid at step 284, gives way to its
/// power grasp).
pub const AUTO_PATIENCE: u32 = 100;

/// Searches every movement the request names and returns the best result. `sink` hears each
/// movement's start and every step. With several movements and `params.threads` above 1 the
/// movements are searched side by side, each on a thread of its own (the sink then hears the
/// searches interleaved); on one thread they take a step each in turn. A search with no valid
/// pose after [`AUTO_PATIENCE`] steps stops once another movement's search has ended with a valid
/// grasp within as many steps; each search judges that with the others at the same step, so
/// without a budget the result is the same either way. A budget ([`GraspRequest::budget`]) is
/// the whole request's: every search stops when it is spent, and advances by slices instead
/// of steps, to stop within it.
pub fn find_grasp(
    hand: &HandModel,
    object: &ObjectModel,
    request: &GraspRequest,
    sink: &mut dyn SearchSink,
) -> Result<GraspResult, SearchError> {
    let deadline = request.budget.map(|budget| Instant::now() + budget);
    let movements = movements_to_try(hand, &request.movement)?;
    let planners = if request.params.threads > 1 && movements.len() > 1 {
        search_side_by_side(hand, object, request, &movements, deadline, sink)?
    } else {
        search_in_turn(hand, object, request, &movements, deadline, sink)?
    };
    Ok(best_result(hand, &planners, request.params.threads))
}

/// The planner of one movement of the request.
fn planner<'a>(
    hand: &'a HandModel,
    object: &'a ObjectModel,
    movement: &'a GraspMovement,
    request: &GraspRequest,
) -> Result<GraspPlanner<'a>, SearchError> {
    GraspPlanner::new(
        hand,
        object,
        movement,
        request.shoulder,
        request.params.clone(),
    )
}

/// The planner's result (its best valid pose, else its current one).
fn result(hand: &HandModel, planner: &GraspPlanner) -> GraspResult {
    GraspResult::from_planner(planner, &mut Workspace::new(hand))
}

/// Where one movement's search of a request is.
#[derive(Debug, Clone, Copy, Default)]
struct Progress {
    /// Steps taken (when ended: the step it ended at).
    steps: u32,
    /// `Some(valid)` once the search has ended, with or without a valid grasp.
    ended: Option<bool>,
}

impl Progress {
    /// Records the planner's step, and its end when it stopped `searching`.
    fn record(&mut self, planner: &GraspPlanner, searching: bool) {
        self.steps = planner.stats().steps;
        if !searching {
            self.ended = Some(planner.best().is_some());
        }
    }
}

/// The patience rule of [`find_grasp`]: does search `me`, with no valid pose after its
/// `progress[me].steps` steps, stop? It reads only searches at the same step or ended.
fn out_of_patience(progress: &[Progress], me: usize) -> bool {
    let steps = progress[me].steps;
    steps >= AUTO_PATIENCE
        && progress
            .iter()
            .enumerate()
            .any(|(j, p)| j != me && p.ended == Some(true) && p.steps <= steps)
}

/// Would a slice as long as the `last` one end past the `deadline`, if there is one?
fn out_of_time(deadline: Option<Instant>, last: Duration) -> bool {
    deadline.is_some_and(|deadline| would_overrun(deadline, last))
}

/// Advances `planner` by a step, or with a `deadline` by a [slice](GraspPlanner::slice) (a
/// step's first evaluation, its restart's initial approximation above all, takes much longer
/// than a frame's budget); returns whether it is still searching and how long that took.
fn advance(
    planner: &mut GraspPlanner,
    deadline: Option<Instant>,
    sink: &mut dyn SearchSink,
) -> (bool, Duration) {
    let began = Instant::now();
    let status = match deadline {
        Some(_) => planner.slice_into(sink),
        None => planner.step_into(sink),
    };
    (status == PlannerStatus::Searching, began.elapsed())
}

/// The movements' searches a step (with a `deadline`, a slice) each in turn, on this thread,
/// to their stop rules, the patience rule or the `deadline`.
fn search_in_turn<'a>(
    hand: &'a HandModel,
    object: &'a ObjectModel,
    request: &GraspRequest,
    movements: &[&'a GraspMovement],
    deadline: Option<Instant>,
    sink: &mut dyn SearchSink,
) -> Result<Vec<GraspPlanner<'a>>, SearchError> {
    let mut planners = movements
        .iter()
        .map(|movement| planner(hand, object, movement, request))
        .collect::<Result<Vec<_>, _>>()?;
    let mut progress = vec![Progress::default(); planners.len()];
    let mut last_step = vec![Duration::ZERO; planners.len()];
    let mut last = None;
    while progress.iter().any(|p| p.ended.is_none()) {
        for (k, planner) in planners.iter_mut().enumerate() {
            if progress[k].ended.is_some() {
                continue;
            }
            if out_of_time(deadline, last_step[k]) {
                progress[k].record(planner, false);
                continue;
            }
            if last != Some(k) {
                sink.movement_started(movements[k].name());
                last = Some(k);
            }
            let searching;
            (searching, last_step[k]) = advance(planner, deadline, sink);
            progress[k].record(planner, searching);
        }
        // Judged after the round, every search at the same step (or ended).
        for (k, planner) in planners.iter().enumerate() {
            if progress[k].ended.is_none()
                && planner.best().is_none()
                && out_of_patience(&progress, k)
            {
                progress[k].ended = Some(false);
            }
        }
    }
    Ok(planners)
}

/// The result of the search that wins among those of one request. Only the searches that found
/// a valid grasp can win, or every one when none did. As within one search, a valid grasp that
/// pushes from every side beats a one-sided wrap whatever their ε
/// (`EvaluationContext::rank`); then [`better_grasp`]'s order decides, the first movement
/// winning ties. A result's 6-D wrench-space hull is the dearest part of it (a few
/// milliseconds on a scan), so the contenders are compared on their ε alone, from the part of
/// the hull that decides it ([`EvaluationContext::epsilon`]), and only the winner's whole
/// result is built, from the pose and contacts its judgement left in its workspace. With
/// `threads` above 1 the contenders are judged side by side on rayon's pool; each judgement is
/// the same on any thread.
fn best_result(hand: &HandModel, planners: &[GraspPlanner], threads: usize) -> GraspResult {
    let any_valid = planners.iter().any(|p| p.best().is_some());
    let can_win: Vec<&GraspPlanner> = planners
        .iter()
        .filter(|p| !any_valid || p.best().is_some())
        .collect();
    if let [only] = can_win[..] {
        return result(hand, only);
    }
    // (valid, pushes from every side, ε, −gDist): `better_grasp`'s order after the ranking,
    // with the pose re-created and its contacts found.
    let judge = |p: &&GraspPlanner| {
        let (chosen, ctx) = p.chosen();
        let mut ws = Workspace::new(hand);
        let again = ctx.evaluate_pose(&chosen.rotation, &mut ws);
        let key = (
            p.best().is_some(),
            p.best().is_some_and(|b| ctx.pushes_from_every_side(b)),
            ctx.epsilon(&mut ws),
            -chosen.terms.gdist,
        );
        (key, again, ws)
    };
    let mut judged: Vec<_> = if threads > 1 {
        can_win.par_iter().map(judge).collect()
    } else {
        can_win.iter().map(judge).collect()
    };
    let mut winner = 0;
    for (k, (key, ..)) in judged.iter().enumerate() {
        if *key > judged[winner].0 {
            winner = k;
        }
    }
    let (_, again, mut ws) = judged.swap_remove(winner);
    let planner = can_win[winner];
    GraspResult::from_found_contacts(planner, planner.chosen().1, again, &mut ws)
}

/// The progress of the searches running side by side, shared by their threads.
struct Race {
    progress: Mutex<Vec<Progress>>,
    advanced: Condvar,
}

impl Race {
    fn lock(&self) -> MutexGuard<'_, Vec<Progress>> {
        self.progress.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Records search `k`'s step; returns whether it goes on. A search out of valid poses for
    /// [`AUTO_PATIENCE`] steps first waits for every search behind it to reach its step.
    fn after_step(&self, k: usize, planner: &GraspPlanner, searching: bool) -> bool {
        let mut progress = self.lock();
        progress[k].record(planner, searching);
        if searching && planner.best().is_none() && progress[k].steps >= AUTO_PATIENCE {
            self.advanced.notify_all();
            let steps = progress[k].steps;
            progress = self
                .advanced
                .wait_while(progress, |p| {
                    p.iter()
                        .enumerate()
                        .any(|(j, q)| j != k && q.ended.is_none() && q.steps < steps)
                })
                .unwrap_or_else(PoisonError::into_inner);
            if out_of_patience(&progress, k) {
                progress[k].ended = Some(false);
            }
        }
        self.advanced.notify_all();
        progress[k].ended.is_none()
    }
}

/// Marks search `k` ended however its thread leaves (a planner error, a panic), so that no
/// search waits for it.
struct EndsSearch<'r>(&'r Race, usize);

impl Drop for EndsSearch<'_> {
    fn drop(&mut self) {
        let mut progress = self.0.lock();
        progress[self.1].ended.get_or_insert(false);
        self.0.advanced.notify_all();
    }
}

/// What a search running on another thread tells the caller's sink.
enum Event {
    Step(Box<(SearchStats, Evaluation)>),
    Improved(Box<Evaluation>),
}

/// A sink that sends its search's events, tagged with the movement's index, to the caller.
struct Forward {
    movement: usize,
    events: Sender<(usize, Event)>,
}

impl SearchSink for Forward {
    fn step(&mut self, stats: &SearchStats, current: &Evaluation) {
        let _ = self.events.send((
            self.movement,
            Event::Step(Box::new((*stats, current.clone()))),
        ));
    }

    fn improved(&mut self, best: &Evaluation) {
        let _ = self
            .events
            .send((self.movement, Event::Improved(Box::new(best.clone()))));
    }
}

/// Every movement's search on a scoped thread of its own (a few movements, each searching for
/// tens of milliseconds or more: a thread's start costs nothing beside it, and unlike a task on
/// rayon's pool it leaves this thread free to pass the events on to `sink`, which need not be
/// `Send`). The candidates of each step still go to rayon's pool.
fn search_side_by_side<'a>(
    hand: &'a HandModel,
    object: &'a ObjectModel,
    request: &GraspRequest,
    movements: &[&'a GraspMovement],
    deadline: Option<Instant>,
    sink: &mut dyn SearchSink,
) -> Result<Vec<GraspPlanner<'a>>, SearchError> {
    let (events, received) = std::sync::mpsc::channel();
    let race = Race {
        progress: Mutex::new(vec![Progress::default(); movements.len()]),
        advanced: Condvar::new(),
    };
    let race = &race;
    std::thread::scope(|scope| {
        let searches: Vec<_> = movements
            .iter()
            .enumerate()
            .map(|(k, &movement)| {
                let mut forward = Forward {
                    movement: k,
                    events: events.clone(),
                };
                scope.spawn(move || {
                    let _ends = EndsSearch(race, k);
                    let mut planner = planner(hand, object, movement, request)?;
                    let mut last_step = Duration::ZERO;
                    loop {
                        if out_of_time(deadline, last_step) {
                            race.lock()[k].record(&planner, false);
                            break;
                        }
                        let searching;
                        (searching, last_step) = advance(&mut planner, deadline, &mut forward);
                        if !race.after_step(k, &planner, searching) {
                            break;
                        }
                    }
                    Ok(planner)
                })
            })
            .collect();
        drop(events);
        // The sink hears which movement each event comes from before the event.
        let mut last = None;
        for (k, event) in received {
            if last != Some(k) {
                sink.movement_started(movements[k].name());
                last = Some(k);
            }
            match event {
                Event::Step(step) => sink.step(&step.0, &step.1),
                Event::Improved(best) => sink.improved(&best),
            }
        }
        searches
            .into_iter()
            .map(|search| search.join().expect("a movement's search panicked"))
            .collect::<Result<Vec<_>, SearchError>>()
    })
}
