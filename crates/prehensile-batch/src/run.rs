//! Running a batch on all cores: objects set up once each, attempts in parallel (rayon), rows
//! handed to one writer thread that adds them to the dataset in whole parts.

use std::collections::HashSet;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

use prehensile_core::search::find_grasp;
use prehensile_core::{HandModel, ObjectModel};
use prehensile_formats::sources::{hand_from_spec, object_from_spec};
use rayon::prelude::*;

use crate::{Attempt, AttemptRow, AttemptStatus, BatchError, BatchPlan, Dataset, RowKey, Shoulder};

/// A part is written at least this often while rows come in, so that a kill loses little.
const FLUSH_INTERVAL: Duration = Duration::from_secs(5);

/// Hears how a batch goes (called from one thread at a time).
pub trait BatchProgress: Sync {
    /// Before the first attempt: how many attempts the plan makes, and how many the dataset
    /// already has.
    fn started(&self, _total: usize, _already_done: usize) {}
    /// After each attempt's row is received.
    fn attempt_done(&self, _row: &AttemptRow) {}
}

/// Progress that nobody watches.
impl BatchProgress for () {}

/// How a batch went.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BatchSummary {
    /// Attempts in the plan.
    pub total: usize,
    /// Attempts the dataset already had when this run began.
    pub already_done: usize,
    /// Attempts this run made.
    pub ran: usize,
    /// Of those, valid grasps.
    pub valid: usize,
    /// Of those, searches that found no valid grasp.
    pub invalid: usize,
    /// Of those, attempts that could not run.
    pub errors: usize,
    /// Parts this run wrote.
    pub parts_written: usize,
}

/// Rows a batch writes into one part file by default ([`run_batch`]'s `flush_rows`).
pub const FLUSH_ROWS: usize = 256;

/// Runs every attempt of `plan` that the dataset in `folder` lacks, writing a part every
/// `flush_rows` rows (and at least every few seconds). A failing attempt becomes an error row;
/// only the dataset failing stops the run, keeping every part written.
pub fn run_batch(
    plan: &BatchPlan,
    folder: &Path,
    flush_rows: usize,
    progress: &dyn BatchProgress,
) -> Result<BatchSummary, BatchError> {
    plan.check()?;
    let (dataset, done) = Dataset::open(folder, plan)?;
    let pending: Vec<Vec<Attempt>> = (0..plan.objects.len())
        .map(|o| {
            plan.attempts_of(o)
                .into_iter()
                .filter(|a| !done.contains(&key(plan, a)))
                .collect()
        })
        .collect();
    progress.started(plan.attempt_count(), done.len());
    // Hands load once, up front; one that fails makes error rows, not a stopped batch.
    let hands: Vec<Result<HandModel, String>> = plan
        .hands
        .iter()
        .map(|spec| {
            catch_unwind(|| hand_from_spec(spec))
                .map_err(|p| internal_error(&*p))
                .and_then(|r| r.map_err(|e| e.to_string()))
        })
        .collect();
    let stop = AtomicBool::new(false);
    let (sender, receiver) = sync_channel::<AttemptRow>(4 * flush_rows.max(1));
    std::thread::scope(|scope| {
        let writer = scope.spawn(|| write_rows(dataset, receiver, flush_rows, progress, &stop));
        pending
            .par_iter()
            .enumerate()
            .filter(|(_, attempts)| !attempts.is_empty())
            .for_each_with(sender, |sender, (o, attempts)| {
                if stop.load(Ordering::Relaxed) {
                    return;
                }
                let began = Instant::now();
                let object = catch_unwind(|| {
                    object_from_spec(&plan.objects[o], plan.options.scale, plan.options.weld)
                })
                .map_err(|p| internal_error(&*p))
                .and_then(|r| r.map(|(o, _)| o).map_err(|e| e.to_string()));
                let setup = began.elapsed().as_secs_f64();
                attempts
                    .par_iter()
                    .for_each_with(sender.clone(), |sender, a| {
                        if stop.load(Ordering::Relaxed) {
                            return;
                        }
                        let row = match &object {
                            Ok(object) => run_attempt(plan, a, &hands[a.hand], object, setup),
                            Err(e) => AttemptRow::failed(key(plan, a), e.clone(), setup),
                        };
                        // The writer hangs up only after an error, which it returns below.
                        let _ = sender.send(row);
                    });
            });
        writer.join().expect("the writer thread does not panic")
    })
    .map(|mut summary| {
        summary.total = plan.attempt_count();
        summary.already_done = done.len();
        summary
    })
}

/// The key of an attempt.
fn key(plan: &BatchPlan, a: &Attempt) -> RowKey {
    RowKey {
        hand: plan.hands[a.hand].clone(),
        object: plan.objects[a.object].clone(),
        movement_requested: plan.movements[a.movement].clone(),
        shoulder_choice: plan.shoulders[a.shoulder].to_string(),
        seed: a.seed,
    }
}

/// One search, never panicking: its failures become an error row.
fn run_attempt(
    plan: &BatchPlan,
    attempt: &Attempt,
    hand: &Result<HandModel, String>,
    object: &ObjectModel,
    setup: f64,
) -> AttemptRow {
    let key = key(plan, attempt);
    let hand = match hand {
        Ok(h) => h,
        Err(e) => return AttemptRow::failed(key, e.clone(), setup),
    };
    let shoulder = match plan.shoulders[attempt.shoulder] {
        Shoulder::Default => None,
        Shoulder::At(p) => Some(p),
    };
    let options =
        plan.options
            .grasp_options(&plan.movements[attempt.movement], shoulder, attempt.seed);
    let began = Instant::now();
    match catch_unwind(AssertUnwindSafe(|| {
        let request = options.request(hand, object)?;
        find_grasp(hand, object, &request, &mut ())
    })) {
        Ok(Ok(result)) => AttemptRow::searched(key, result, setup, began.elapsed().as_secs_f64()),
        Ok(Err(e)) => AttemptRow::failed(key, e.to_string(), setup),
        Err(p) => AttemptRow::failed(key, internal_error(&*p), setup),
    }
}

fn internal_error(payload: &(dyn std::any::Any + Send)) -> String {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into());
    format!("internal error (please report it with the input): {what}")
}

/// The writer: collects rows and adds them to the dataset a part at a time. On an error it
/// raises `stop`, drops the channel (senders then fail quietly) and returns the error.
fn write_rows(
    mut dataset: Dataset,
    rows: Receiver<AttemptRow>,
    flush_rows: usize,
    progress: &dyn BatchProgress,
    stop: &AtomicBool,
) -> Result<BatchSummary, BatchError> {
    let mut summary = BatchSummary::default();
    let mut buffer: Vec<AttemptRow> = Vec::new();
    let mut seen: HashSet<RowKey> = HashSet::new();
    let mut last_flush = Instant::now();
    let mut flush = |buffer: &mut Vec<AttemptRow>,
                     summary: &mut BatchSummary,
                     last_flush: &mut Instant|
     -> Result<(), BatchError> {
        if !buffer.is_empty() {
            dataset.write_part(buffer)?;
            summary.parts_written += 1;
            buffer.clear();
        }
        *last_flush = Instant::now();
        Ok(())
    };
    loop {
        let received = rows.recv_timeout(FLUSH_INTERVAL);
        let result = match received {
            Ok(row) => {
                debug_assert!(seen.insert(row.key.clone()), "an attempt ran twice");
                summary.ran += 1;
                match row.status {
                    AttemptStatus::Valid => summary.valid += 1,
                    AttemptStatus::Invalid => summary.invalid += 1,
                    AttemptStatus::Error => summary.errors += 1,
                }
                progress.attempt_done(&row);
                buffer.push(row);
                if buffer.len() >= flush_rows.max(1) || last_flush.elapsed() >= FLUSH_INTERVAL {
                    flush(&mut buffer, &mut summary, &mut last_flush)
                } else {
                    Ok(())
                }
            }
            Err(RecvTimeoutError::Timeout) => flush(&mut buffer, &mut summary, &mut last_flush),
            Err(RecvTimeoutError::Disconnected) => {
                return flush(&mut buffer, &mut summary, &mut last_flush).map(|()| summary);
            }
        };
        if let Err(e) = result {
            stop.store(true, Ordering::Relaxed);
            return Err(e);
        }
    }
}
