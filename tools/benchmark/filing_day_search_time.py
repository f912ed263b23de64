"""Search time per grasp against the build issue 13 was filed on (6eb4c05: the thesis's rules,
the Shadow hand's only movement `close`), side by side with today's, alternating runs: the
human hand's power grasp in both, the Shadow hand's `close` then and `power` now; ten objects,
seeds 1-3, medians of the result's `stats.seconds` (docs/QUALITY.md, session 28).

    git worktree add ../filed 6eb4c05 && (cd ../filed && cargo build --release -p prehensile-cli)
    python3 tools/benchmark/filing_day_search_time.py ../filed/target/release/prehensile \\
        target/release/prehensile [ROUNDS]

The old CLI has no `--threads` and searched on one thread; today's is given `--threads 1`.
Standard library only.
"""
import json
import pathlib
import statistics
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools/quality"))
from grasp_survey import OBJECTS  # noqa: E402

SHADOW = str(ROOT / "assets/hands/shadow_hand/reach.xml")
# (hand, movement on the filing day, movement today)
CASES = [("human", "power", "power"), (SHADOW, "close", "power")]
SEEDS = [1, 2, 3]


def search(binary, hand, movement, obj, seed, today):
    """(milliseconds of search, valid) of one grasp, or None if it wrote no result."""
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        args = [binary, "grasp", "--hand", hand, "--object", obj, "--movement", movement,
                "--seed", str(seed), "--out", out.name]
        if today:
            args += ["--threads", "1"]
        subprocess.run(args, capture_output=True, text=True, cwd=ROOT)
        try:
            result = json.loads(pathlib.Path(out.name).read_text())
        except (OSError, ValueError):
            return None
    return result["stats"]["seconds"] * 1000, result["valid"]


def main():
    old, new = sys.argv[1], sys.argv[2]
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 2
    for hand, then, now in CASES:
        print(f"{pathlib.Path(hand).name}: {then} then, {now} now")
        all_old, all_new = [], []
        for obj in OBJECTS:
            runs = {False: [], True: []}
            for _ in range(rounds):
                for seed in SEEDS:
                    for today, binary, movement in ((False, old, then), (True, new, now)):
                        found = search(binary, hand, movement, obj, seed, today)
                        if found:
                            runs[today].append(found)
            a = [ms for ms, _ in runs[False]]
            b = [ms for ms, _ in runs[True]]
            all_old += a
            all_new += b
            valid = [sum(v for _, v in runs[t]) for t in (False, True)]
            ma, mb = statistics.median(a), statistics.median(b)
            print(f"  {pathlib.Path(obj).name:24s} then {ma:7.1f} ms (valid {valid[0]}/{len(a)})"
                  f"  now {mb:7.1f} ms (valid {valid[1]}/{len(b)})  {mb / ma:5.2f}x")
        ma, mb = statistics.median(all_old), statistics.median(all_new)
        print(f"  every search: median then {ma:.1f} ms, now {mb:.1f} ms: {mb / ma:.2f}x")


if __name__ == "__main__":
    main()
