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

/// The type of a column.
#[derive(Clone, Copy)]
enum Kind {
    Text,
    Texts,
    U32,
    U64,
    F64,
    F64s,
    Bool,
}

impl Kind {
    fn data_type(self) -> DataType {
        match self {
            Self::Text => DataType::Utf8,
            Self::Texts => list_of(DataType::Utf8),
            Self::U32 => DataType::UInt32,
            Self::U64 => DataType::UInt64,
            Self::F64 => DataType::Float64,
            Self::F64s => list_of(DataType::Float64),
            Self::Bool => DataType::Boolean,
        }
    }
}

use Kind::{Bool, F64s, Text, Texts, F64, U32, U64};

/// Every column: its name, type, whether it may be null, and what it means.
const COLUMNS: [(&str, Kind, bool, &str); 32] = [
    (
        "hand",
        Text,
        false,
        "hand as given: a built-in name or a file",
    ),
    (
        "object",
        Text,
        false,
        "object as given: a built-in name or a mesh file",
    ),
    (
        "movement_requested",
        Text,
        false,
        "movement asked for (auto tries each)",
    ),
    (
        "shoulder_choice",
        Text,
        false,
        "shoulder as given: default or X,Y,Z",
    ),
    ("seed", U64, false, "seed of the random search angles"),
    (
        "status",
        Text,
        false,
        "valid, invalid (searched, nothing valid) or error (did not run)",
    ),
    ("reason", Text, true, "why not valid, or the error"),
    ("hand_name", Text, true, "the hand's own name"),
    ("object_name", Text, true, "the object's own name"),
    ("movement", Text, true, "the movement of the chosen result"),
    (
        "shoulder",
        F64s,
        true,
        "shoulder position used, object frame, metres",
    ),
    ("hook", F64s, true, "hook position, object frame, metres"),
    (
        "quality",
        F64,
        true,
        "the search's quality (null when -inf)",
    ),
    ("gdist", F64, true, "quality term gDist, metres"),
    ("fdist", F64, true, "quality term fDist"),
    ("tdist", F64, true, "quality term tDist*"),
    ("wdist", F64, true, "quality term wDist"),
    ("stability_term", F64, true, "quality term epsilon times L"),
    (
        "force_closure",
        Bool,
        true,
        "contacts in force closure with the friction cones",
    ),
    (
        "epsilon",
        F64,
        true,
        "Ferrari-Canny epsilon (L1), torques over torque_scale",
    ),
    (
        "load_ratio",
        F64s,
        true,
        "load held along +x,-x,+y,-y,+z,-z per newton of grip",
    ),
    (
        "torque_scale",
        F64,
        true,
        "metres dividing torques in epsilon",
    ),
    ("contact_count", U32, true, "number of contacts"),
    (
        "fingers_touching",
        Texts,
        true,
        "fingers touching the object",
    ),
    (
        "joint_names",
        Texts,
        true,
        "joint degrees of freedom, the hand file's names",
    ),
    ("joint_angles", F64s, true, "their angles, radians"),
    (
        "wrist_position",
        F64s,
        true,
        "wrist (root bone) position, metres",
    ),
    (
        "wrist_rotation_xyzw",
        F64s,
        true,
        "wrist rotation, unit quaternion x,y,z,w",
    ),
    (
        "steps",
        U32,
        true,
        "optimization steps of the chosen search",
    ),
    (
        "evaluations",
        U64,
        true,
        "poses evaluated by the chosen search",
    ),
    (
        "setup_seconds",
        F64,
        false,
        "reading and setting up the object (shared by its rows)",
    ),
    (
        "search_seconds",
        F64,
        false,
        "search time of this attempt, all movements",
    ),
];

/// The dataset's columns, in order, with what each means (also written to the manifest).
pub fn columns() -> Vec<(Field, &'static str)> {
    COLUMNS
        .iter()
        .map(|&(name, kind, nullable, meaning)| {
            (Field::new(name, kind.data_type(), nullable), meaning)
        })
        .collect()
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
