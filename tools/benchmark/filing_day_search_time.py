"""Search time per grasp against the build issue 13 was filed on (6eb4c05: the thesis's rules,
the Shadow hand's only movement `close`), side by side with today's, alternating runs: the
human hand's power grasp in both, the Shadow hand's `close` then and `power` now; ten objects,
seeds 1-3, medians of the result's `stats.seconds` and of the whole run's wall time (the build
of the filing day filled its distance grid while setting the object up, outside the search's
time; today's fills it as the search reads it, inside) (docs/QUALITY.md, session 28).

    git worktree add ../filed 6eb4c05 && (cd ../filed && cargo build --release -p prehensile-cli)
    python3 tools/benchmark/filing_day_search_time.py ../filed/target/release/prehensile \\
        target/release/prehensile [ROUNDS] [SHADOW_MOVEMENT] [--thesis-rules]

SHADOW_MOVEMENT is the Shadow hand's movement today (default power; `close` compares the
filing day's movement with itself). `--thesis-rules` searches today's build under the thesis's
validity rules (`--validity thesis`), the filing day's: with `close` for the Shadow hand, both
builds then do the same task, and what is left of the ratio is what the search's machinery
costs (docs/QUALITY.md, session 33). `--fill-grid` fills today's distance grid before its
search (`prehensile grasp --fill-grid`), as the filing day's setup filled its own: both searches
then read a filled grid, and their timers time the same kind of work (docs/QUALITY.md,
session 37). Whole runs are then no longer comparable (today's fills every node, not only
those its search reads).

The old CLI has no `--threads` and searched on one thread; today's is given `--threads 1`.
Needs numpy and scipy (the object list comes from tools/quality/grasp_survey.py, which imports
them).
"""
import argparse
import json
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools/quality"))
from grasp_survey import OBJECTS  # noqa: E402

SHADOW = str(ROOT / "assets/hands/shadow_hand/reach.xml")
SEEDS = [1, 2, 3]


def search(binary, hand, movement, obj, seed, today, extra):
    """(milliseconds of search, valid, milliseconds of the whole run) of one grasp, or None if it
    wrote no result. `extra` are today's further arguments."""
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        args = [binary, "grasp", "--hand", hand, "--object", obj, "--movement", movement,
                "--seed", str(seed), "--out", out.name]
        if today:
            args += ["--threads", "1", *extra]
        began = time.perf_counter()
        subprocess.run(args, capture_output=True, text=True, cwd=ROOT)
        wall = (time.perf_counter() - began) * 1000
        try:
            result = json.loads(pathlib.Path(out.name).read_text())
        except (OSError, ValueError):
            return None
    return result["stats"]["seconds"] * 1000, result["valid"], wall


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("old", help="the filing day's CLI (6eb4c05)")
    parser.add_argument("new", help="today's CLI")
    parser.add_argument("rounds", nargs="?", type=int, default=2, help="runs of every seed")
    parser.add_argument("shadow_now", nargs="?", default="power",
                        help="the Shadow hand's movement today")
    parser.add_argument("--thesis-rules", action="store_true",
                        help="search today's build under the thesis's validity rules")
    parser.add_argument("--fill-grid", action="store_true",
                        help="fill today's distance grid before its search, as the filing day's")
    options = parser.parse_args()
    old, new, rounds, shadow_now = options.old, options.new, options.rounds, options.shadow_now
    extra = ["--validity", "thesis"] if options.thesis_rules else []
    extra += ["--fill-grid"] if options.fill_grid else []
    # (hand, movement on the filing day, movement today)
    cases = [("human", "power", "power"), (SHADOW, "close", shadow_now)]
    for hand, then, now in cases:
        print(f"{pathlib.Path(hand).name}: {then} then, {now} now (search ms, whole run ms)")
        every = {False: [], True: []}
        for obj in OBJECTS:
            runs = {False: [], True: []}
            for _ in range(rounds):
                for seed in SEEDS:
                    for today, binary, movement in ((False, old, then), (True, new, now)):
                        found = search(binary, hand, movement, obj, seed, today, extra)
                        if found:
                            runs[today].append(found)
            for today in (False, True):
                every[today] += runs[today]
            line = f"  {pathlib.Path(obj).name:24s}"
            for today, label in ((False, "then"), (True, "now")):
                r = runs[today]
                valid = sum(v for _, v, _ in r)
                line += (f" {label} {median(r, 0):7.1f} / {median(r, 2):7.1f} ms"
                         f" (valid {valid}/{len(r)})")
            line += (f"  {median(runs[True], 0) / median(runs[False], 0):5.2f}x /"
                     f" {median(runs[True], 2) / median(runs[False], 2):5.2f}x")
            print(line)
        print(f"  every run: search {median(every[False], 0):.1f} -> {median(every[True], 0):.1f} ms"
              f" ({median(every[True], 0) / median(every[False], 0):.2f}x), whole run"
              f" {median(every[False], 2):.1f} -> {median(every[True], 2):.1f} ms"
              f" ({median(every[True], 2) / median(every[False], 2):.2f}x)")


def median(runs, field):
    """The median of one field of `runs`."""
    return statistics.median(r[field] for r in runs)


if __name__ == "__main__":
    main()
