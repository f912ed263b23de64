//! The crate's one error type: why a simulation cannot run, or why it stopped.

use prehensile_control::DynamicsError;
use prehensile_core::search::{Invalid, SearchError};

/// Why a simulation cannot run or stopped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SimError {
    /// A setting is outside the range the engines can use.
    #[error("{setting} = {value} is outside its range [{low}, {high}]")]
    OutOfRange {
        /// The setting's name (`dt`, `friction`, `reduced.sweeps`, `alpha`, ...).
        setting: &'static str,
        /// The value given.
        value: f64,
        /// Smallest value taken.
        low: f64,
        /// Largest value taken.
        high: f64,
    },
    /// A name (engine, scenario) is not one this crate knows.
    #[error("unknown {what} '{name}'; use one of: {}", known.join(", "))]
    UnknownName {
        /// What was named.
        what: &'static str,
        /// The name given.
        name: String,
        /// The names known.
        known: &'static [&'static str],
    },
    /// A bone moves but has no mass.
    #[error("bone '{bone}' moves but has no mass; give it an inertial")]
    Massless {
        /// The bone.
        bone: String,
    },
    /// The reduced engine holds the root bone still as the palm, but it has a joint.
    #[error("hand '{hand}': the reduced engine holds the root bone '{bone}' as the palm, and it has a joint; use the rapier engine")]
    JointedRoot {
        /// The hand.
        hand: String,
        /// Its root bone.
        bone: String,
    },
    /// A start pose or controller does not match the hand's degrees of freedom.
    #[error("hand '{hand}' has {dofs} degrees of freedom; the start pose and every setpoint need {dofs} values")]
    ControllerLength {
        /// The hand.
        hand: String,
        /// Its degrees of freedom.
        dofs: usize,
    },
    /// A setpoint, limit or start angle is NaN or infinite.
    #[error(
        "hand '{hand}': a setpoint, limit or start angle is not finite (value {index} of them)"
    )]
    ControllerNotFinite {
        /// The hand.
        hand: String,
        /// Which value, counting setpoints, then the neutral pose, start pose and limits.
        index: usize,
    },
    /// More hands than a world takes.
    #[error("at most {0} hands")]
    TooManyHands(usize),
    /// A scenario was given no objects.
    #[error("give at least one object")]
    NoObjects,
    /// A grasp result does not belong to this hand.
    #[error("the result ({movement}, {angles} joint angles) is not of hand '{hand}' ({dofs} degrees of freedom, movements {})", movements.join(", "))]
    ForeignResult {
        /// The result's movement.
        movement: String,
        /// The result's joint angle count.
        angles: usize,
        /// The hand.
        hand: String,
        /// Its degrees of freedom.
        dofs: usize,
        /// Its movements.
        movements: Vec<String>,
    },
    /// The object has no convex hull (flat or degenerate).
    #[error("object '{0}' is flat or degenerate: no convex hull")]
    FlatObject(String),
    /// The grasp search found no valid grasp of the object.
    #[error("no valid {movement} grasp of '{object}' was found for hand '{hand}'{}", why.as_ref().map(|w| format!(" (the last pose tried: {w})")).unwrap_or_default())]
    NoGrasp {
        /// The movement searched.
        movement: String,
        /// The object.
        object: String,
        /// The hand.
        hand: String,
        /// Why the last pose tried was not valid.
        why: Option<Invalid>,
    },
    /// The grasp search for the scenario could not start.
    #[error(transparent)]
    Search(#[from] SearchError),
    /// The hand's dynamics or its controller could not be computed.
    #[error(transparent)]
    Dynamics(Box<DynamicsError>),
    /// The hand's mass matrix is not positive definite.
    #[error("hand '{0}': the mass matrix is not positive definite")]
    MassMatrix(String),
    /// The simulation blew up; stopped before anything non-finite was written.
    #[error("the simulation diverged at t = {time:.4} s: {what}")]
    Diverged {
        /// Seconds.
        time: f64,
        /// Which hand, bone and joint, or the object.
        what: Divergence,
    },
}

/// What ran away when a simulation diverged.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Divergence {
    /// A bone moved faster than anything a hand does, or to a non-finite place.
    #[error(
        "hand {hand}, bone '{bone}' (joint {joint}) ran away: lower the gains or the time step"
    )]
    Bone {
        /// Which hand.
        hand: usize,
        /// The bone.
        bone: String,
        /// Its first degree of freedom's name, or `fixed`.
        joint: String,
    },
    /// A bone came off its joint (rapier's joints are constraints that can give).
    #[error("hand {hand}, bone '{bone}' came {:.1} mm off its joint: lower the gains or the time step", gap * 1e3)]
    JointGap {
        /// Which hand.
        hand: usize,
        /// The bone.
        bone: String,
        /// How far, metres.
        gap: f64,
    },
    /// The object moved faster than anything a hand does, or to a non-finite place.
    #[error("the object ran away")]
    Object,
    /// A hand's dynamics could not be computed from its state.
    #[error("hand {hand}: {error}")]
    Dynamics {
        /// Which hand.
        hand: usize,
        /// What failed.
        error: Box<DynamicsError>,
    },
}

impl From<DynamicsError> for SimError {
    fn from(e: DynamicsError) -> Self {
        Self::Dynamics(Box::new(e))
    }
}
