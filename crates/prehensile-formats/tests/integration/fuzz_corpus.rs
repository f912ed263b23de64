//! Replays the fuzzing seeds (`fuzz/seeds/<target>/`, small real files, all accepted) and every
//! input a fuzzer found a bug with (`fuzz/regressions/<target>/`) through the readers on stable
//! Rust: none may panic. A local fuzzing corpus (`fuzz/corpus/`, not committed) is replayed too
//! when present. (`gltf_structured` inputs are encoded for its generator: the GLB each crash
//! stood for is saved under `regressions/mesh_gltf`.)

use std::path::Path;

use prehensile_testkit::fuzz_entry::{run, TARGETS};

fn inputs(folder: &str, target: &str) -> Vec<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz")
        .join(folder)
        .join(target);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Vec::new();
    };
    let mut files: Vec<_> = entries.map(|e| e.unwrap().path()).collect();
    files.sort();
    files
}

#[test]
fn every_seed_regression_and_corpus_input_is_read_without_panicking() {
    let (mut seeds, mut others) = (0, 0);
    for target in TARGETS {
        for file in inputs("seeds", target) {
            let data = std::fs::read(&file).unwrap();
            seeds += 1;
            assert!(
                run(target, &data).unwrap(),
                "seed {} is refused",
                file.display()
            );
        }
        for file in [inputs("regressions", target), inputs("corpus", target)].concat() {
            // A running fuzzer may have replaced a corpus file meanwhile.
            let Ok(data) = std::fs::read(&file) else {
                continue;
            };
            others += 1;
            run(target, &data).unwrap();
        }
    }
    assert!(seeds >= TARGETS.len(), "{seeds} seeds");
    eprintln!(
        "{seeds} seeds accepted, {others} regressions and corpus inputs read without panicking"
    );
}
