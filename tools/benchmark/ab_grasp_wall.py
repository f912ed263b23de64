"""Two `prehensile` builds' whole `grasp` runs (process start to exit) timed side by side, the
builds alternating run by run, reported as medians of wall time per object, and of the search's
own time (the result's `stats.seconds`) (docs/PERFORMANCE.md).

Build the CLI in two checkouts (for instance `git worktree add ../before HEAD~1`), then:
    python3 tools/benchmark/ab_grasp_wall.py BEFORE/target/release/prehensile \\
        target/release/prehensile [--hand H] [--objects bread milk ...] [--rounds N]
An object is a robosuite scan's short name (assets/objects/robosuite_NAME.*), a built-in object
or a mesh path. Standard library only.
"""
import argparse
import json
import pathlib
import statistics
import subprocess
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILT_IN = {"sphere", "box", "cylinder", "torus", "mug"}


def object_argument(name):
    if name in BUILT_IN or pathlib.Path(name).is_file():
        return name
    found = sorted((ROOT / "assets/objects").glob(f"robosuite_{name}.*"))
    if not found:
        raise SystemExit(f"no object '{name}': give a built-in name, a robosuite scan or a path")
    return str(found[0])


def timed_grasp(binary, hand, mesh, seed, movement, threads, out):
    """Wall time of one `grasp` run and its search time, milliseconds."""
    command = [binary, "grasp", "--hand", hand, "--object", mesh, "--movement", movement,
               "--seed", str(seed), "--out", out]
    if threads:
        command += ["--threads", str(threads)]
    start = time.perf_counter()
    subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    wall = (time.perf_counter() - start) * 1e3
    with open(out, encoding="utf-8") as f:
        return wall, json.load(f)["stats"]["seconds"] * 1e3


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("a", help="prehensile binary A (e.g. the build before a change)")
    parser.add_argument("b", help="prehensile binary B (e.g. the build after it)")
    parser.add_argument("--objects", nargs="+", default=["bread", "milk", "cereal", "can"])
    parser.add_argument("--seeds", nargs="+", type=int, default=[1, 2, 3])
    parser.add_argument("--hand", default="human", help="passed on as --hand")
    parser.add_argument("--movement", default="power")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--threads", type=int, help="passed on as --threads (default: the CLI's)")
    args = parser.parse_args()
    out = str(pathlib.Path(tempfile.mkdtemp()) / "result.json")
    print(f"{'':10}   wall: A        B    B/A | search: A        B    B/A")
    for name in args.objects:
        mesh = object_argument(name)
        times = {args.a: [], args.b: []}
        for _ in range(args.rounds):
            for seed in args.seeds:
                for binary in (args.a, args.b):
                    times[binary].append(
                        timed_grasp(binary, args.hand, mesh, seed, args.movement, args.threads,
                                    out))
        (wa, sa), (wb, sb) = (
            tuple(statistics.median(t[k] for t in times[x]) for k in (0, 1))
            for x in (args.a, args.b))
        print(f"{name:10} {wa:7.1f} ms {wb:7.1f} ms {wb / wa:5.2f} | "
              f"{sa:7.1f} ms {sb:7.1f} ms {sb / sa:5.2f}")
    pathlib.Path(out).unlink(missing_ok=True)
    pathlib.Path(out).parent.rmdir()


if __name__ == "__main__":
    main()
