"""Survey of grasp validity and stability across hands, objects, movements and seeds.

Runs `prehensile grasp` for every combination under each validity rule asked for (default: `holds`,
the default rule, `strict` and `thesis`) and reports, per rule: how many searches return a valid
grasp, how many of those are in force closure (from the result's own `stability`, computed with
the full 8-edge cone and Qhull-checked hull), and how many have every contact normal on one side of a plane (a hand that only
pushes the object one way: found by a small linear program with scipy), and how many of the
valid grasps the hold test (`--hold`, on the simulation's default engine: squeeze with grip strength 0.5, then gravity along each
axis direction for 1 s) holds in at least 5 of 6 directions and against gravity along -z.

Run from the repository root after `cargo build --release -p prehensile-cli`:
    pip install scipy numpy
    python3 tools/quality/grasp_survey.py > /tmp/survey.txt
    python3 tools/quality/grasp_survey.py --rules holds strict   # only these rules
"""
import argparse
import itertools
import json
import subprocess
import sys
import tempfile

import numpy as np
from scipy.optimize import linprog

HANDS = ["human", "human-left", "robot3", "cartoon4", "assets/hands/shadow_hand/reach.xml"]
OBJECTS = ["sphere", "box", "cylinder", "torus", "mug",
           "assets/objects/robosuite_lemon.stl", "assets/objects/robosuite_milk.stl",
           "assets/objects/robosuite_bread.stl", "assets/objects/robosuite_cereal.stl",
           "assets/objects/robosuite_can.obj"]
SEEDS = [1, 2]
MOVEMENTS = ["power", "precision"]


def one_sided(normals):
    """True when some direction u has u . n > 0 for every normal n."""
    if len(normals) == 0:
        return True
    n = np.asarray(normals)
    # maximize s subject to n u >= s, -1 <= u <= 1
    c = np.array([0, 0, 0, -1.0])
    a = np.hstack([-n, np.ones((len(n), 1))])
    res = linprog(c, A_ub=a, b_ub=np.zeros(len(n)), bounds=[(-1, 1)] * 3 + [(None, 1)])
    return res.status == 0 and -res.fun > 1e-9


CLI = "./target/release/prehensile"  # the build surveyed: --cli


def run(hand, obj, movement, seed, rule):
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        p = subprocess.run([CLI, "grasp", "--hand", hand, "--object", obj,
                            "--movement", movement, "--seed", str(seed), "--validity", rule,
                            "--hold", "--out", f.name], capture_output=True, text=True)
        if p.returncode == 2:
            return None
        return json.load(open(f.name))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rules", nargs="+", default=["holds", "strict", "thesis"],
                    choices=["holds", "strict", "thesis"])
    ap.add_argument("--cli", default=CLI, help="the prehensile binary to survey")
    args = ap.parse_args()
    globals()["CLI"] = args.cli
    rows = {}
    for rule in args.rules:
        stats = {"searches": 0, "valid": 0, "fc": 0, "one_sided": 0, "eps": [], "ms": [],
                 "held5": 0, "held_gravity": 0, "valid_ms": []}
        per_hand = {}
        for hand, obj, movement, seed in itertools.product(HANDS, OBJECTS, MOVEMENTS, SEEDS):
            if hand.endswith(".xml") and movement == "precision":
                movement = "close"  # the Shadow hand has only the derived movement
            r = run(hand, obj, movement, seed, rule)
            if r is None:
                continue
            stats["searches"] += 1
            h = per_hand.setdefault(hand.split("/")[-1], [0, 0, 0])
            h[0] += 1
            stats["ms"].append(r["stats"]["seconds"] * 1000)
            if not r["valid"]:
                continue
            h[1] += 1
            stats["valid"] += 1
            stats["valid_ms"].append(r["stats"]["seconds"] * 1000)
            if r["stability"]["force_closure"]:
                stats["fc"] += 1
                h[2] += 1
            stats["eps"].append(r["stability"]["epsilon"])
            if one_sided([c["normal"] for c in r["contacts"]]):
                stats["one_sided"] += 1
            stats["held5"] += r["hold"]["held"] >= 5
            stats["held_gravity"] += r["hold"]["directions"][5]["held"]
        rows[rule] = (stats, per_hand)
    for rule, (s, per_hand) in rows.items():
        print(f"validity {rule}: {s['searches']} searches, {s['valid']} valid; of the valid: "
              f"{s['fc']} in force closure ({100 * s['fc'] / max(s['valid'], 1):.0f}%), "
              f"{s['one_sided']} with every contact normal on one side; "
              f"median epsilon {np.median(s['eps']) if s['eps'] else 0:.3f}; "
              f"median search {np.median(s['ms']):.1f} ms ({np.median(s['valid_ms']):.1f} ms for "
              f"those that found a valid grasp); hold test: {s['held5']} held in "
              f">= 5 of 6 directions, {s['held_gravity']} against gravity")
        for hand, (n, v, fc) in per_hand.items():
            print(f"    {hand:<12} {n:>3} searches, {v:>3} valid, {fc:>3} in force closure")


if __name__ == "__main__":
    sys.exit(main())
