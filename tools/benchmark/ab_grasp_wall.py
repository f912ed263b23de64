"""Two `prehensile` builds' whole `grasp` runs (process start to exit) timed side by side, the
builds alternating run by run, reported as medians of wall time per object (docs/PERFORMANCE.md).

Build the CLI in two checkouts (for instance `git worktree add ../before HEAD~1`), then:
    python3 tools/benchmark/ab_grasp_wall.py BEFORE/target/release/prehensile \\
        target/release/prehensile [--objects bread milk ...] [--rounds N]
An object is a robosuite scan's short name (assets/objects/robosuite_NAME.*), a built-in object
or a mesh path. Standard library only.
"""
import argparse
import pathlib
import statistics
import subprocess
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


def wall_ms(binary, mesh, seed, movement):
    start = time.perf_counter()
    subprocess.run(
        [binary, "grasp", "--object", mesh, "--movement", movement, "--seed", str(seed),
         "--out", "/dev/null"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    return (time.perf_counter() - start) * 1e3


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("a", help="prehensile binary A (e.g. the build before a change)")
    parser.add_argument("b", help="prehensile binary B (e.g. the build after it)")
    parser.add_argument("--objects", nargs="+", default=["bread", "milk", "cereal", "can"])
    parser.add_argument("--seeds", nargs="+", type=int, default=[1, 2, 3])
    parser.add_argument("--movement", default="power")
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    for name in args.objects:
        mesh = object_argument(name)
        times = {args.a: [], args.b: []}
        for _ in range(args.rounds):
            for seed in args.seeds:
                for binary in (args.a, args.b):
                    times[binary].append(wall_ms(binary, mesh, seed, args.movement))
        a, b = (statistics.median(times[x]) for x in (args.a, args.b))
        print(f"{name:10} A {a:7.1f} ms   B {b:7.1f} ms   B/A {b / a:.2f}")


if __name__ == "__main__":
    main()
