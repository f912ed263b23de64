//! The defaults of a grasp request, in one place: [`super::GraspOptions::default`], the CLI's
//! help, the Python signatures and stubs (tested against them) and the browser build read
//! these.

use crate::parameter::UpAxis;
use crate::stability::ContactModel;

use super::quality::ValidityRule;

/// The movement name that tries each of the hand's movements and keeps the best.
pub const AUTO_MOVEMENT: &str = "auto";
/// The movement: `auto` tries each of the hand's movements and keeps the best.
pub const MOVEMENT: &str = AUTO_MOVEMENT;
/// Seed of the random search angles.
pub const SEED: u64 = 1;
/// The world's up axis.
pub const UP: UpAxis = UpAxis::Z;
/// Coulomb friction the search assumes ([`ContactModel::DEFAULT_FRICTION`]).
pub const FRICTION: f64 = ContactModel::DEFAULT_FRICTION;
/// Which grasps are valid.
pub const VALIDITY: ValidityRule = ValidityRule::Holds;
/// The default [`SearchParams::one_sided_patience`](super::SearchParams::one_sided_patience): steps a search goes on with a valid best
/// grasp that pushes from one side only, looking for one that pushes from every side.
/// Measured on power grasps of ten objects, seeds 1–4 (docs/QUALITY.md): the Shadow
/// hand returns 15 one-sided grasps of 38 after 15 steps, 9 after 60,
/// 6 after 120, 5 with no limit (its sphere grasps of seeds 3 and 4 push from every side after
/// 107 and 116 steps), its torus search taking 10 ms before the ranking, 45 ms after 60 steps,
/// 81 ms after 120 and 285 ms with no limit (medians); the human hand returns none after 30.
pub const ONE_SIDED_PATIENCE: u32 = 120;
/// The largest budget a request takes, milliseconds (a day).
pub const MAX_BUDGET_MS: f64 = 86_400_000.0;
/// The most threads a search takes.
pub const MAX_THREADS: usize = 256;
/// The largest friction coefficient the contact model takes.
pub const MAX_FRICTION: f64 = 10.0;
