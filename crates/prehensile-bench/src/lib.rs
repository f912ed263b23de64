//! Nothing but a home for the workspace's criterion benchmarks (`benches/`); run them with
//! `cargo bench -p prehensile-bench --bench <name>` (docs/PERFORMANCE.md lists what each measures).
#![deny(missing_docs)]
