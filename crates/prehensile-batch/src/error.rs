//! Why a batch cannot run, or stopped: a plan it cannot use, or a dataset it cannot read or write.

use prehensile_core::parameter::ParameterError;

/// Why a batch stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BatchError {
    /// The plan is unusable.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// The output folder holds a dataset made from other inputs.
    #[error("{folder} holds a dataset made with other inputs ({} differ); use another --out folder, or delete it to start over", what.join(", "))]
    ManifestMismatch {
        /// The dataset folder.
        folder: String,
        /// Which inputs differ.
        what: Vec<&'static str>,
    },
    /// Reading or writing a file of the dataset failed (a full disk, no permission).
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
    /// A file of the dataset could not be written whole.
    #[error("{path}: {source}")]
    Output {
        /// The file.
        path: String,
        /// What went wrong.
        #[source]
        source: prehensile_formats::OutputError,
    },
    /// A Parquet part could not be written or read.
    #[error("{path}: {source}")]
    Parquet {
        /// The part.
        path: String,
        /// What the Parquet library said.
        #[source]
        source: parquet::errors::ParquetError,
    },
    /// Rows could not be put into or read from Arrow arrays.
    #[error("{path}: {source}")]
    Arrow {
        /// The part.
        path: String,
        /// What the Arrow library said.
        #[source]
        source: arrow_schema::ArrowError,
    },
    /// A dataset's manifest is not one this version reads.
    #[error("{path}: not a dataset manifest: {source}")]
    Manifest {
        /// The manifest.
        path: String,
        /// What the JSON reader said.
        #[source]
        source: serde_json::Error,
    },
    /// The dataset folder holds something this version did not write.
    #[error("{path}: {problem}")]
    Damaged {
        /// The file or folder.
        path: String,
        /// What is wrong with it.
        problem: DatasetProblem,
    },
}

/// Why a batch's inputs cannot make a plan.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PlanError {
    /// A list of the plan is empty.
    #[error("the batch has no {0}")]
    Empty(&'static str),
    /// A name appears twice in a list.
    #[error("{what} '{name}' is listed twice")]
    Repeated {
        /// Which list.
        what: &'static str,
        /// The name.
        name: String,
    },
    /// A search option is out of range.
    #[error(transparent)]
    Parameter(#[from] ParameterError),
    /// A shoulder is neither `default` nor three finite numbers.
    #[error("shoulder '{0}': use default or three finite numbers X,Y,Z (metres, at most 1e6)")]
    Shoulder(String),
    /// A folder of objects holds no mesh file.
    #[error("{folder}: the folder has no mesh files ({})", extensions.join(", "))]
    EmptyFolder {
        /// The folder.
        folder: String,
        /// The extensions looked for.
        extensions: &'static [&'static str],
    },
    /// A folder of objects could not be listed.
    #[error("{folder}: cannot list the folder ({kind})")]
    UnreadableFolder {
        /// The folder.
        folder: String,
        /// What the system said.
        kind: std::io::ErrorKind,
    },
    /// An object pattern is not a valid glob pattern.
    #[error("{pattern}: not a valid pattern: {problem} at character {position}")]
    Pattern {
        /// The pattern.
        pattern: String,
        /// Where it goes wrong.
        position: usize,
        /// What is wrong there.
        problem: &'static str,
    },
    /// An object pattern matches no file.
    #[error("{0}: matches no file")]
    NoMatch(String),
    /// More seeds than a batch takes.
    #[error("{0} seeds: give 1 to {MAX_SEEDS}")]
    Seeds(u64),
}

/// The most seeds a batch takes.
pub const MAX_SEEDS: u64 = 1_000_000;

/// What is wrong with a file or folder of a dataset.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DatasetProblem {
    /// The manifest names another dataset schema.
    #[error("dataset schema '{found}', this version writes '{expected}'")]
    Schema {
        /// The schema found.
        found: String,
        /// The schema this version writes.
        expected: &'static str,
    },
    /// A folder without a manifest is not empty.
    #[error(
        "the folder is not empty ({0} is there) and has no manifest; choose an empty or new folder"
    )]
    NotEmpty(String),
    /// A part's file name is not one this version writes.
    #[error("not a part name this version writes")]
    PartName,
    /// A key column has another type.
    #[error("column {0} is not of the type this version writes")]
    ColumnType(usize),
    /// A row lacks its key.
    #[error("row {0} has no key")]
    NoKey(usize),
    /// A row is in the dataset twice.
    #[error("a row ({0}) is in the dataset twice; the folder was edited")]
    Duplicate(String),
}
