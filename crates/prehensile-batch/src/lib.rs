//! Grasp datasets in batch: every combination of hands, objects, movements, shoulders and seeds,
//! searched on all cores with each object set up once, written as an Apache Parquet dataset with
//! a JSON manifest, resumable after a kill at any moment.
//!
//! A dataset is a folder:
//! - `_manifest.json`: the inputs (hands, objects, movements, shoulders, seeds, options), the
//!   version of prehensile that wrote it, and what each column means;
//! - `part-NNNNN.parquet`: rows, one per attempt. A part is written to a temporary name and
//!   renamed when complete, so a part is either whole or absent; a resumed run reads the keys of
//!   the parts present and does only the attempts missing. Rows are never duplicated or lost.
//!
//! Failures (a hand or mesh that does not load, a search that cannot start, a panic inside one
//! attempt) are rows with `status = "error"` and the message; they never stop the batch. Only
//! the dataset itself failing (a full disk, a folder made with other inputs) stops it, with the
//! rows written so far kept.
#![deny(missing_docs)]

mod dataset;
mod error;
mod plan;
mod row;
mod run;

pub use dataset::{read_rows, ColumnDoc, Dataset, Manifest, DATASET_SCHEMA};
pub use error::{BatchError, DatasetProblem, PlanError, MAX_SEEDS};
pub use plan::{expand_objects, Attempt, BatchOptions, BatchPlan, Shoulder};
pub use row::{
    columns, schema, to_record_batch, AttemptRow, AttemptStatus, RowKey, TIMING_COLUMNS,
};
pub use run::{run_batch, BatchProgress, BatchSummary, FLUSH_ROWS};
