//! The thesis's timing table (§6.6, combinations a–h of P, v and N) and whole grasps.
//!
//! Run: `cargo bench -p prehensile-bench --bench search`. The thesis's v (TranslateToFree
//! placements per pose) is set through the step length; the realised mean is printed.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use prehensile_core::finger_closing::ClosingParams;
use prehensile_core::math::Point3;
use prehensile_core::search::{GraspPlanner, SearchParams, StepKind, TranslateMode};
use prehensile_core::{shapes, HandModel, ObjectModel};

fn torus16k() -> ObjectModel {
    ObjectModel::new("torus16k", shapes::torus(0.045, 0.014, 128, 64), None).unwrap()
}

const SHOULDER: [f64; 3] = [-0.35, -0.2, 0.35];

fn params(step: StepKind, translate_step: f64, n: u32, seed: u64) -> SearchParams {
    SearchParams {
        step,
        seed,
        translate: TranslateMode::Steps {
            step: translate_step,
        },
        closing: ClosingParams {
            interpolations: n,
            ..Default::default()
        },
        ..Default::default()
    }
}

/// Steps of one whole human power search, start to converged, from [`SHOULDER`].
fn whole_search(hand: &HandModel, object: &ObjectModel, params: SearchParams) -> u32 {
    let movement = hand.movement("power").unwrap();
    let mut planner =
        GraspPlanner::new(hand, object, movement, Point3::from(SHOULDER), params).unwrap();
    planner.run_to_end();
    planner.stats().steps
}

/// Over 40 steps from 10 seeds: mean placements per evaluated pose, queries per step, and the
/// share of steps that place no candidate (every candidate beyond the wrist's range: the
/// random angle reaches 180°, so such a step costs microseconds and the step's mean time is an
/// average of those and of steps that place and close the hand).
fn counts(hand: &HandModel, object: &ObjectModel, p: &SearchParams) -> (f64, f64, f64) {
    let movement = hand.movement("power").unwrap();
    let (mut placements, mut evaluations, mut queries, mut steps) = (0u64, 0u64, 0u64, 0u64);
    let mut placing_nothing = 0u64;
    for seed in 0..10 {
        let mut planner = GraspPlanner::new(
            hand,
            object,
            movement,
            Point3::from(SHOULDER),
            SearchParams { seed, ..p.clone() },
        )
        .unwrap();
        while planner.restarting() {
            planner.slice();
        }
        for _ in 0..4 {
            let before = planner.stats();
            planner.step();
            let after = planner.stats();
            placements += after.placements - before.placements;
            evaluations += after.evaluations - before.evaluations;
            queries += after.collision_queries - before.collision_queries;
            steps += (after.steps - before.steps) as u64;
            placing_nothing += u64::from(after.placements == before.placements);
        }
    }
    (
        placements as f64 / evaluations.max(1) as f64,
        queries as f64 / steps.max(1) as f64,
        placing_nothing as f64 / steps.max(1) as f64,
    )
}

fn bench(c: &mut Criterion) {
    let hand = prehensile_formats::builtin_hand("human").unwrap();
    let object = torus16k();
    thesis_table(c, &hand, &object);
    let sphere =
        ObjectModel::new("sphere", shapes::builtin_object("sphere").unwrap(), None).unwrap();
    whole_grasps(c, &hand, &object, &sphere);
    stability_judging(c, &hand, &object, &sphere);
}

/// The thesis's §6.6 table: one optimization step of each combination a–h.
fn thesis_table(c: &mut Criterion, hand: &HandModel, object: &ObjectModel) {
    let movement = hand.movement("power").unwrap();
    // (name, P, v target -> step length, N, the thesis's T_AVG in ms)
    let table = [
        ("a", StepKind::SevenPose, 7, 10, 11.0),
        ("b", StepKind::SevenPose, 7, 20, 17.0),
        ("c", StepKind::SevenPose, 10, 10, 13.0),
        ("d", StepKind::SevenPose, 10, 20, 19.5),
        ("e", StepKind::Unidirectional, 7, 10, 5.5),
        ("f", StepKind::Unidirectional, 7, 20, 9.5),
        ("g", StepKind::Unidirectional, 10, 10, 6.5),
        ("h", StepKind::Unidirectional, 10, 20, 9.5),
    ];
    // Step lengths that give about 7 and 10 placements per pose on this object.
    let step_for_v = |v: u32| if v == 7 { 0.0045 } else { 0.003 };
    let mut group = c.benchmark_group("thesis_table_step");
    for (name, kind, v, n, thesis_ms) in table {
        let p = params(kind, step_for_v(v), n, 0);
        let (v_real, queries, placing_nothing) = counts(hand, object, &p);
        eprintln!(
            "{name}: P={} v={v} (measured {v_real:.1}) N={n}: {queries:.0} capsule queries per step (thesis model P*nb*(v+N) = {}), {:.0}% of steps place nothing, thesis T_AVG {thesis_ms} ms",
            kind.poses(),
            kind.poses() as u32 * 24 * (v + n),
            100.0 * placing_nothing
        );
        // Row c also on two threads (the step's candidates shared out on rayon's pool), and with
        // every candidate's stability judged (`SearchParams::lazy_stability` off).
        let variants: &[(usize, bool)] = if name == "c" {
            &[(1, true), (2, true), (1, false)]
        } else {
            &[(1, true)]
        };
        for &(threads, lazy_stability) in variants {
            let label = match (threads, lazy_stability) {
                (1, true) => format!("{name}_P{}_v{v}_N{n}", kind.poses()),
                (1, false) => format!("{name}_P{}_v{v}_N{n}_every_candidate", kind.poses()),
                (t, _) => format!("{name}_P{}_v{v}_N{n}_threads{t}", kind.poses()),
            };
            let mut seed = 0;
            group.bench_function(label, |b| {
                b.iter_batched(
                    || {
                        seed += 1;
                        let p = SearchParams {
                            threads,
                            lazy_stability,
                            ..params(kind, step_for_v(v), n, seed)
                        };
                        let mut planner =
                            GraspPlanner::new(hand, object, movement, Point3::from(SHOULDER), p)
                                .unwrap();
                        // The start (initial approximation) is setup, not a step: the planner
                        // does it in slices of its first steps, so finish it here.
                        while planner.restarting() {
                            planner.slice();
                        }
                        planner
                    },
                    |mut planner| planner.step(),
                    BatchSize::SmallInput,
                )
            });
        }
    }
    group.finish();
}

/// Whole power grasps, start to converged, on one thread and two.
fn whole_grasps(c: &mut Criterion, hand: &HandModel, object: &ObjectModel, sphere: &ObjectModel) {
    let mut group = c.benchmark_group("whole_grasp");
    for ((label, obj), threads) in [("torus16k", object), ("sphere", sphere)]
        .into_iter()
        .flat_map(|o| [(o, 1), (o, 2)])
    {
        let mut seed = 0;
        let name = match threads {
            1 => format!("human_power_{label}_start_to_converged"),
            t => format!("human_power_{label}_start_to_converged_threads{t}"),
        };
        group.bench_function(name, |b| {
            b.iter(|| {
                seed += 1;
                let p = SearchParams {
                    seed,
                    threads,
                    ..Default::default()
                };
                whole_search(hand, obj, p)
            })
        });
    }
    group.finish();
}

/// Side by side in one run: whole power grasps (seeds 1-6 in turn, so each side sees the same
/// searches) with every candidate's stability judged and with it judged lazily.
fn stability_judging(
    c: &mut Criterion,
    hand: &HandModel,
    object: &ObjectModel,
    sphere: &ObjectModel,
) {
    let mut group = c.benchmark_group("stability_judging");
    for (label, obj) in [("torus16k", object), ("sphere", sphere)] {
        for lazy_stability in [false, true] {
            let mut seed = 0;
            let how = if lazy_stability {
                "lazy"
            } else {
                "every_candidate"
            };
            group.bench_function(format!("human_power_{label}_{how}"), |b| {
                b.iter(|| {
                    seed = seed % 6 + 1;
                    let p = SearchParams {
                        seed,
                        lazy_stability,
                        ..Default::default()
                    };
                    whole_search(hand, obj, p)
                })
            });
        }
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
