//! `prehensile batch`: a grasp dataset over every combination of the inputs.

use std::sync::Mutex;

use indicatif::{ProgressBar, ProgressStyle};
use prehensile_batch::{
    expand_objects, run_batch, AttemptRow, AttemptStatus, BatchError, BatchOptions, BatchPlan,
    BatchProgress, Shoulder, MAX_SEEDS,
};

use crate::args::BatchArgs;
use crate::CliError;

/// A progress bar with the valid, invalid and error counts, and the time left.
struct Bar {
    bar: ProgressBar,
    counts: Mutex<[usize; 3]>,
}

impl BatchProgress for Bar {
    fn started(&self, total: usize, already_done: usize) {
        self.bar.set_length(total as u64);
        self.bar.set_position(already_done as u64);
        self.bar.reset_eta();
        if already_done > 0 {
            self.bar.println(format!(
                "resuming: {already_done} of {total} attempts are already in the dataset"
            ));
        }
    }

    fn attempt_done(&self, row: &AttemptRow) {
        let mut counts = self.counts.lock().expect("not poisoned");
        counts[match row.status {
            AttemptStatus::Valid => 0,
            AttemptStatus::Invalid => 1,
            AttemptStatus::Error => 2,
        }] += 1;
        self.bar.set_message(format!(
            "{} valid, {} invalid, {} errors",
            counts[0], counts[1], counts[2]
        ));
        self.bar.inc(1);
    }
}

/// Runs `prehensile batch`.
pub fn run(args: &BatchArgs) -> Result<i32, CliError> {
    let plan = BatchPlan {
        hands: args.hands.clone(),
        objects: expand_objects(&args.objects).map_err(BatchError::from)?,
        movements: args.movements.clone(),
        shoulders: args
            .shoulders
            .iter()
            .map(|s| Shoulder::parse(s))
            .collect::<Result<_, _>>()
            .map_err(BatchError::from)?,
        seeds: (1..=args.seeds.min(MAX_SEEDS + 1)).collect(),
        options: BatchOptions {
            scale: args.mesh_options.factor(),
            weld: args.mesh_options.weld,
            up: args.up,
            validity: args.validity,
            friction: args.friction,
            one_sided_patience: args.one_sided_patience,
        },
    };
    let bar = ProgressBar::new(plan.attempt_count() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} attempts, {per_sec}, {eta} left: {msg}")
            .expect("valid template"),
    );
    let progress = Bar {
        bar,
        counts: Mutex::new([0; 3]),
    };
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        let most = prehensile_core::search::defaults::MAX_THREADS as f64;
        prehensile_core::parameter::in_range("threads", n as f64, 1.0, most, "")?;
        pool = pool.num_threads(n);
    }
    let pool = pool
        .build()
        .map_err(|e| CliError::Usage(format!("cannot start the worker threads: {e}")))?;
    let summary = pool.install(|| run_batch(&plan, &args.out, args.flush_rows, &progress))?;
    progress.bar.finish_and_clear();
    out!(
        "{} attempts in {}: this run made {} ({} valid, {} invalid, {} errors) in {} part file(s); {} were already there",
        summary.total,
        args.out.display(),
        summary.ran,
        summary.valid,
        summary.invalid,
        summary.errors,
        summary.parts_written,
        summary.already_done
    );
    out!(
        "load it with: python3 -c \"import pandas; print(pandas.read_parquet('{}'))\"",
        args.out.display()
    );
    Ok(0)
}
