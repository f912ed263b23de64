//! One grasp request end to end, the decisions every front end shares (the CLI, the batch and
//! the Python package): which movements `auto` tries, a planner per movement, and which result
//! wins.

use std::time::Duration;

use crate::hand::HandModel;
use crate::math::Point3;
use crate::movement::GraspMovement;
use crate::object::ObjectModel;
use crate::workspace::Workspace;

use super::{GraspPlanner, GraspResult, SearchError, SearchParams, SearchSink};

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
/// movement's start and every step.
pub fn find_grasp(
    hand: &HandModel,
    object: &ObjectModel,
    request: &GraspRequest,
    sink: &mut dyn SearchSink,
) -> Result<GraspResult, SearchError> {
    let mut best: Option<GraspResult> = None;
    let mut ws = Workspace::new(hand);
    for movement in movements_to_try(hand, &request.movement)? {
        sink.movement_started(movement.name());
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
        let result = GraspResult::from_planner(&planner, &mut ws);
        if best.as_ref().is_none_or(|b| better_grasp(&result, b)) {
            best = Some(result);
        }
    }
    Ok(best.expect("movements_to_try returns at least one movement"))
}
