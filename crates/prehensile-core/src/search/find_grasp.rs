//! One grasp request end to end, the decisions every front end shares (the CLI, the batch and
//! the Python package): which movements `auto` tries, a planner per movement, and which result
//! wins.

use std::time::Duration;

use crate::hand::HandModel;
use crate::math::Point3;
use crate::movement::GraspMovement;
use crate::object::ObjectModel;
use crate::workspace::Workspace;

use std::sync::mpsc::Sender;

use super::{
    Evaluation, GraspPlanner, GraspResult, SearchError, SearchParams, SearchSink, SearchStats,
};

/// The movement name that tries the hand's movements and keeps the best result.
pub const AUTO_MOVEMENT: &str = "auto";

/// What to search for.
#[derive(Debug, Clone)]
pub struct GraspRequest {
    /// A movement of the hand, or [`AUTO_MOVEMENT`].
    pub movement: String,
    /// Shoulder position, object frame.
    pub shoulder: Point3,
    /// Search parameters (the seed among them).
    pub params: SearchParams,
    /// Wall-time budget per movement; `None` runs each search to its stop rule, which makes the
    /// result depend on the inputs and the seed only.
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
            .ok_or_else(|| SearchError::UnknownMovement(describe(hand, "close")));
    }
    hand.movement(movement)
        .map(|m| vec![m])
        .ok_or_else(|| SearchError::UnknownMovement(describe(hand, movement)))
}

fn describe(hand: &HandModel, movement: &str) -> String {
    let names: Vec<&str> = hand.movements().iter().map(|m| m.name()).collect();
    format!(
        "hand '{}' has no movement '{movement}'; it has {}, or use {AUTO_MOVEMENT}",
        hand.name(),
        names.join(", ")
    )
}

/// Whether result `a` beats `b`: valid first, then the larger Ferrari–Canny ε (the grasp that
/// resists the largest disturbance), then the smaller gDist. Qualities of different movements
/// use different formulas (Eq. 5.1 and 5.2) and are not compared.
pub fn better_grasp(a: &GraspResult, b: &GraspResult) -> bool {
    (a.valid, a.stability.epsilon, -a.terms.gdist) > (b.valid, b.stability.epsilon, -b.terms.gdist)
}

/// Searches every movement the request names and returns the best result. `sink` hears each
/// movement's start and every step. With several movements and `params.threads` above 1 the
/// movements are searched side by side, each on a thread of its own (the sink then hears the
/// searches interleaved); the result is the same either way.
pub fn find_grasp(
    hand: &HandModel,
    object: &ObjectModel,
    request: &GraspRequest,
    sink: &mut dyn SearchSink,
) -> Result<GraspResult, SearchError> {
    let movements = movements_to_try(hand, &request.movement)?;
    let results = if request.params.threads > 1 && movements.len() > 1 {
        search_side_by_side(hand, object, request, &movements, sink)
    } else {
        movements
            .iter()
            .map(|movement| {
                sink.movement_started(movement.name());
                search_movement(hand, object, movement, request, sink)
            })
            .collect()
    };
    let mut best: Option<GraspResult> = None;
    for result in results {
        let result = result?;
        if best.as_ref().is_none_or(|b| better_grasp(&result, b)) {
            best = Some(result);
        }
    }
    Ok(best.expect("movements_to_try returns at least one movement"))
}

/// One movement's search to its stop rule (or the request's budget) and its result.
fn search_movement(
    hand: &HandModel,
    object: &ObjectModel,
    movement: &GraspMovement,
    request: &GraspRequest,
    sink: &mut dyn SearchSink,
) -> Result<GraspResult, SearchError> {
    let mut planner = GraspPlanner::new(
        hand,
        object,
        movement,
        request.shoulder,
        request.params.clone(),
    )?;
    match request.budget {
        Some(b) => planner.run_for_into(b, sink),
        None => planner.run_to_end_into(sink),
    };
    Ok(GraspResult::from_planner(
        &planner,
        &mut Workspace::new(hand),
    ))
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
fn search_side_by_side(
    hand: &HandModel,
    object: &ObjectModel,
    request: &GraspRequest,
    movements: &[&GraspMovement],
    sink: &mut dyn SearchSink,
) -> Vec<Result<GraspResult, SearchError>> {
    let (events, received) = std::sync::mpsc::channel();
    std::thread::scope(|scope| {
        let searches: Vec<_> = movements
            .iter()
            .enumerate()
            .map(|(k, &movement)| {
                let mut forward = Forward {
                    movement: k,
                    events: events.clone(),
                };
                scope.spawn(move || search_movement(hand, object, movement, request, &mut forward))
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
            .collect()
    })
}
