//! The dataset folder: its manifest, its parts, and what a resumed run has already done.
//!
//! `_manifest.json` and `part-NNNNN.parquet` files; a part being written is named
//! `.part-NNNNN.parquet.partial` until it is complete.

use std::collections::HashSet;
use std::fs::File;
use std::path::{Path, PathBuf};

use arrow_array::{Array, RecordBatch, StringArray, UInt64Array};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::arrow::{ArrowWriter, ProjectionMask};
use parquet::basic::Compression;
use parquet::file::properties::WriterProperties;

use crate::error::{BatchError, DatasetProblem};
use crate::row::{columns, schema, to_record_batch};
use crate::{AttemptRow, BatchPlan, RowKey};

/// The `schema` field of every manifest this version writes.
pub const DATASET_SCHEMA: &str = "prehensile.batch/1";
/// Named with a leading underscore so that pyarrow and pandas, reading the folder as a
/// dataset, skip it (as they skip the dot-named partial parts).
const MANIFEST: &str = "_manifest.json";
const PART_PREFIX: &str = "part-";
const PART_SUFFIX: &str = ".parquet";
const PARTIAL_SUFFIX: &str = ".partial";

/// One column, described.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ColumnDoc {
    /// Column name.
    pub name: String,
    /// Arrow type.
    #[serde(rename = "type")]
    pub data_type: String,
    /// What it holds.
    pub meaning: String,
}

/// `manifest.json`: what made the dataset.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Manifest {
    /// [`DATASET_SCHEMA`].
    pub schema: String,
    /// Version of prehensile that created the dataset.
    pub prehensile_version: String,
    /// The inputs.
    pub plan: BatchPlan,
    /// Every column.
    pub columns: Vec<ColumnDoc>,
}

impl Manifest {
    /// The manifest of a dataset made by this version from `plan`.
    pub fn new(plan: &BatchPlan) -> Self {
        Self {
            schema: DATASET_SCHEMA.into(),
            prehensile_version: env!("CARGO_PKG_VERSION").into(),
            plan: plan.clone(),
            columns: columns()
                .into_iter()
                .map(|(f, meaning)| ColumnDoc {
                    name: f.name().clone(),
                    data_type: f.data_type().to_string(),
                    meaning: meaning.into(),
                })
                .collect(),
        }
    }
}

/// An open dataset folder that parts are added to.
#[derive(Debug)]
pub struct Dataset {
    folder: PathBuf,
    next_part: u32,
}

fn io(path: &Path, source: std::io::Error) -> BatchError {
    BatchError::Io {
        path: path.display().to_string(),
        source,
    }
}

fn parquet(path: &Path, source: parquet::errors::ParquetError) -> BatchError {
    BatchError::Parquet {
        path: path.display().to_string(),
        source,
    }
}

fn arrow(path: &Path, source: arrow_schema::ArrowError) -> BatchError {
    BatchError::Arrow {
        path: path.display().to_string(),
        source,
    }
}

fn damaged(path: &Path, problem: DatasetProblem) -> BatchError {
    BatchError::Damaged {
        path: path.display().to_string(),
        problem,
    }
}

/// Writes `bytes` to `path` whole or not at all ([`prehensile_formats::write_atomically`]).
fn write_whole(path: &Path, bytes: &[u8]) -> Result<(), BatchError> {
    prehensile_formats::write_atomically(path, bytes).map_err(|e| BatchError::Output {
        path: path.display().to_string(),
        source: e,
    })
}

impl Dataset {
    /// Opens `folder` for `plan`: creates it with its manifest, or checks that the manifest
    /// there was made from the same plan. Returns the dataset and the keys of the rows it
    /// already has.
    pub fn open(folder: &Path, plan: &BatchPlan) -> Result<(Self, HashSet<RowKey>), BatchError> {
        std::fs::create_dir_all(folder).map_err(|e| io(folder, e))?;
        let manifest_path = folder.join(MANIFEST);
        let wanted = Manifest::new(plan);
        let entries: Vec<PathBuf> = std::fs::read_dir(folder)
            .map_err(|e| io(folder, e))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        let name = |p: &Path| {
            p.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        };
        if manifest_path.is_file() {
            let text =
                std::fs::read_to_string(&manifest_path).map_err(|e| io(&manifest_path, e))?;
            let found: Manifest =
                serde_json::from_str(&text).map_err(|source| BatchError::Manifest {
                    path: manifest_path.display().to_string(),
                    source,
                })?;
            if found.schema != DATASET_SCHEMA {
                return Err(damaged(
                    &manifest_path,
                    DatasetProblem::Schema {
                        found: found.schema,
                        expected: DATASET_SCHEMA,
                    },
                ));
            }
            let differ = differences(&found.plan, plan);
            if !differ.is_empty() {
                return Err(BatchError::ManifestMismatch {
                    folder: folder.display().to_string(),
                    what: differ,
                });
            }
        } else {
            if let Some(stranger) = entries.iter().find(|p| !name(p).ends_with(PARTIAL_SUFFIX)) {
                return Err(damaged(folder, DatasetProblem::NotEmpty(name(stranger))));
            }
            let text = serde_json::to_string_pretty(&wanted).expect("a manifest always serializes");
            write_whole(&manifest_path, text.as_bytes())?;
        }
        // A part cut short by a kill never got its final name: remove it, its rows are redone.
        for p in &entries {
            if name(p).ends_with(PARTIAL_SUFFIX) {
                std::fs::remove_file(p).map_err(|e| io(p, e))?;
            }
        }
        let mut dataset = Self {
            folder: folder.to_path_buf(),
            next_part: 0,
        };
        let mut done = HashSet::new();
        for part in dataset.parts()? {
            let number: u32 = name(&part)[PART_PREFIX.len()..name(&part).len() - PART_SUFFIX.len()]
                .parse()
                .map_err(|_| damaged(&part, DatasetProblem::PartName))?;
            dataset.next_part = dataset.next_part.max(number + 1);
            for key in read_keys(&part)? {
                if !done.insert(key.clone()) {
                    return Err(damaged(
                        &part,
                        DatasetProblem::Duplicate(format!("{key:?}")),
                    ));
                }
            }
        }
        Ok((dataset, done))
    }

    /// The finished parts, in order.
    pub fn parts(&self) -> Result<Vec<PathBuf>, BatchError> {
        part_files(&self.folder)
    }

    /// The folder.
    pub fn folder(&self) -> &Path {
        &self.folder
    }

    /// Writes `rows` as the next part (whole or not at all).
    pub fn write_part(&mut self, rows: &[AttemptRow]) -> Result<PathBuf, BatchError> {
        let path = self
            .folder
            .join(format!("{PART_PREFIX}{:05}{PART_SUFFIX}", self.next_part));
        let batch = to_record_batch(rows).map_err(|e| arrow(&path, e))?;
        let properties = WriterProperties::builder()
            .set_compression(Compression::SNAPPY)
            .build();
        let mut bytes = Vec::new();
        let mut writer = ArrowWriter::try_new(&mut bytes, schema(), Some(properties))
            .map_err(|e| parquet(&path, e))?;
        writer.write(&batch).map_err(|e| parquet(&path, e))?;
        writer.close().map_err(|e| parquet(&path, e))?;
        write_whole(&path, &bytes)?;
        self.next_part += 1;
        Ok(path)
    }
}

fn part_files(folder: &Path) -> Result<Vec<PathBuf>, BatchError> {
    let mut parts: Vec<PathBuf> = std::fs::read_dir(folder)
        .map_err(|e| io(folder, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name().is_some_and(|n| {
                let n = n.to_string_lossy();
                n.starts_with(PART_PREFIX) && n.ends_with(PART_SUFFIX)
            })
        })
        .collect();
    parts.sort();
    Ok(parts)
}

/// Which inputs of two plans differ, by name.
fn differences(a: &BatchPlan, b: &BatchPlan) -> Vec<&'static str> {
    [
        ("hands", a.hands != b.hands),
        ("objects", a.objects != b.objects),
        ("movements", a.movements != b.movements),
        ("shoulders", a.shoulders != b.shoulders),
        ("seeds", a.seeds != b.seeds),
        ("options", a.options != b.options),
    ]
    .into_iter()
    .filter_map(|(name, differs)| differs.then_some(name))
    .collect()
}

/// The keys of the rows in one part.
fn read_keys(part: &Path) -> Result<Vec<RowKey>, BatchError> {
    let file = File::open(part).map_err(|e| io(part, e))?;
    let builder = ParquetRecordBatchReaderBuilder::try_new(file).map_err(|e| parquet(part, e))?;
    let mask = ProjectionMask::roots(builder.parquet_schema(), [0, 1, 2, 3, 4]);
    let reader = builder
        .with_projection(mask)
        .build()
        .map_err(|e| parquet(part, e))?;
    let mut keys = Vec::new();
    for batch in reader {
        let batch = batch.map_err(|e| arrow(part, e))?;
        let text = |i: usize| {
            batch
                .column(i)
                .as_any()
                .downcast_ref::<StringArray>()
                .ok_or_else(|| damaged(part, DatasetProblem::ColumnType(i)))
        };
        let (hand, object, movement, shoulder) = (text(0)?, text(1)?, text(2)?, text(3)?);
        let seed = batch
            .column(4)
            .as_any()
            .downcast_ref::<UInt64Array>()
            .ok_or_else(|| damaged(part, DatasetProblem::ColumnType(4)))?;
        for r in 0..batch.num_rows() {
            if hand.is_null(r) || object.is_null(r) || seed.is_null(r) {
                return Err(damaged(part, DatasetProblem::NoKey(r)));
            }
            keys.push(RowKey {
                hand: hand.value(r).into(),
                object: object.value(r).into(),
                movement_requested: movement.value(r).into(),
                shoulder_choice: shoulder.value(r).into(),
                seed: seed.value(r),
            });
        }
    }
    Ok(keys)
}

/// Every row of the dataset in `folder`, part by part.
pub fn read_rows(folder: &Path) -> Result<Vec<RecordBatch>, BatchError> {
    let mut out = Vec::new();
    for part in part_files(folder)? {
        let file = File::open(&part).map_err(|e| io(&part, e))?;
        let reader = ParquetRecordBatchReaderBuilder::try_new(file)
            .and_then(|b| b.build())
            .map_err(|e| parquet(&part, e))?;
        for batch in reader {
            out.push(batch.map_err(|e| arrow(&part, e))?);
        }
    }
    Ok(out)
}
