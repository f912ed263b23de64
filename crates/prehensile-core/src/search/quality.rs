//! Quality of a grasp pose (§5.5, Alg. 6–7): weighted distances, every term reported, and whether
//! the pose is a valid grasp.

use crate::collision::Capsule;
use crate::finger_closing::{close_fingers_while, ClosingParams};
use crate::hand::movement::GraspMovement;
use crate::hand::{Finger, HandModel};
use crate::math::{Point3, Rotation, Transform};
use crate::object::ObjectModel;
use crate::parameter::{ParameterError, WeightsProblem};
use crate::stability::{
    find_contacts, narrowest_normal_cap, opposition_angle, pad_normal, ContactModel, Stability,
};
use crate::workspace::Workspace;

use super::translate_to_free::{hand_root, translate_to_free, TranslateMode};
use super::wrist_range::WristRange;

/// Distance within which a capsule counts as touching, and depth beyond which it penetrates.
pub const CONTACT_TOLERANCE: f64 = 0.001;
/// How much a quality bound is loosened against rounding before it stops an evaluation
/// ([`EvaluationContext::evaluate_pose_to_beat`]); qualities are sums of a few metres.
const BOUND_MARGIN: f64 = 1e-9;

/// Smallest angle between the thumb's and the index's pad normals in a precision grasp (120°).
pub const OPPOSITION_ANGLE: f64 = 2.0 * std::f64::consts::FRAC_PI_3;

/// The narrowest cone of contact normals a grasp may have at the default friction μ = 0.5 (78°);
/// see [`one_sided_cap`]. Of 77 Shadow-hand power grasps replayed in MuJoCo (the file's own
/// solver, friction 1), the 38 with a narrower cone held 1 in at least 5 of 6 load directions,
/// the 39 others 12; at friction 0.5 with MuJoCo's anti-slip settings, searched with the rule,
/// 62% held against 37% without it (docs/QUALITY.md).
pub const ONE_SIDED_CAP: f64 = 78.0 * std::f64::consts::PI / 180.0;

/// The narrowest cone of contact normals a grasp may have with friction `friction`, radians:
/// [`ONE_SIDED_CAP`] at μ = 0.5, moved by how far atan μ moves from atan 0.5 (59.6° at μ = 1),
/// and at most 90°.
///
/// Each contact force lies within atan μ of its normal. If the normals fit in a cone of
/// half-angle θ, every force fits in θ + atan μ, and below 90° all forces push into one open
/// half-space: no squeeze can balance, it pushes the object out and only friction's reserve holds
/// it. So the threshold falls as friction grows, one for one with atan μ; the 14.6° it keeps
/// above that bare bound is the reserve measured at μ = 0.5. At 90° the normals fit in no open
/// hemisphere, the most this test can ask.
pub fn one_sided_cap(friction: f64) -> f64 {
    let cap = ONE_SIDED_CAP + 0.5f64.atan() - friction.max(0.0).atan();
    cap.min(std::f64::consts::FRAC_PI_2)
}

/// Default weight of the stability term; see [`QualityWeights::stability`]. Zero for now: with
/// weight 2 or more the search moved the ball-jointed robot3's sphere grasp to one with a larger
/// ε and a larger load ratio against gravity that the rapier simulation nonetheless drops, so the
/// term's benefit is not shown; force closure gates validity whatever the weight.
pub const STABILITY_WEIGHT: f64 = 0.0;

/// Which grasps count as valid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ValidityRule {
    /// The default: the grasp must hold. No penetration, the thesis's finger counts, force
    /// closure with the contact model's friction, contacts that push from more than one side
    /// (their normals not all within [`one_sided_cap`] of one direction, 78° at μ = 0.5), and
    /// for a movement with contact fingers the first two (thumb and index) pads opposed by at
    /// least [`OPPOSITION_ANGLE`]. The search ranks a wrap that pushes from every side above a
    /// valid one-sided one ([`EvaluationContext::pushes_from_every_side`]) and walks as under
    /// [`ValidityRule::Strict`] ([`EvaluationContext::walk_rank`]), so a one-sided grasp is
    /// returned only when none other is found.
    #[default]
    Holds,
    /// The thesis's rules only (§6.4.1): no penetration and enough fingers touching.
    Thesis,
    /// [`ValidityRule::Holds`], and a grasp without contact fingers (a power grasp, `close`: a
    /// wrap) has its contact normals in no open half-space, however much friction could hold it:
    /// no grasp with all its contact normals on one side. A pinch (a movement with
    /// contact fingers) keeps the friction-aware test: two pads 150° apart share an open
    /// half-space, and their opposition is the pinch's own test of sides. It refuses grasps
    /// that hold, such as a three-fingered claw whose tips meet a ball 3–5° above its equator,
    /// so it is not the default (docs/QUALITY.md).
    Strict,
}

impl ValidityRule {
    /// Every rule, by [`ValidityRule::name`].
    pub const ALL: [ValidityRule; 3] = [Self::Holds, Self::Strict, Self::Thesis];
    /// Every rule's name, in the order of [`ValidityRule::ALL`].
    pub const NAMES: [&'static str; 3] = ["holds", "strict", "thesis"];

    /// Does the rule judge a pose's contacts (force closure, sides, opposition)?
    pub fn judges_contacts(self) -> bool {
        self != ValidityRule::Thesis
    }

    /// The rule's name in options and files: `holds`, `strict` or `thesis`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Holds => "holds",
            Self::Strict => "strict",
            Self::Thesis => "thesis",
        }
    }

    /// The narrowest cone of contact normals (half-angle, radians) the rule accepts at
    /// `friction` for a wrap or, with `pinch`, for a movement with contact fingers; `None` for
    /// the thesis's rule, which does not look at normals.
    pub fn needed_normal_cap(self, friction: f64, pinch: bool) -> Option<f64> {
        match self {
            // No open half-space: the widest cap [`one_sided_cap`] asks for, at any friction.
            Self::Strict if !pinch => Some(std::f64::consts::FRAC_PI_2),
            Self::Strict | Self::Holds => Some(one_sided_cap(friction)),
            Self::Thesis => None,
        }
    }
}

impl std::fmt::Display for ValidityRule {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for ValidityRule {
    type Err = ParameterError;

    /// Parses [`ValidityRule::name`]; the error lists the names.
    fn from_str(s: &str) -> Result<Self, ParameterError> {
        Self::ALL
            .into_iter()
            .find(|r| r.name() == s)
            .ok_or_else(|| ParameterError::UnknownName {
                what: "validity rule",
                name: s.to_string(),
                known: &Self::NAMES,
            })
    }
}

/// Weights of the quality's terms: quality = −(g·gDist + f·fDist + t·tDist* + w·wDist) + s·m·L,
/// with m the force-closure margin and L the object's size.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct QualityWeights {
    /// Weight of gDist, the grasp center–hook distance (k1, w1).
    pub gdist: f64,
    /// Weight of fDist, the first-contact phalanges–hook distances (k2).
    pub fdist: f64,
    /// Weight of tDist*, the contact fingers' tips–hook distances (w2).
    pub tdist: f64,
    /// Weight of wDist, the wrist–shoulder distance (k3, w3).
    pub wdist: f64,
    /// Weight of the stability term m·L (the force-closure margin of
    /// [`crate::stability::force_closure`] times the object's size, so that it is in metres like
    /// the others); beyond the thesis, 0 under its validity rule.
    #[serde(default)]
    pub stability: f64,
}

impl QualityWeights {
    /// Eq. 5.1 with Alg. 6's weights: k1 = 5, k2 = 1, k3 = 1.
    pub fn power() -> Self {
        Self {
            gdist: 5.0,
            fdist: 1.0,
            tdist: 0.0,
            wdist: 1.0,
            stability: STABILITY_WEIGHT,
        }
    }

    /// Eq. 5.2; the thesis does not print its weights, so w1 = 5, w2 = 1, w3 = 1 as for power.
    pub fn precision() -> Self {
        Self {
            gdist: 5.0,
            fdist: 0.0,
            tdist: 1.0,
            wdist: 1.0,
            stability: STABILITY_WEIGHT,
        }
    }

    /// Eq. 5.2 for movements that name contact fingers, Eq. 5.1 otherwise.
    pub fn for_movement(movement: &GraspMovement) -> Self {
        if movement.contact_fingers().is_empty() {
            Self::power()
        } else {
            Self::precision()
        }
    }

    /// The weights from four (G, F, T, W; S is [`STABILITY_WEIGHT`]) or five (G, F, T, W, S)
    /// numbers, each finite and not negative, not all zero.
    pub fn from_slice(weights: &[f64]) -> Result<Self, ParameterError> {
        let problem = |problem| ParameterError::Weights {
            weights: weights.to_vec(),
            problem,
        };
        let w = match *weights {
            [g, f, t, w] => [g, f, t, w, STABILITY_WEIGHT],
            [g, f, t, w, s] => [g, f, t, w, s],
            _ => return Err(problem(WeightsProblem::Count)),
        };
        let weights = Self {
            gdist: w[0],
            fdist: w[1],
            tdist: w[2],
            wdist: w[3],
            stability: w[4],
        };
        weights.check().map(|()| weights)
    }

    /// All weights finite and not negative, and not all zero.
    pub fn check(&self) -> Result<(), ParameterError> {
        let w = [
            self.gdist,
            self.fdist,
            self.tdist,
            self.wdist,
            self.stability,
        ];
        let problem = |problem| {
            Err(ParameterError::Weights {
                weights: w.to_vec(),
                problem,
            })
        };
        if !w.iter().all(|w| w.is_finite() && *w >= 0.0) {
            return problem(WeightsProblem::Negative);
        }
        if w.iter().all(|w| *w == 0.0) {
            return problem(WeightsProblem::AllZero);
        }
        Ok(())
    }
}

/// Every term of the quality, in metres (§5.5.1).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct QualityTerms {
    /// Grasp center–hook distance.
    pub gdist: f64,
    /// Sum over fingers of the distance from the end of the first-contact bone to the hook.
    pub fdist: f64,
    /// Sum over all fingers of the tip–hook distance.
    pub tdist: f64,
    /// Sum over the movement's contact fingers of the tip–hook distance (tDist*).
    pub tdist_contact: f64,
    /// Wrist–shoulder distance.
    pub wdist: f64,
    /// Mean interpolation reached by the moving bones.
    pub mean_reached: f64,
    /// m·L, the stability term in metres: the force-closure margin times the object's size (0
    /// when not computed or not in force closure).
    pub stability: f64,
}

/// Why a pose is not a valid grasp.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum Invalid {
    /// The search has not evaluated a pose yet (it is still sampling its start).
    NotEvaluated,
    /// The hook rotation is outside the wrist range (§6.5.4).
    OutsideWristRange,
    /// The hand could not be backed off free of the object.
    NotFreed {
        /// How far it was backed off, metres.
        max_offset: f64,
    },
    /// A capsule enters the object by more than [`CONTACT_TOLERANCE`].
    Penetrates {
        /// The bone.
        bone: String,
    },
    /// Too few fingers touch the object.
    TooFewFingers {
        /// Fingers touching.
        touching: usize,
        /// Fingers required.
        required: usize,
    },
    /// A finger the movement needs does not touch.
    MissingContact {
        /// The finger.
        finger: String,
    },
    /// The contacts cannot resist every wrench with the contact model's friction.
    NoForceClosure {
        /// Contacts found.
        contacts: usize,
    },
    /// Every contact pushes the object roughly the same way: a squeeze would push it out.
    OneSided {
        /// Half-angle of the narrowest cone holding every contact normal, degrees.
        cap_degrees: f64,
        /// The half-angle the rule asks for at the search's friction, degrees:
        /// [`ValidityRule::needed_normal_cap`].
        needed_degrees: f64,
        /// Would [`ValidityRule::Holds`] accept the cone at this friction (friction holds the
        /// grasp on paper)?
        holds_accepts: bool,
    },
    /// The thumb's and the index's pads do not push against each other.
    NoOpposition {
        /// Angle between their pad normals, degrees.
        angle_degrees: f64,
    },
    /// Not evaluated to the end: its back-off already bounded its quality below the pose it
    /// had to beat ([`EvaluationContext::evaluate_pose_to_beat`]).
    Outranked,
}

impl std::fmt::Display for Invalid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Invalid::NotEvaluated => write!(f, "the search has not evaluated a pose yet"),
            Invalid::Outranked => write!(
                f,
                "its quality could not beat the search's current pose (evaluation stopped early)"
            ),
            Invalid::OutsideWristRange => write!(f, "the hand would leave the wrist's range"),
            Invalid::NotFreed { max_offset } => {
                write!(
                    f,
                    "the hand still touches the object after backing off {max_offset:.3} m"
                )
            }
            Invalid::Penetrates { bone } => {
                write!(f, "bone '{bone}' enters the object by more than 1 mm")
            }
            Invalid::TooFewFingers { touching, required } => {
                write!(
                    f,
                    "{touching} finger(s) touch the object, {required} needed"
                )
            }
            Invalid::MissingContact { finger } => {
                write!(f, "the {finger} does not touch the object")
            }
            Invalid::NoForceClosure { contacts } => write!(
                f,
                "not in force closure: its {contacts} contact(s) cannot resist every push and twist with this friction"
            ),
            Invalid::OneSided {
                cap_degrees,
                needed_degrees,
                holds_accepts,
            } => {
                write!(
                    f,
                    "every contact pushes the object one way (all normals within {cap_degrees:.0}° of \
                     one direction, {needed_degrees:.0}° needed at this friction): a squeeze would \
                     push it out of the hand"
                )?;
                if *holds_accepts {
                    write!(
                        f,
                        "; friction could hold it, and the `holds` validity rule accepts it"
                    )?;
                }
                Ok(())
            }
            Invalid::NoOpposition { angle_degrees } => write!(
                f,
                "the thumb and index pads are {angle_degrees:.0}° apart, {:.0}° needed to pinch",
                OPPOSITION_ANGLE.to_degrees()
            ),
        }
    }
}

/// The evaluation of one hook rotation.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// The hook rotation evaluated.
    pub rotation: Rotation,
    /// Quality (higher is better); −∞ outside the wrist range or when the hand cannot be freed.
    pub quality: f64,
    /// The terms.
    pub terms: QualityTerms,
    /// How far the grasp center was backed off the hook, metres.
    pub offset: f64,
    /// Fingers touching the object.
    pub fingers_touching: usize,
    /// `Ok` for a valid grasp.
    pub validity: Result<(), Invalid>,
    /// Force-closure margin of the pose's contacts, computed for poses that pass the other
    /// checks under [`ValidityRule::Holds`].
    pub closure_margin: Option<f64>,
    /// Half-angle (radians) of the narrowest cone holding every contact normal, π/2 when they
    /// push from every side ([`narrowest_normal_cap`]); computed with `closure_margin`.
    pub normal_cap: Option<f64>,
}

/// What an evaluation needs besides the rotation.
#[derive(Debug, Clone, Copy)]
pub struct EvaluationContext<'a> {
    /// The hand.
    pub hand: &'a HandModel,
    /// The object.
    pub object: &'a ObjectModel,
    /// The grasp movement.
    pub movement: &'a GraspMovement,
    /// The hook point, world.
    pub hook: Point3,
    /// How deep the hook lies inside the object, metres ([`hook_depth`]): what the fDist floor
    /// of every valid pose from this hook comes from ([`finger_fdist_floor`]), computed once per
    /// hook for the step's bound ([`EvaluationContext::evaluate_pose_to_beat`]). Kept with
    /// `hook` by [`EvaluationContext::set_hook`].
    pub hook_depth: f64,
    /// How much nearer the palm than the movement's grasp center the hand hangs from the hook,
    /// metres: 0, or in a search's second hang more (nearer) or less (farther out)
    /// ([`crate::search::GraspPlanner`]).
    pub hang_shift: f64,
    /// The character's shoulder, world.
    pub shoulder: Point3,
    /// Hook rotation of the starting position.
    pub start: Rotation,
    /// Wrist range relative to `start`.
    pub wrist_range: WristRange,
    /// Quality weights.
    pub weights: QualityWeights,
    /// TranslateToFree mode.
    pub translate: TranslateMode,
    /// Furthest the hand may back off, metres.
    pub max_offset: f64,
    /// Finger closing parameters.
    pub closing: ClosingParams,
    /// Fingers that must touch for a movement without named contact fingers.
    pub min_fingers: usize,
    /// Which grasps are valid.
    pub validity: ValidityRule,
    /// How contacts resist forces.
    pub contact_model: ContactModel,
    /// The object's size `L` that torques are divided by: the largest distance of a vertex from
    /// the centre of mass, metres.
    pub torque_scale: f64,
}

/// How deep `hook` lies inside the object, metres: its distance to the surface when inside, 0
/// outside, and 0 where the inside comes from winding numbers (an open mesh's inside also ends
/// across its holes, away from any triangle, so the surface does not bound the way out).
pub fn hook_depth(object: &ObjectModel, hook: &Point3) -> f64 {
    let exact = object.collider().exact();
    if exact.uses_winding_numbers() {
        return 0.0;
    }
    // NaN (no answer) counts as outside: `max` keeps the 0.
    (-exact.signed_distance(hook)).max(0.0)
}

/// A lower bound on the fDist of every valid pose of `hand` hung from `hook`, metres. Each
/// finger adds the distance of its first-contact point (Alg. 7) from the hook: the end of the
/// last capsule of the finger's last bone among those that reached the fewest interpolations.
/// That bone has capsules when the finger's last bone has: a bone stops with a touching bone
/// after it or at the end, and ties go to the later bone (only a rigid coupling's follower
/// takes another bone's count, so it must have capsules too). In a valid pose the point is
/// outside the object and at least the capsule's radius less [`CONTACT_TOLERANCE`] from the
/// surface, so the way to it from a hook that deep inside the object crosses the surface and is at
/// least their sum long. A finger that finger closing may leave unchecked
/// ([`crate::hand::closing_facts::closes_checked`]) adds nothing. Tested against the fDist of valid
/// poses (`the_fdist_floor_bounds_every_valid_pose`).
pub fn fdist_floor(hand: &HandModel, object: &ObjectModel, hook: &Point3) -> f64 {
    fdist_floor_at(hand, hook_depth(object, hook))
}

/// [`fdist_floor`] for a hook `depth` metres inside the object.
fn fdist_floor_at(hand: &HandModel, depth: f64) -> f64 {
    (0..hand.fingers().len())
        .map(|f| finger_fdist_floor(hand, f, depth))
        .sum()
}

/// What finger `finger` adds to [`fdist_floor`] for a hook `depth` metres inside the object
/// ([`hook_depth`]): each finger's term of a valid pose is at least this on its own, so a
/// finger once closed may replace its floor by its term.
pub fn finger_fdist_floor(hand: &HandModel, finger: usize, depth: f64) -> f64 {
    match hand.finger_floor_radius(finger) {
        Some(radius) if depth > 0.0 => (depth + radius - CONTACT_TOLERANCE).max(0.0),
        _ => 0.0,
    }
}

impl EvaluationContext<'_> {
    /// Moves the hook to `hook` (world), with its depth.
    pub fn set_hook(&mut self, hook: Point3) {
        self.hook = hook;
        self.hook_depth = hook_depth(self.object, &hook);
    }

    /// Where the wrist is with the hand hung from `hook` backed off `offset`, as finger
    /// closing places it.
    fn wrist(&self, hook: &Transform, offset: f64) -> Point3 {
        let root = hand_root(hook, self.movement, offset);
        let palm = &self.hand.bones()[0];
        let local = palm.rest
            * Transform::from_parts(Default::default(), self.movement.rotation_at(0, 0.0));
        (root * local).translation.vector.into()
    }

    /// Hook transform for a rotation: at the hook, moved [`EvaluationContext::hang_shift`]
    /// along its +y (toward the palm, which faces +y) so that the hand hangs that much nearer
    /// its palm. An evaluation's `offset` is measured from here; a result reports it less the
    /// shift, from the hook itself.
    pub fn hook_frame(&self, rotation: &Rotation) -> Transform {
        Transform::from_parts(self.hook.coords.into(), *rotation)
            * Transform::translation(0.0, self.hang_shift, 0.0)
    }

    /// Places the hand for `rotation` (TranslateToFree, then finger closing) and evaluates it.
    /// The pose stays in `ws`.
    pub fn evaluate(&self, rotation: &Rotation, ws: &mut Workspace) -> Evaluation {
        let mut eval = self.evaluate_pose(rotation, ws);
        if self.stability_pending(&eval) {
            self.judge_stability(&mut eval, ws);
        }
        eval
    }

    /// [`EvaluationContext::evaluate`] but for the stability of its contacts: under
    /// [`ValidityRule::Holds`] a pose that passes every other check is left `Ok` with no
    /// `closure_margin` ([`EvaluationContext::stability_pending`]), for
    /// [`EvaluationContext::judge_stability`] to finish from its world capsules. Its quality is
    /// final when the stability weight is 0.
    pub fn evaluate_pose(&self, rotation: &Rotation, ws: &mut Workspace) -> Evaluation {
        self.evaluate_pose_to_beat(rotation, ws, f64::NEG_INFINITY)
    }

    /// [`EvaluationContext::evaluate_pose`] for a pose that counts only with a quality above
    /// `bar` (a search's step, whose current and best poses are valid and rank first). Beyond
    /// the thesis, a bound stops it early, as [`Invalid::Outranked`] with quality −∞, once its
    /// quality cannot exceed `bar`: the quality is at most −(g·gDist + w·wDist + f·fDist
    /// floor) ([`fdist_floor`]; tDist* ≥ 0), known after TranslateToFree, and
    /// since backing off by δ moves the wrist by δ, TranslateToFree gives up at the back-off
    /// where even that bound falls to `bar`. Finger closing, most of an evaluation, is skipped
    /// for every pose that could not have changed the search. Where the fingers close one after
    /// another ([`crate::hand::closing_facts::fingers_close_apart`]), each finger that has closed
    /// swaps its floor ([`finger_fdist_floor`]) for its own fDist term (and a contact finger
    /// adds its tDist term), and the pose stops as soon as the bound falls below `bar`. Only when
    /// the stability term's weight is 0 and the others are not negative; else, as for `bar` =
    /// −∞, the whole pose is evaluated.
    pub fn evaluate_pose_to_beat(
        &self,
        rotation: &Rotation,
        ws: &mut Workspace,
        bar: f64,
    ) -> Evaluation {
        let mut eval = Evaluation {
            rotation: *rotation,
            quality: f64::NEG_INFINITY,
            terms: QualityTerms::default(),
            offset: 0.0,
            fingers_touching: 0,
            validity: Ok(()),
            closure_margin: None,
            normal_cap: None,
        };
        if !self.wrist_range.contains(&self.start, rotation) {
            eval.validity = Err(Invalid::OutsideWristRange);
            return eval;
        }
        let hook = self.hook_frame(rotation);
        let w = &self.weights;
        let bounded = bar > f64::NEG_INFINITY
            && w.stability == 0.0
            && [w.gdist, w.fdist, w.tdist, w.wdist]
                .iter()
                .all(|&k| k >= 0.0);
        // The quality bound less the back-off's and the wrist's terms, loosened by a margin so
        // that rounding never prunes a pose whose quality is `bar` to the last bits.
        let rest = if bounded {
            BOUND_MARGIN - w.fdist * fdist_floor_at(self.hand, self.hook_depth)
        } else {
            f64::INFINITY
        };
        let give_up_at = if bounded && w.gdist > w.wdist {
            let wrist = (self.wrist(&hook, 0.0) - self.shoulder).norm();
            (rest - w.wdist * wrist - bar) / (w.gdist - w.wdist) + BOUND_MARGIN
        } else {
            f64::INFINITY
        };
        let Some(offset) = translate_to_free(
            self.hand,
            self.object,
            self.movement,
            &hook,
            self.translate,
            self.max_offset,
            give_up_at,
            ws,
        ) else {
            eval.validity = Err(if give_up_at < f64::INFINITY {
                Invalid::Outranked
            } else {
                Invalid::NotFreed {
                    max_offset: self.max_offset,
                }
            });
            return eval;
        };
        // The bound once the hand is placed; each finger that closes then swaps its floor for
        // its own fDist term (and, for a contact finger, adds its tDist term).
        let mut bound = f64::INFINITY;
        if bounded {
            let wrist = (self.wrist(&hook, offset) - self.shoulder).norm();
            bound = rest - w.gdist * offset - w.wdist * wrist;
            if bound < bar {
                eval.validity = Err(Invalid::Outranked);
                return eval;
            }
        }
        eval.offset = offset;
        let root = hand_root(&hook, self.movement, offset);
        let contact = self.movement.contact_fingers();
        let mut still_beats_the_bar = |f: usize, ws: &Workspace| {
            if bounded {
                let finger = &self.hand.fingers()[f];
                bound -= w.fdist
                    * (self.finger_fdist(finger, ws)
                        - finger_fdist_floor(self.hand, f, self.hook_depth));
                if contact.contains(&f) {
                    bound -= w.tdist * self.tip_distance(finger, ws);
                }
            }
            bound >= bar
        };
        let Some(outcome) = close_fingers_while(
            self.hand,
            self.object,
            self.movement,
            &root,
            &self.closing,
            ws,
            &mut still_beats_the_bar,
        ) else {
            eval.validity = Err(Invalid::Outranked);
            return eval;
        };
        eval.terms = self.terms(offset, ws);
        eval.fingers_touching = self
            .hand
            .fingers()
            .iter()
            .filter(|f| f.bones.iter().any(|&b| ws.touching[b]))
            .count();
        eval.validity = self.validity(outcome.started_in_collision, eval.fingers_touching, ws);
        eval.quality = self.quality(&eval.terms);
        eval
    }

    /// Is `eval` (from [`EvaluationContext::evaluate_pose`]) valid but for the stability of its
    /// contacts, which is not judged yet?
    pub fn stability_pending(&self, eval: &Evaluation) -> bool {
        self.validity.judges_contacts() && eval.validity.is_ok() && eval.closure_margin.is_none()
    }

    /// Does the pose rank among the grasps that push from every side? Under
    /// [`ValidityRule::Holds`] a wrap (a movement without contact fingers) whose contact normals
    /// all lie in one open half-space is valid — friction holds it on paper — but ranks below
    /// every valid wrap that pushes from every side, whatever their qualities, and the search
    /// walks past it as if it were invalid ([`EvaluationContext::walk_rank`]): it returns the
    /// one-sided grasp only when it finds none that pushes from every side
    /// (docs/decisions/004-one-sided-patience.md). Every other pose ranks by validity and quality alone.
    pub fn pushes_from_every_side(&self, eval: &Evaluation) -> bool {
        self.validity != ValidityRule::Holds
            || !self.movement.contact_fingers().is_empty()
            || eval
                .normal_cap
                .is_none_or(|cap| cap >= std::f64::consts::FRAC_PI_2)
    }

    /// Do the contacts in `ws.contacts` push from every side (their normals in no open
    /// half-space)? What [`EvaluationContext::pushes_from_every_side`] asks of a valid wrap, from
    /// its contacts alone, before its force closure is judged.
    pub fn contacts_push_from_every_side(&self, ws: &Workspace) -> bool {
        narrowest_normal_cap(ws.contacts.iter().map(|c| c.normal)) >= std::f64::consts::FRAC_PI_2
    }

    /// The order of the best poses (higher is better): valid before invalid, among valid
    /// ones [`EvaluationContext::pushes_from_every_side`] first, then quality (invalid poses
    /// by quality alone). The current pose moves by [`EvaluationContext::walk_rank`].
    pub fn rank(&self, eval: &Evaluation) -> (bool, bool, f64) {
        let valid = eval.validity.is_ok();
        (
            valid,
            valid && self.pushes_from_every_side(eval),
            eval.quality,
        )
    }

    /// The order the search moves its current pose by (higher is better): valid grasps that
    /// [push from every side](EvaluationContext::pushes_from_every_side) before every other
    /// pose, then quality. A one-sided wrap ranks among the invalid poses here, so the search
    /// walks as [`ValidityRule::Strict`]'s does and is not caught in the one-sided grasps around
    /// it; the best valid pose, by [`EvaluationContext::rank`], keeps it as the grasp returned
    /// when none that pushes from every side turns up.
    pub fn walk_rank(&self, eval: &Evaluation) -> (bool, f64) {
        (
            eval.validity.is_ok() && self.pushes_from_every_side(eval),
            eval.quality,
        )
    }

    /// Does a pose's quality leave out its stability (weight 0), so that a search may judge the
    /// stability of only the poses whose validity could change what it does?
    pub fn quality_ignores_stability(&self) -> bool {
        self.weights.stability == 0.0
    }

    /// Finishes a pose [`EvaluationContext::stability_pending`] whose world capsules are in
    /// `ws.capsules`: its contacts, force-closure margin, the rules that need contacts, and its
    /// quality with the stability term.
    pub fn judge_stability(&self, eval: &mut Evaluation, ws: &mut Workspace) {
        self.find_contacts(ws);
        self.judge_found_contacts(eval, ws);
    }

    /// [`EvaluationContext::judge_stability`] once the pose's contacts are in `ws.contacts`.
    pub fn judge_found_contacts(&self, eval: &mut Evaluation, ws: &mut Workspace) {
        ws.counters.stability_tests += 1;
        let margin = ws.wrench_space.closure_margin(
            &ws.contacts,
            &self.contact_model,
            &self.object.center_of_mass(),
            self.torque_scale,
        );
        eval.terms.stability = margin * self.torque_scale;
        let cap = narrowest_normal_cap(ws.contacts.iter().map(|c| c.normal));
        eval.validity = self.holds(margin, cap, ws);
        eval.closure_margin = Some(margin);
        eval.normal_cap = Some(cap);
        eval.quality = self.quality(&eval.terms);
    }

    /// The weighted sum of the quality terms (Eq. 5.1–5.2, and the stability term).
    fn quality(&self, t: &QualityTerms) -> f64 {
        let w = &self.weights;
        -(w.gdist * t.gdist + w.fdist * t.fdist + w.tdist * t.tdist_contact + w.wdist * t.wdist)
            + w.stability * t.stability
    }

    /// Finds the contacts of the pose in `ws` (into `ws.contacts`).
    pub fn find_contacts(&self, ws: &mut Workspace) {
        find_contacts(
            self.hand,
            self.object,
            &ws.capsules,
            CONTACT_TOLERANCE,
            &mut ws.contacts,
        );
    }

    /// Finds the contacts of the pose in `ws` and their stability (force closure, ε, loads).
    pub fn stability(&self, ws: &mut Workspace) -> Stability {
        self.find_contacts(ws);
        self.stability_of_found_contacts(ws)
    }

    /// [`EvaluationContext::stability`] once the pose's contacts are in `ws.contacts`.
    pub fn stability_of_found_contacts(&self, ws: &mut Workspace) -> Stability {
        ws.wrench_space.evaluate(
            &ws.contacts,
            &self.contact_model,
            &self.object.center_of_mass(),
            self.torque_scale,
        )
    }

    /// Finds the contacts of the pose in `ws` and their Ferrari–Canny ε alone
    /// ([`GraspWrenchSpace::epsilon`](crate::stability::GraspWrenchSpace::epsilon)): what
    /// [`EvaluationContext::stability`] gives as `epsilon`, for less.
    pub fn epsilon(&self, ws: &mut Workspace) -> f64 {
        self.find_contacts(ws);
        ws.wrench_space.epsilon(
            &ws.contacts,
            &self.contact_model,
            &self.object.center_of_mass(),
            self.torque_scale,
        )
    }

    /// Force closure, pushes from more than one side, and for a movement with contact fingers
    /// the opposition of the first two.
    fn holds(&self, closure_margin: f64, cap: f64, ws: &Workspace) -> Result<(), Invalid> {
        if closure_margin <= 0.0 {
            return Err(Invalid::NoForceClosure {
                contacts: ws.contacts.len(),
            });
        }
        let friction = self.contact_model.friction;
        let pinch = !self.movement.contact_fingers().is_empty();
        // The thesis's rule asks nothing of the normals (it never gets here).
        let needed = self
            .validity
            .needed_normal_cap(friction, pinch)
            .unwrap_or(0.0);
        if cap < needed {
            return Err(Invalid::OneSided {
                cap_degrees: cap.to_degrees(),
                needed_degrees: needed.to_degrees(),
                holds_accepts: cap >= one_sided_cap(friction),
            });
        }
        if let [thumb, index, ..] = *self.movement.contact_fingers() {
            let pads = (
                pad_normal(self.hand, thumb, &ws.contacts),
                pad_normal(self.hand, index, &ws.contacts),
            );
            let angle = match pads {
                (Some(a), Some(b)) => opposition_angle(&a, &b),
                _ => 0.0,
            };
            if angle < OPPOSITION_ANGLE {
                return Err(Invalid::NoOpposition {
                    angle_degrees: angle.to_degrees(),
                });
            }
        }
        Ok(())
    }

    fn terms(&self, offset: f64, ws: &Workspace) -> QualityTerms {
        let hand = self.hand;
        let mut terms = QualityTerms {
            gdist: offset,
            wdist: (ws.world[0].translation.vector - self.shoulder.coords).norm(),
            ..Default::default()
        };
        let contact = self.movement.contact_fingers();
        for (fi, finger) in hand.fingers().iter().enumerate() {
            let tip_distance = self.tip_distance(finger, ws);
            terms.tdist += tip_distance;
            if contact.contains(&fi) {
                terms.tdist_contact += tip_distance;
            }
            terms.fdist += self.finger_fdist(finger, ws);
        }
        let moving = hand.bones().len().saturating_sub(1).max(1);
        terms.mean_reached =
            ws.reached.iter().skip(1).map(|&r| r as f64).sum::<f64>() / moving as f64;
        terms
    }

    /// The distance of `finger`'s tip from the hook in the pose in `ws` (its tDist term).
    fn tip_distance(&self, finger: &Finger, ws: &Workspace) -> f64 {
        let last = *finger.bones.last().expect("fingers have bones");
        (ws.world[last] * finger.tip - self.hook).norm()
    }

    /// `finger`'s fDist term in the pose in `ws`, metres. Alg. 7: the first-contact bone is the
    /// last of those that reached the fewest interpolations; its end point is the end of its
    /// capsule.
    pub fn finger_fdist(&self, finger: &Finger, ws: &Workspace) -> f64 {
        let fewest = finger
            .bones
            .iter()
            .map(|&b| ws.reached[b])
            .min()
            .unwrap_or(0);
        let first_contact = *finger
            .bones
            .iter()
            .rev()
            .find(|&&b| ws.reached[b] == fewest)
            .expect("the minimum is reached by some bone");
        let end = self
            .hand
            .bone_capsules(first_contact)
            .last()
            .map_or(ws.world[first_contact].translation.vector.into(), |c| {
                ws.world[first_contact] * c.b
            });
        (end - self.hook).norm()
    }

    fn validity(
        &self,
        started_in_collision: bool,
        touching: usize,
        ws: &mut Workspace,
    ) -> Result<(), Invalid> {
        let hand = self.hand;
        if started_in_collision
            || self
                .closing
                .contact_tolerance
                .is_none_or(|t| t > CONTACT_TOLERANCE)
        {
            // Without contact refinement bones may stop inside the object: check every capsule.
            for c in hand.capsules() {
                let w = ws.world[c.bone];
                let shrunk = Capsule {
                    a: w * c.a,
                    b: w * c.b,
                    radius: c.radius - CONTACT_TOLERANCE,
                };
                if shrunk.radius > 0.0 && self.object.capsule_touches(&shrunk, &mut ws.counters) {
                    return Err(Invalid::Penetrates {
                        bone: hand.bones()[c.bone].name.clone(),
                    });
                }
            }
        }
        let contact = self.movement.contact_fingers();
        if contact.is_empty() {
            let required = self.min_fingers.min(hand.fingers().len());
            if touching < required {
                return Err(Invalid::TooFewFingers { touching, required });
            }
        }
        for &fi in contact {
            let finger = &hand.fingers()[fi];
            if !finger.bones.iter().any(|&b| ws.touching[b]) {
                return Err(Invalid::MissingContact {
                    finger: finger.name.clone(),
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_one_sided_threshold_follows_friction() {
        let degrees = |mu: f64| one_sided_cap(mu).to_degrees();
        assert!((degrees(0.5) - 78.0).abs() < 1e-12);
        // 78° − (45° − 26.565°) at μ = 1.
        assert!((degrees(1.0) - 59.565).abs() < 1e-3, "{}", degrees(1.0));
        // Slippery contacts ask for normals in no open hemisphere, and no more.
        assert_eq!(degrees(0.1), 90.0);
        assert_eq!(degrees(0.0), 90.0);
        let mut last = 90.0;
        for k in 1..=40 {
            let d = degrees(k as f64 * 0.1);
            assert!(d <= last, "μ = {}: {d}° after {last}°", k as f64 * 0.1);
            last = d;
        }
    }

    #[test]
    fn the_rules_parse_their_names_and_strict_spares_pinches() {
        for rule in ValidityRule::ALL {
            assert_eq!(rule.name().parse::<ValidityRule>(), Ok(rule));
            assert_eq!(rule.to_string(), rule.name());
        }
        let e = "loose".parse::<ValidityRule>().unwrap_err();
        assert!(e.to_string().contains("holds, strict, thesis"), "{e}");
        assert_eq!(ValidityRule::default(), ValidityRule::Holds);

        let deg = |rule: ValidityRule, mu: f64, pinch: bool| {
            rule.needed_normal_cap(mu, pinch).map(f64::to_degrees)
        };
        for mu in [0.0, 0.25, 0.5, 1.0, 3.0] {
            let holds = one_sided_cap(mu).to_degrees();
            assert_eq!(deg(ValidityRule::Holds, mu, false), Some(holds));
            assert_eq!(deg(ValidityRule::Holds, mu, true), Some(holds));
            assert_eq!(deg(ValidityRule::Strict, mu, false), Some(90.0));
            assert_eq!(deg(ValidityRule::Strict, mu, true), Some(holds));
            assert_eq!(deg(ValidityRule::Thesis, mu, false), None);
        }
    }
}
