"""Two builds of `examples/step_timing.rs` timed side by side in alternating pairs, reported as the
median ratio of their step times (docs/PERFORMANCE.md: how this machine's drift is cancelled).

Build the example in two checkouts (for instance `git worktree add ../before HEAD~1`), then:
    python3 tools/benchmark/ab_step_timing.py BEFORE/target/release/examples/step_timing \\
        target/release/examples/step_timing [--hand HAND] [--dt DT] [--pairs N] [--engine E]
Each pair is 1000 steps of A then 1000 of B, each timed as the median of blocks of 100 steps; the
ratio A/B above 1 means B is faster. Standard library only.
"""
import argparse
import pathlib
import statistics

from step_timing_client import StepTiming

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("a", help="step_timing binary A (e.g. the build before a change)")
    parser.add_argument("b", help="step_timing binary B (e.g. the build after it)")
    parser.add_argument("--hand", default=str(ROOT / "assets/hands/shadow_hand/reach.xml"))
    parser.add_argument("--dt", default="0.001", help="step length, seconds")
    parser.add_argument("--pairs", type=int, default=30)
    parser.add_argument("--engine", default="reduced", choices=["rapier", "reduced"])
    args = parser.parse_args()
    if args.pairs < 2:
        parser.error("--pairs must be at least 2")
    a, b = (StepTiming(binary, args.hand, [args.dt], engine=args.engine)
            for binary in (args.a, args.b))
    a.step_us(args.dt, 2000)  # warm up both
    b.step_us(args.dt, 2000)
    times_a, times_b = [], []
    for _ in range(args.pairs):
        times_a.append(a.step_us(args.dt, 1000))
        times_b.append(b.step_us(args.dt, 1000))
    ratios = [x / y for x, y in zip(times_a, times_b)]
    low, _, high = statistics.quantiles(ratios, n=4)
    print(
        f"A {statistics.median(times_a):.1f} µs/step, B {statistics.median(times_b):.1f} µs/step;"
        f" A/B median {statistics.median(ratios):.3f} (quartiles {low:.3f}–{high:.3f})"
    )


if __name__ == "__main__":
    main()
