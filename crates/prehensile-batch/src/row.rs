//! One row per attempt, and its Arrow columns.

use std::sync::Arc;

use arrow_array::builder::{
    BooleanBuilder, Float64Builder, ListBuilder, StringBuilder, UInt32Builder, UInt64Builder,
};
use arrow_array::{ArrayRef, RecordBatch};
use arrow_schema::{ArrowError, DataType, Field, Schema, SchemaRef};
use prehensile_core::search::GraspResult;

/// What became of an attempt.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AttemptStatus {
    /// The search found a valid grasp.
    Valid,
    /// The search ran and found none; `reason` says which test the best pose failed.
    Invalid,
    /// The attempt could not run (the hand or mesh did not load, the search could not start,
    /// an internal error); `reason` says why.
    Error,
}

impl AttemptStatus {
    /// The column's text.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Valid => "valid",
            Self::Invalid => "invalid",
            Self::Error => "error",
        }
    }
}

/// What identifies an attempt across runs: the inputs as the manifest names them, and the seed.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RowKey {
    /// Hand as given.
    pub hand: String,
    /// Object as given (after folder and pattern expansion).
    pub object: String,
    /// Movement as requested (may be `auto`).
    pub movement_requested: String,
    /// Shoulder as given (`default` or `X,Y,Z`).
    pub shoulder_choice: String,
    /// Seed.
    pub seed: u64,
}

/// One attempt's outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct AttemptRow {
    /// Which attempt.
    pub key: RowKey,
    /// Valid, invalid or error.
    pub status: AttemptStatus,
    /// Why not valid, or the error.
    pub reason: Option<String>,
    /// The full search result (absent for errors).
    pub result: Option<GraspResult>,
    /// Seconds reading and setting up the object (shared by its attempts; each row repeats it).
    pub setup_seconds: f64,
    /// Seconds of search for this attempt.
    pub search_seconds: f64,
}

impl AttemptRow {
    /// A row for a search that ran.
    pub fn searched(key: RowKey, result: GraspResult, setup: f64, search: f64) -> Self {
        Self {
            key,
            status: if result.valid {
                AttemptStatus::Valid
            } else {
                AttemptStatus::Invalid
            },
            reason: result.invalid_reason.clone(),
            result: Some(result),
            setup_seconds: setup,
            search_seconds: search,
        }
    }

    /// A row for an attempt that could not run.
    pub fn failed(key: RowKey, reason: String, setup: f64) -> Self {
        Self {
            key,
            status: AttemptStatus::Error,
            reason: Some(reason),
            result: None,
            setup_seconds: setup,
            search_seconds: 0.0,
        }
    }
}

/// Columns whose values depend on the machine's speed, not on the inputs: left out when two
/// datasets are compared row for row.
pub const TIMING_COLUMNS: [&str; 2] = ["setup_seconds", "search_seconds"];

fn list_of(item: DataType) -> DataType {
    DataType::List(Arc::new(Field::new("item", item, true)))
}

/// The dataset's columns, in order, with what each means (also written to the manifest).
pub fn columns() -> Vec<(Field, &'static str)> {
    use DataType::{Boolean, Float64, UInt32, UInt64, Utf8};
    let f = |name: &str, t: DataType, nullable: bool| Field::new(name, t, nullable);
    vec![
        (
            f("hand", Utf8, false),
            "hand as given: a built-in name or a file",
        ),
        (
            f("object", Utf8, false),
            "object as given: a built-in name or a mesh file",
        ),
        (
            f("movement_requested", Utf8, false),
            "movement asked for (auto tries each)",
        ),
        (
            f("shoulder_choice", Utf8, false),
            "shoulder as given: default or X,Y,Z",
        ),
        (f("seed", UInt64, false), "seed of the random search angles"),
        (
            f("status", Utf8, false),
            "valid, invalid (searched, nothing valid) or error (did not run)",
        ),
        (f("reason", Utf8, true), "why not valid, or the error"),
        (f("hand_name", Utf8, true), "the hand's own name"),
        (f("object_name", Utf8, true), "the object's own name"),
        (
            f("movement", Utf8, true),
            "the movement of the chosen result",
        ),
        (
            f("shoulder", list_of(Float64), true),
            "shoulder position used, object frame, metres",
        ),
        (
            f("hook", list_of(Float64), true),
            "hook position, object frame, metres",
        ),
        (
            f("quality", Float64, true),
            "the search's quality (null when -inf)",
        ),
        (f("gdist", Float64, true), "quality term gDist, metres"),
        (f("fdist", Float64, true), "quality term fDist"),
        (f("tdist", Float64, true), "quality term tDist*"),
        (f("wdist", Float64, true), "quality term wDist"),
        (
            f("stability_term", Float64, true),
            "quality term epsilon times L",
        ),
        (
            f("force_closure", Boolean, true),
            "contacts in force closure with the friction cones",
        ),
        (
            f("epsilon", Float64, true),
            "Ferrari-Canny epsilon (L1), torques over torque_scale",
        ),
        (
            f("load_ratio", list_of(Float64), true),
            "load held along +x,-x,+y,-y,+z,-z per newton of grip",
        ),
        (
            f("torque_scale", Float64, true),
            "metres dividing torques in epsilon",
        ),
        (f("contact_count", UInt32, true), "number of contacts"),
        (
            f("fingers_touching", list_of(Utf8), true),
            "fingers touching the object",
        ),
        (
            f("joint_names", list_of(Utf8), true),
            "joint degrees of freedom, the hand file's names",
        ),
        (
            f("joint_angles", list_of(Float64), true),
            "their angles, radians",
        ),
        (
            f("wrist_position", list_of(Float64), true),
            "wrist (root bone) position, metres",
        ),
        (
            f("wrist_rotation_xyzw", list_of(Float64), true),
            "wrist rotation, unit quaternion x,y,z,w",
        ),
        (
            f("steps", UInt32, true),
            "optimization steps of the chosen search",
        ),
        (
            f("evaluations", UInt64, true),
            "poses evaluated by the chosen search",
        ),
        (
            f("setup_seconds", Float64, false),
            "reading and setting up the object (shared by its rows)",
        ),
        (
            f("search_seconds", Float64, false),
            "search time of this attempt, all movements",
        ),
    ]
}

/// The Arrow schema of [`columns`].
pub fn schema() -> SchemaRef {
    Arc::new(Schema::new(
        columns().into_iter().map(|(f, _)| f).collect::<Vec<_>>(),
    ))
}

fn of(r: &AttemptRow) -> Option<&GraspResult> {
    r.result.as_ref()
}

/// Rows as one Arrow record batch.
pub fn to_record_batch(rows: &[AttemptRow]) -> Result<RecordBatch, ArrowError> {
    let text = |get: &dyn Fn(&AttemptRow) -> Option<String>| -> ArrayRef {
        let mut b = StringBuilder::new();
        for r in rows {
            b.append_option(get(r));
        }
        Arc::new(b.finish())
    };
    let float = |get: &dyn Fn(&AttemptRow) -> Option<f64>| -> ArrayRef {
        let mut b = Float64Builder::new();
        for r in rows {
            b.append_option(get(r));
        }
        Arc::new(b.finish())
    };
    let floats = |get: &dyn Fn(&GraspResult) -> Vec<f64>| -> ArrayRef {
        let mut b = ListBuilder::new(Float64Builder::new());
        for r in rows {
            match &r.result {
                Some(g) => {
                    b.values().append_slice(&get(g));
                    b.append(true);
                }
                None => b.append(false),
            }
        }
        Arc::new(b.finish())
    };
    let texts = |get: &dyn Fn(&GraspResult) -> Vec<String>| -> ArrayRef {
        let mut b = ListBuilder::new(StringBuilder::new());
        for r in rows {
            match &r.result {
                Some(g) => {
                    for s in get(g) {
                        b.values().append_value(s);
                    }
                    b.append(true);
                }
                None => b.append(false),
            }
        }
        Arc::new(b.finish())
    };
    let mut seed = UInt64Builder::new();
    let mut closure = BooleanBuilder::new();
    let mut contacts = UInt32Builder::new();
    let mut steps = UInt32Builder::new();
    let mut evaluations = UInt64Builder::new();
    for r in rows {
        seed.append_value(r.key.seed);
        closure.append_option(of(r).map(|g| g.stability.force_closure));
        contacts.append_option(of(r).map(|g| g.contacts.len() as u32));
        steps.append_option(of(r).map(|g| g.stats.steps));
        evaluations.append_option(of(r).map(|g| g.stats.evaluations));
    }
    let arrays: Vec<ArrayRef> = vec![
        text(&|r| Some(r.key.hand.clone())),
        text(&|r| Some(r.key.object.clone())),
        text(&|r| Some(r.key.movement_requested.clone())),
        text(&|r| Some(r.key.shoulder_choice.clone())),
        Arc::new(seed.finish()),
        text(&|r| Some(r.status.as_str().to_string())),
        text(&|r| r.reason.clone()),
        text(&|r| of(r).map(|g| g.hand.clone())),
        text(&|r| of(r).map(|g| g.object.clone())),
        text(&|r| of(r).map(|g| g.movement.clone())),
        floats(&|g| g.shoulder.to_vec()),
        floats(&|g| g.hook.to_vec()),
        float(&|r| of(r).and_then(|g| g.quality)),
        float(&|r| of(r).map(|g| g.terms.gdist)),
        float(&|r| of(r).map(|g| g.terms.fdist)),
        float(&|r| of(r).map(|g| g.terms.tdist)),
        float(&|r| of(r).map(|g| g.terms.wdist)),
        float(&|r| of(r).map(|g| g.terms.stability)),
        Arc::new(closure.finish()),
        float(&|r| of(r).map(|g| g.stability.epsilon)),
        floats(&|g| g.stability.load_ratio.to_vec()),
        float(&|r| of(r).map(|g| g.stability.torque_scale)),
        Arc::new(contacts.finish()),
        texts(&|g| g.fingers_touching.clone()),
        texts(&|g| g.joints.iter().map(|j| j.name.clone()).collect()),
        floats(&|g| g.joints.iter().map(|j| j.angle).collect()),
        floats(&|g| g.wrist.position.to_vec()),
        floats(&|g| g.wrist.rotation_xyzw.to_vec()),
        Arc::new(steps.finish()),
        Arc::new(evaluations.finish()),
        float(&|r| Some(r.setup_seconds)),
        float(&|r| Some(r.search_seconds)),
    ];
    RecordBatch::try_new(schema(), arrays)
}
