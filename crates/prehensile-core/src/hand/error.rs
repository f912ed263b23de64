//! Why a hand cannot be built: every error names the bone, degree of freedom or movement, and
//! says how to fix it.

use super::limits::{MAX_BONES, MAX_HAND_EXTENT};

/// Why a hand description cannot become a hand model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum HandError {
    /// The hand has no bones or too many.
    #[error("the hand has {0} bones; it needs at least 3 (a root and two fingers) and at most {MAX_BONES}")]
    BoneCount(usize),
    /// Two bones share a name.
    #[error("bone '{0}' is defined twice; bone names must be unique")]
    DuplicateBone(String),
    /// A parent name refers to no bone.
    #[error("bone '{bone}' names parent '{parent}', which is not a bone of this hand; check the spelling")]
    MissingParent {
        /// The bone.
        bone: String,
        /// The parent it names.
        parent: String,
    },
    /// Zero or several bones without a parent.
    #[error("the hand must have exactly one root bone (one without a parent); found {0:?}")]
    RootCount(Vec<String>),
    /// Following parents from a bone comes back to it.
    #[error("bone '{0}' is part of a parent cycle; every chain of parents must end at the root")]
    Cycle(String),
    /// A number is NaN or infinite.
    #[error("bone '{bone}': {what} is not a finite number")]
    NonFinite {
        /// The bone.
        bone: String,
        /// Which field.
        what: &'static str,
    },
    /// A bone's length is zero.
    #[error("bone '{bone}' has length {length:e} m; its joint and its end (next joint or tip) must differ")]
    ZeroLength {
        /// The bone.
        bone: String,
        /// The measured length.
        length: f64,
    },
    /// A radius is not positive.
    #[error("bone '{bone}' has radius {radius:?}; radii must be positive metres, at most {MAX_HAND_EXTENT} m")]
    BadRadius {
        /// The bone.
        bone: String,
        /// The radius given.
        radius: f64,
    },
    /// Limits with min > max.
    #[error("bone '{bone}': limits [{min}, {max}] are not ordered; write [min, max]")]
    UnorderedLimits {
        /// The bone.
        bone: String,
        /// Lower limit, degrees.
        min: f64,
        /// Upper limit, degrees.
        max: f64,
    },
    /// A finger bone with several children.
    #[error("bone '{bone}' has {children} children; only the root may branch, fingers are chains")]
    Branching {
        /// The bone.
        bone: String,
        /// Child count.
        children: usize,
    },
    /// A finger's last bone has no tip, or a middle bone has one.
    #[error("bone '{0}' ends a finger but has no `tip`; add the fingertip position")]
    MissingTip(String),
    /// Tip on a bone that has a child.
    #[error("bone '{0}' has a `tip` but also a child; only the last bone of a finger has a tip")]
    MisplacedTip(String),
    /// Fewer than two fingers.
    #[error("the hand has {0} finger(s); a prehensile hand needs at least two (§3.1.1)")]
    TooFewFingers(usize),
    /// The flexion direction is along the bone.
    #[error("bone '{0}': `flexes_toward` is parallel to the bone; give a direction across it")]
    DegenerateFrame(String),
    /// A bone position, tip or capsule lies farther than any hand reaches.
    #[error("bone '{bone}': its {what} lies more than {MAX_HAND_EXTENT} m away; hands are metres-scale at most, so check the units (metres)")]
    TooFar {
        /// The bone.
        bone: String,
        /// `origin`, `tip`, `position` or `capsule end`.
        what: &'static str,
    },
    /// A bone names more or fewer degrees of freedom than its joint has.
    #[error("bone '{bone}' names {named} degree(s) of freedom but its joint has {joint}")]
    DofNameCount {
        /// The bone.
        bone: String,
        /// Names given.
        named: usize,
        /// The joint's degrees of freedom.
        joint: usize,
    },
    /// Two degrees of freedom share a name.
    #[error("two degrees of freedom are named '{0}'; names must be unique")]
    DuplicateDof(String),
    /// Two fingers share a name.
    #[error("two fingers are named '{0}'; set a distinct finger name on their first bones")]
    DuplicateFinger(String),
    /// A name given for a degree of freedom is none of the hand's.
    #[error("{what} names '{name}', which is no degree of freedom of this hand")]
    UnknownDof {
        /// Who names it (`the close movement`, `a coupling`).
        what: &'static str,
        /// The name.
        name: String,
    },
    /// A coupling names a bone the hand does not have.
    #[error("a coupling names bone '{0}', which does not exist")]
    CouplingBone(String),
    /// A coupling names a degree of freedom past its bone's joint.
    #[error("a coupling uses degree of freedom {index} of bone '{bone}', whose joint has {dofs}")]
    CouplingDof {
        /// The bone.
        bone: String,
        /// The index given.
        index: usize,
        /// The joint's degrees of freedom.
        dofs: usize,
    },
    /// A coupling's ratio is not finite.
    #[error("the coupling of '{0}' has a non-finite ratio")]
    CouplingRatio(String),
    /// A degree of freedom is coupled to itself.
    #[error(
        "'{0}' is coupled to itself; couple it to another degree of freedom or drop the coupling"
    )]
    SelfCoupled(String),
    /// A degree of freedom follows two leaders.
    #[error("'{0}' follows two leaders; give it one")]
    TwoLeaders(String),
    /// Couplings form a cycle.
    #[error("the couplings through '{0}' form a cycle; one degree of freedom of the cycle must lead freely")]
    CouplingCycle(String),
    /// A movement of the hand file is wrong.
    #[error("movement '{movement}': {problem}")]
    Movement {
        /// The movement.
        movement: String,
        /// What is wrong with it.
        problem: MovementProblem,
    },
}

/// What is wrong with a movement of a hand file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MovementProblem {
    /// The via pose's fraction is not strictly between 0 and 1.
    #[error("via_fraction = {0:?} is not strictly between 0 and 1")]
    ViaFraction(f64),
    /// The via pose has the wrong number of angles.
    #[error("the via pose has {got} angles, the hand {dofs} degrees of freedom")]
    ViaLength {
        /// Angles given.
        got: usize,
        /// Degrees of freedom.
        dofs: usize,
    },
    /// A pose names a bone the hand does not have.
    #[error("its {pose} pose names bone '{bone}', which does not exist")]
    UnknownBone {
        /// `start`, `end` or `via`.
        pose: &'static str,
        /// The bone.
        bone: String,
    },
    /// A pose gives a bone more or fewer angles than its joint has.
    #[error("its {pose} pose gives {got} angle(s) for bone '{bone}', whose joint has {joint}")]
    AngleCount {
        /// `start`, `end` or `via`.
        pose: &'static str,
        /// The bone.
        bone: String,
        /// Angles given.
        got: usize,
        /// The joint's degrees of freedom.
        joint: usize,
    },
    /// A pose's angle is outside its joint's limits.
    #[error("its {pose} pose: bone '{bone}' angle {index} = {degrees:?}° is outside its limits [{low:.1}°, {high:.1}°]")]
    OutsideLimits {
        /// `start`, `end` or `via`.
        pose: &'static str,
        /// The bone.
        bone: String,
        /// Which of its angles.
        index: usize,
        /// The angle given, degrees.
        degrees: f64,
        /// The lower limit, degrees.
        low: f64,
        /// The upper limit, degrees.
        high: f64,
    },
    /// A finger name is not one of the hand's.
    #[error("names finger '{finger}'; the hand's fingers are {fingers:?}")]
    UnknownFinger {
        /// The name given.
        finger: String,
        /// The hand's fingers.
        fingers: Vec<String>,
    },
    /// The grasp center is not finite.
    #[error("grasp_center is not finite")]
    GraspCenterNotFinite,
    /// Both a grasp center and fingers to put it between.
    #[error("give either grasp_center or grasp_center_between, not both")]
    GraspCenterTwice,
}
