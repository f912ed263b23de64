//! The pose search (thesis ch. 5–6): hand positioning around a hook, quality, the optimization
//! steps with random angles, the initial approximation and an anytime planner.

pub mod defaults;
pub mod find_grasp;
pub mod initial_approximation;
pub mod material_hook;
pub mod optimization_step;
pub mod planner;
pub mod quality;
pub mod request;
pub mod result;
pub mod shared_planner;
pub mod start_position;
pub mod translate_to_free;
pub mod wrist_range;

pub use defaults::{AUTO_MOVEMENT, ONE_SIDED_PATIENCE};
pub use find_grasp::{
    better_grasp, default_movement, find_grasp, movements_to_try, GraspRequest, AUTO_PATIENCE,
};
pub use optimization_step::StepKind;
pub use planner::{
    GraspPlanner, PlannerStatus, SearchError, SearchParams, SearchSink, SearchStats, StopRule,
    SAMPLES_PER_SLICE,
};
pub use quality::{
    fdist_floor, finger_fdist_floor, hook_depth, one_sided_cap, Evaluation, Invalid, QualityTerms,
    QualityWeights, ValidityRule, ONE_SIDED_CAP,
};
pub use request::GraspOptions;
pub use result::{GraspResult, RESULT_SCHEMA};
pub use shared_planner::SharedPlanner;
pub use start_position::default_shoulder;
pub use translate_to_free::TranslateMode;
pub use wrist_range::WristRange;
