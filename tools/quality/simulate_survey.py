"""Which objects `prehensile simulate --scenario grasp` holds, hand by hand.

For each hand: the default run (sphere, box and cylinder with one controller fitted to the
sphere's grasp, the paper's Fig. 6 set-up) and each object alone (the controller fitted to its own
grasp). Prints one line per hand, `object:H/slip_mm` (H held, - not), and the total held.

Run from the repository root after `cargo build --release -p prehensile-cli`:
    python3 tools/quality/simulate_survey.py [--cli target/release/prehensile] [--candidates N]
        [--engine rapier|reduced] [--dt SECONDS]
"""
import argparse
import json
import subprocess
import tempfile

HANDS = ["human", "human-left", "robot3", "robot3_ball", "cartoon4",
         "assets/hands/shadow_hand/reach.xml",
         "assets/hands/webxr_generic_hand/left.glb", "assets/hands/webxr_generic_hand/right.glb"]
RUNS = ["sphere,box,cylinder", "sphere", "box", "cylinder"]


def run(cli, hand, objects, extra):
    if hand == "robot3_ball":
        hand = "assets/hands/robot3_ball.toml"
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        p = subprocess.run([cli, "simulate", "--hand", hand, "--object", objects, "--out", f.name] + extra,
                           capture_output=True, text=True)
        if p.returncode != 0:
            return [("error: " + p.stderr.strip().splitlines()[-1], False, None)]
        report = json.load(open(f.name))
    return [(c["label"], bool(c["held"]), c["object_slip_m"]) for c in report["cases"]]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cli", default="target/release/prehensile")
    parser.add_argument("--candidates", type=int,
                        help="grasps per object checked before each run (default: the CLI's)")
    parser.add_argument("--engine", default="reduced", choices=["rapier", "reduced"],
                        help="the simulation's engine (prehensile simulate --engine)")
    parser.add_argument("--dt", type=float, help="time step, seconds (default: the CLI's)")
    args = parser.parse_args()
    extra = [] if args.candidates is None else ["--candidates", str(args.candidates)]
    extra += ["--engine", args.engine]
    extra += [] if args.dt is None else ["--dt", str(args.dt)]
    held = total = 0
    for hand in HANDS:
        cells = []
        for objects in RUNS:
            cases = run(args.cli, hand, objects, extra)
            held += sum(h for _, h, _ in cases)
            total += len(cases)
            cells.append(" ".join(f"{label}:{'H' if h else '-'}/{1000 * slip:.1f}"
                                  if slip is not None else label for label, h, slip in cases))
        print(f"{hand.split('/')[-1]:12} | " + " | ".join(cells))
    print(f"held {held} of {total}")


if __name__ == "__main__":
    main()
