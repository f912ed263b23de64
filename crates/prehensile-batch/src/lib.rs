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

mod dataset;
mod plan;
mod row;
mod run;

pub use dataset::{read_rows, ColumnDoc, Dataset, Manifest, DATASET_SCHEMA};
pub use plan::{expand_objects, Attempt, BatchOptions, BatchPlan, Shoulder};
pub use row::{
    columns, schema, to_record_batch, AttemptRow, AttemptStatus, RowKey, TIMING_COLUMNS,
};
pub use run::{run_batch, BatchProgress, BatchSummary};

/// Why a batch stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BatchError {
    /// The plan is unusable (no objects, a bad shoulder, an option out of range).
    #[error("{0}")]
    Plan(String),
    /// The output folder holds a dataset made from other inputs.
    #[error("{folder} holds a dataset made with other inputs ({what} differ); use another --out folder, or delete it to start over")]
    ManifestMismatch {
        /// The dataset folder.
        folder: String,
        /// Which inputs differ.
        what: String,
    },
    /// Reading or writing the dataset failed (a full disk, no permission, a damaged part).
    #[error("{path}: {reason}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        reason: String,
    },
}
