#!/usr/bin/env bash
# A library user's debug build (docs/PERFORMANCE.md): a program outside this workspace that
# depends on prehensile-core by path, built with `cargo build` (the dev profile, dependencies at
# opt-level 0), then again with prehensile-core optimized by the user's own manifest; each runs
# the human hand's power grasp of the built-in sphere twice and prints setup and search times.
# Run from anywhere: bash tools/benchmark/debug_build_user.sh
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/src"
cat > "$work/src/main.rs" <<'RUST'
use prehensile_core::math::Vec3;
use prehensile_core::search::{default_shoulder, GraspPlanner, SearchParams};
use prehensile_core::{shapes, ObjectModel};
use std::time::Instant;

fn main() {
    let t = Instant::now();
    let mesh = shapes::builtin_object("sphere").unwrap();
    let object = ObjectModel::new("sphere", mesh, None).unwrap();
    let setup = t.elapsed();
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let movement = hand.movement("power").unwrap();
    let shoulder = default_shoulder(&hand, &object.center_of_mass(), &Vec3::z());
    let t = Instant::now();
    let params = SearchParams { seed: 1, ..Default::default() };
    let mut planner = GraspPlanner::new(&hand, &object, movement, shoulder, params).unwrap();
    planner.run_to_end();
    println!(
        "  setup {:.1} ms, search {:.1} ms, valid {}",
        setup.as_secs_f64() * 1e3,
        t.elapsed().as_secs_f64() * 1e3,
        planner.best().is_some()
    );
}
RUST
manifest() {
  cat > "$work/Cargo.toml" <<TOML
[package]
name = "debug-build-user"
version = "0.1.0"
edition = "2021"

[dependencies]
prehensile-core = { path = "$root/crates/prehensile-core" }
prehensile-formats = { path = "$root/crates/prehensile-formats" }
$1
TOML
}
manifest ""
(cd "$work" && cargo build --quiet)
echo "plain cargo build (dependencies at opt-level 0):"
"$work/target/debug/debug-build-user"
"$work/target/debug/debug-build-user"
manifest $'\n[profile.dev.package.prehensile-core]\nopt-level = 3'
(cd "$work" && cargo build --quiet)
echo "with [profile.dev.package.prehensile-core] opt-level = 3:"
"$work/target/debug/debug-build-user"
"$work/target/debug/debug-build-user"
