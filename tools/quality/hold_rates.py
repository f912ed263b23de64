"""The rapier hold test's rates for power grasps: how many valid grasps hold in >= 5 and in all 6
directions (`prehensile grasp --hold`: squeeze with grip strength 0.5, then gravity along each axis
direction for 1 s; held = moved < 2 cm and turned < 30 degrees).

Human and Shadow hands; the built-in sphere, box and cylinder and five robosuite scans; seeds 1-4.
Run from the repository root after `cargo build --release -p prehensile-cli` (two searches at a
time, about 2 minutes):
    python3 tools/quality/hold_rates.py [--cli target/release/prehensile]
"""
import argparse
import itertools
import json
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor

HANDS = ["human", "assets/hands/shadow_hand/reach.xml"]
OBJECTS = ["sphere", "box", "cylinder"] + [
    f"assets/objects/robosuite_{name}"
    for name in ["bread.stl", "milk.stl", "cereal.stl", "can.obj", "lemon.stl"]]
SEEDS = [1, 2, 3, 4]


def held_directions(cli, hand, obj, seed):
    """Directions held by the valid power grasp, or None when the search finds none."""
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        p = subprocess.run([cli, "grasp", "--hand", hand, "--object", obj, "--movement", "power",
                            "--seed", str(seed), "--hold", "--out", f.name],
                           capture_output=True, text=True)
        if p.returncode != 0:
            return None
        result = json.load(open(f.name))
    return result["hold"]["held"] if result["valid"] else None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cli", default="target/release/prehensile")
    args = parser.parse_args()
    runs = list(itertools.product(HANDS, OBJECTS, SEEDS))
    with ThreadPoolExecutor(2) as pool:
        held = list(pool.map(lambda r: held_directions(args.cli, *r), runs))
    for hand in HANDS:
        rows = [(obj, seed, h) for (hd, obj, seed), h in zip(runs, held) if hd == hand and h is not None]
        counts = [h for _, _, h in rows]
        print(f"{hand.split('/')[-1]}: {len(counts)} valid, {sum(h >= 5 for h in counts)} held in >= 5 "
              f"directions, {sum(h == 6 for h in counts)} in all 6, mean "
              f"{sum(counts) / max(len(counts), 1):.2f}")
        print("    " + " ".join(f"{obj.split('/')[-1].split('.')[0].removeprefix('robosuite_')}"
                                f"{seed}:{h}" for obj, seed, h in rows))


if __name__ == "__main__":
    main()
