//! `prehensile batch`: the dataset it writes, resuming after a kill, and failures as rows.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use arrow_array::{Array, RecordBatch, StringArray, UInt64Array};
use prehensile_batch::{read_rows, TIMING_COLUMNS};

fn scratch(name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("prehensile-batch-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn batch(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_prehensile"));
    c.arg("batch").args(args);
    c
}

fn text(batch: &RecordBatch, column: &str, row: usize) -> Option<String> {
    let a = batch
        .column_by_name(column)
        .unwrap()
        .as_any()
        .downcast_ref::<StringArray>()
        .unwrap();
    (!a.is_null(row)).then(|| a.value(row).to_string())
}

/// Every row by its key (hand, object, movement, shoulder, seed), with every other column but
/// the timings rendered as text; fails on a duplicate key.
fn rows_by_key(folder: &Path) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for b in read_rows(folder).unwrap() {
        let seeds = b
            .column_by_name("seed")
            .unwrap()
            .as_any()
            .downcast_ref::<UInt64Array>()
            .unwrap();
        for r in 0..b.num_rows() {
            let key = format!(
                "{:?} {:?} {:?} {:?} {}",
                text(&b, "hand", r),
                text(&b, "object", r),
                text(&b, "movement_requested", r),
                text(&b, "shoulder_choice", r),
                seeds.value(r)
            );
            let values: Vec<String> = b
                .schema()
                .fields()
                .iter()
                .enumerate()
                .filter(|(_, f)| !TIMING_COLUMNS.contains(&f.name().as_str()))
                .map(|(i, _)| {
                    let one = b.column(i).slice(r, 1);
                    format!("{one:?}")
                })
                .collect();
            assert!(
                out.insert(key.clone(), values.join("|")).is_none(),
                "{key} twice"
            );
        }
    }
    out
}

fn parts(folder: &Path) -> usize {
    std::fs::read_dir(folder)
        .unwrap()
        .filter(|e| {
            let n = e.as_ref().unwrap().file_name();
            let n = n.to_string_lossy();
            n.starts_with("part-") && n.ends_with(".parquet")
        })
        .count()
}

#[test]
fn a_batch_killed_midway_resumes_without_lost_or_duplicated_rows() {
    let common = [
        "--hands",
        "human",
        "robot3",
        "--objects",
        "sphere",
        "box",
        "cylinder",
        "--seeds",
        "4",
        "--flush-rows",
        "1",
        "--threads",
        "2",
    ];
    // The same batch without interruption, as the reference.
    let whole = scratch("whole");
    let status = batch(&common)
        .args(["--out", whole.to_str().unwrap()])
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    let reference = rows_by_key(&whole);
    assert_eq!(reference.len(), 2 * 3 * 4);

    let cut = scratch("cut");
    let mut child = batch(&common)
        .args(["--out", cut.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let began = Instant::now();
    while parts(&cut) < 3 && began.elapsed() < Duration::from_secs(120) {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let _ = child.kill(); // SIGKILL: no chance to tidy up
    child.wait().unwrap();
    let before = rows_by_key(&cut).len();
    assert!(
        before >= 3 && before < reference.len(),
        "the kill came after {before} rows of {}",
        reference.len()
    );
    let resumed = batch(&common)
        .args(["--out", cut.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(resumed.status.success());
    let said = String::from_utf8_lossy(&resumed.stdout);
    assert!(
        said.contains(&format!("{} were already there", before)),
        "{said}"
    );
    // Same keys, and the same rows: the search depends only on its inputs and seed.
    assert_eq!(rows_by_key(&cut), reference);
    // No partial part is left behind.
    assert!(std::fs::read_dir(&cut).unwrap().all(|e| !e
        .unwrap()
        .file_name()
        .to_string_lossy()
        .ends_with(".partial")));
}

#[test]
fn unreadable_meshes_and_hands_become_error_rows_and_the_batch_goes_on() {
    let dir = scratch("bad");
    let objects = dir.join("objects");
    std::fs::create_dir_all(&objects).unwrap();
    std::fs::write(objects.join("broken.obj"), "v 0 0 0\nf 1 2 3\n").unwrap();
    std::fs::write(objects.join("empty.stl"), "").unwrap();
    std::fs::write(
        objects.join("cube.obj"),
        "v 0 0 0\nv 0.05 0 0\nv 0.05 0.05 0\nv 0 0.05 0\nv 0 0 0.05\nv 0.05 0 0.05\nv 0.05 0.05 0.05\nv 0 0.05 0.05\n\
         f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n",
    )
    .unwrap();
    std::fs::write(dir.join("notes.txt"), "not a mesh").unwrap();
    let hand = dir.join("bad_hand.toml");
    std::fs::write(&hand, "name = 3").unwrap();
    let out = dir.join("dataset");
    let run = batch(&[
        "--hands",
        "human",
        hand.to_str().unwrap(),
        "--objects",
        objects.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
    .output()
    .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let mut statuses = BTreeMap::new();
    for b in read_rows(&out).unwrap() {
        for r in 0..b.num_rows() {
            let object = text(&b, "object", r).unwrap();
            let hand = text(&b, "hand", r).unwrap();
            let file = Path::new(&object)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            let hand = if hand == "human" { "human" } else { "bad" };
            statuses.insert(
                (hand, file),
                (text(&b, "status", r).unwrap(), text(&b, "reason", r)),
            );
        }
    }
    assert_eq!(statuses.len(), 6, "{statuses:?}");
    let (status, reason) = &statuses[&("human", "cube.obj".to_string())];
    assert_eq!(status, "valid", "{reason:?}");
    for file in ["broken.obj", "empty.stl"] {
        let (status, reason) = &statuses[&("human", file.to_string())];
        assert_eq!(status, "error");
        assert!(reason.as_ref().unwrap().contains(file), "{reason:?}");
    }
    let (status, reason) = &statuses[&("bad", "cube.obj".to_string())];
    assert_eq!(status, "error");
    assert!(
        reason.as_ref().unwrap().contains("bad_hand.toml"),
        "{reason:?}"
    );
}

#[test]
fn a_folder_made_with_other_inputs_is_not_mixed_into() {
    let out = scratch("mismatch");
    let first = batch(&["--objects", "sphere", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(first.status.success());
    let second = batch(&["--objects", "box", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(second.status.code(), Some(2));
    let err = String::from_utf8_lossy(&second.stderr);
    assert!(err.contains("objects differ"), "{err}");
    // A folder with other files and no manifest is not taken over either.
    let other = scratch("other");
    std::fs::write(other.join("thesis.pdf"), "x").unwrap();
    let third = batch(&["--objects", "sphere", "--out", other.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(third.status.code(), Some(2));
    let err = String::from_utf8_lossy(&third.stderr);
    assert!(err.contains("thesis.pdf"), "{err}");
}

#[test]
fn a_dataset_folder_that_vanishes_mid_run_stops_the_batch_with_a_message() {
    let out = scratch("vanish");
    let child = batch(&[
        "--objects",
        "sphere",
        "box",
        "cylinder",
        "--seeds",
        "6",
        "--flush-rows",
        "1",
        "--threads",
        "1",
        "--out",
        out.to_str().unwrap(),
    ])
    .stdout(Stdio::null())
    .stderr(Stdio::piped())
    .spawn()
    .unwrap();
    let began = Instant::now();
    while parts(&out) < 1 && began.elapsed() < Duration::from_secs(120) {
        std::thread::sleep(Duration::from_millis(5));
    }
    // As a full disk or a lost mount would: the next part cannot be written. (The writer may
    // add a file while the folder is being removed; try again until it is gone.)
    while std::fs::remove_dir_all(&out).is_err() {
        std::thread::sleep(Duration::from_millis(1));
    }
    let output = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{err}");
    assert!(
        err.contains("part-0000") && err.contains("No such file") && !err.contains("panicked"),
        "{err}"
    );
}
