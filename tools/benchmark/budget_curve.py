"""What a time budget buys: `prehensile grasp --budget-ms B` against the same search run to its
stop rule, for a game or VR developer who must have a grasp within a frame or a few.

For each hand (human and the Shadow hand by default), the ten objects of
tools/quality/grasp_survey.py and seeds 1-3, runs the search once without a budget and once per
budget (default 5, 10, 20 and 40 ms), and reports per budget: how many searches return a valid
grasp, how many of those push the object from every side (no open half-space holds every
contact normal; the same linear program as grasp_survey.py), how far the quality falls short of
the unbudgeted search's where both chose the same movement (qualities of different movements
are different formulas; median and worst, in the units of the result's `quality`), and the
medians of the request's search time (all its movements, as the CLI prints it) and of the whole
run's wall time (docs/PERFORMANCE.md).

    cargo build --release -p prehensile-cli
    python3 tools/benchmark/budget_curve.py [--cli BIN] [--movement auto] [--threads N]
        [--budgets 5 10 20 40] [--hands human assets/hands/shadow_hand/reach.xml]

Needs numpy and scipy (through grasp_survey.py).
"""
import argparse
import json
import pathlib
import re
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools/quality"))
from grasp_survey import OBJECTS, one_sided  # noqa: E402

SHADOW = "assets/hands/shadow_hand/reach.xml"
SEEDS = [1, 2, 3]


def grasp(cli, hand, obj, seed, options, budget):
    """The result of one search (with `budget` milliseconds, or none), the request's search
    milliseconds and the whole run's; None if it wrote no result."""
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        args = [cli, "grasp", "--hand", hand, "--object", obj, "--movement", options.movement,
                "--seed", str(seed), "--out", out.name]
        if options.threads:
            args += ["--threads", str(options.threads)]
        if budget is not None:
            args += ["--budget-ms", str(budget)]
        began = time.perf_counter()
        run = subprocess.run(args, capture_output=True, text=True, cwd=ROOT)
        wall = (time.perf_counter() - began) * 1000
        searched = re.search(r"search ([0-9.]+) ms", run.stderr)
        try:
            result = json.loads(pathlib.Path(out.name).read_text())
        except (OSError, ValueError):
            return None
        return result, float(searched.group(1)) if searched else float("nan"), wall


def summary(label, runs, full):
    """One line for the runs of one budget; `full` maps each case to its unbudgeted result."""
    valid = [(case, r) for case, (r, _, _) in runs.items() if r["valid"]]
    every_side = sum(not one_sided([c["normal"] for c in r["contacts"]]) for _, r in valid)
    shortfall = [full[case]["quality"] - r["quality"] for case, r in valid
                 if full[case]["valid"] and full[case]["movement"] == r["movement"]]
    search = statistics.median(s for _, s, _ in runs.values())
    wall = statistics.median(w for _, _, w in runs.values())
    worst = max(shortfall) if shortfall else 0.0
    middle = statistics.median(shortfall) if shortfall else 0.0
    return (f"  {label:>9}: valid {len(valid):2d}/{len(runs)}, pushing from every side"
            f" {every_side:2d}; quality short of the unbudgeted by {middle:.3f} (median),"
            f" {worst:.3f} (worst) in {len(shortfall)} with its movement; search"
            f" {search:5.1f} ms, whole run {wall:5.1f} ms (medians)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cli", default=str(ROOT / "target/release/prehensile"))
    parser.add_argument("--movement", default="auto")
    parser.add_argument("--threads", type=int, help="the CLI's default (one per core) if unset")
    parser.add_argument("--budgets", type=float, nargs="+", default=[5, 10, 20, 40])
    parser.add_argument("--hands", nargs="+", default=["human", SHADOW])
    options = parser.parse_args()
    for hand in options.hands:
        print(f"{pathlib.Path(hand).name}, movement {options.movement}:")
        runs = {budget: {} for budget in [None, *options.budgets]}
        for obj in OBJECTS:
            for seed in SEEDS:
                # Alternate budgets case by case, so the machine's drift touches them alike.
                for budget in runs:
                    found = grasp(options.cli, hand, obj, seed, options, budget)
                    if found:
                        runs[budget][(obj, seed)] = found
        full = {case: r for case, (r, _, _) in runs[None].items()}
        for budget, by_case in runs.items():
            by_case = {case: found for case, found in by_case.items() if case in full}
            print(summary("no budget" if budget is None else f"{budget:g} ms", by_case, full))


if __name__ == "__main__":
    main()
