"""Which result features rank the directions MuJoCo held? Reads the folder that
`replay_grasps.py --keep DIR` writes (each result JSON with its MuJoCo outcome) and prints, per
feature, Spearman's rank correlation with the number of directions held, then the share held in
>= 5 directions by the thumb's widest opposition.

    python3 tools/mujoco/replay_grasps.py --objects /tmp/objects --seeds 1 2 3 4 --keep /tmp/keep
    python3 tools/mujoco/held_features.py /tmp/keep
"""
import glob
import json
import os
import sys

import numpy as np
from scipy.stats import spearmanr


def pad(contacts, finger):
    """The finger's pad normal: its contact listed last (the most distal bone's)."""
    found = [c for c in contacts if c["finger"] == finger]
    return np.array(found[-1]["normal"]) if found else None


def widest_opposition(contacts):
    """Largest angle between the thumb's pad normal and another finger's, degrees (0 if none)."""
    thumb = pad(contacts, "thumb")
    others = [pad(contacts, f) for f in ["index", "middle", "ring", "little"]]
    angles = [np.degrees(np.arccos(np.clip(thumb @ n, -1, 1)))
              for n in others if n is not None and thumb is not None]
    return max(angles, default=0.0)


def main():
    rows = []
    for path in sorted(glob.glob(os.path.join(sys.argv[1], "*.json"))):
        r = json.load(open(path))
        c = r["contacts"]
        rows.append({
            "held": sum(o["held"] for o in r["mujoco"]),
            "thumb opposition": widest_opposition(c),
            "epsilon": r["stability"]["epsilon"],
            "smallest load ratio": min(r["stability"]["load_ratio"]),
            "palm touches": float(any(x["finger"] == "palm" for x in c)),
            "contacts": len(c),
            "|mean normal|": float(np.linalg.norm(np.mean([x["normal"] for x in c], axis=0))),
        })
    held = [r["held"] for r in rows]
    print(f"{len(rows)} grasps; Spearman's rho with the directions held:")
    for name in rows[0]:
        if name != "held":
            rho, p = spearmanr(held, [r[name] for r in rows])
            print(f"  {name:<22} {rho:+.2f} (p {p:.3f})")
    for lo, hi in [(0, 120), (120, 150), (150, 170), (170, 181)]:
        sel = [r["held"] for r in rows if lo <= r["thumb opposition"] < hi]
        print(f"thumb opposition {lo}-{hi} deg: {sum(h >= 5 for h in sel)} of {len(sel)} "
              "held in >= 5 directions")


if __name__ == "__main__":
    main()
