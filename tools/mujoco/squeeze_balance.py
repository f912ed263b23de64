"""Does a quasi-static squeeze balance predict which Shadow-hand grasps MuJoCo holds?

An experiment behind docs/QUALITY.md, kept so that it can be rerun. For each grasp
that `replay_grasps.py` replays, the contact forces the squeeze produces are estimated from the
hand's own actuation: the squeeze torques (0.2 rad times kp = 1 N·m/rad along the movement's
closing direction) are carried by the contacts' normal forces through MuJoCo's contact Jacobians
(non-negative least squares; each distal joint folded into its middle joint by the fixed tendon's
ratio 1.14). Friction (mu 0.5, 8-sided cones) may then absorb what the normal forces leave
unbalanced; the residual wrench that friction cannot absorb, over the normal forces' sum, is 0
for a grasp in equilibrium under its own squeeze. The script prints it beside the number of
directions MuJoCo held. Measured, it did not separate the grasps that held from those that
did not (a residual of 0.06 held in 3 directions, 0.73 held in 5).

Run from the repository root, as replay_grasps.py (pip install mujoco==4.0.0 numpy scipy):
    python3 tools/mujoco/squeeze_balance.py --objects /tmp/objects --seeds 1 2
"""
import argparse
import json
import os
import sys
import tempfile

import mujoco
import numpy as np
from scipy.optimize import linprog, nnls

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import replay_grasps as replay  # noqa: E402

MU = 0.5
TENDON_RATIO = 1.14


def tangents(n):
    t1 = np.cross(n, [1, 0, 0]) if abs(n[0]) < 0.9 else np.cross(n, [0, 1, 0])
    t1 /= np.linalg.norm(t1)
    return t1, np.cross(n, t1)


def residual(result, mesh):
    """The wrench friction cannot balance under the squeeze, over the sum of normal forces."""
    model = replay.build(result, mesh)
    data = mujoco.MjData(model)
    for j in result["joints"]:
        data.qpos[model.jnt_qposadr[model.joint(j["name"]).id]] = j["angle"]
    mujoco.mj_forward(model, data)
    closing = replay.closing_directions(result["movement"], model)
    com = data.xipos[model.body("object").id]
    tau = np.zeros(model.nv)
    for i in range(model.nu):
        if model.actuator_trntype[i] == mujoco.mjtTrn.mjTRN_JOINT:
            j = model.actuator_trnid[i, 0]
            tau[model.jnt_dofadr[j]] = replay.SQUEEZE * closing.get(model.joint(j).name, 0.0)
    contacts = result["contacts"]
    # Joint torque per unit normal force at each contact (normals point into the object).
    g = np.zeros((model.nv, len(contacts)))
    for k, c in enumerate(contacts):
        jacp = np.zeros((3, model.nv))
        mujoco.mj_jac(model, data, jacp, None, np.array(c["point"]), model.body(c["bone"]).id)
        g[:, k] = jacp.T @ np.array(c["normal"])
    for finger in ["FF", "MF", "RF", "LF"]:
        j1 = model.jnt_dofadr[model.joint(f"robot0:{finger}J1").id]
        j0 = model.jnt_dofadr[model.joint(f"robot0:{finger}J0").id]
        g[j1] += TENDON_RATIO * g[j0]
        g[j0] = 0
    normal_forces, _ = nnls(g, tau)
    # Tangential weights per cone edge, at most mu times each normal force, plus slack.
    rhs = np.zeros(6)
    columns = []
    for k, c in enumerate(contacts):
        p, n = np.array(c["point"]), np.array(c["normal"])
        f = normal_forces[k] * n
        rhs -= np.r_[f, np.cross(p - com, f)]
        t1, t2 = tangents(n)
        for angle in np.arange(8) * np.pi / 4:
            e = np.cos(angle) * t1 + np.sin(angle) * t2
            columns.append(np.r_[e, np.cross(p - com, e)])
    n_edges = len(columns)
    limit = np.zeros((len(contacts), n_edges + 12))
    for k in range(len(contacts)):
        limit[k, 8 * k:8 * k + 8] = 1
    equal = np.hstack([np.array(columns).T, np.eye(6), -np.eye(6)])
    cost = np.r_[np.zeros(n_edges), np.ones(12)]
    lp = linprog(cost, A_ub=limit, b_ub=MU * normal_forces, A_eq=equal, b_eq=rhs,
                 bounds=(0, None), method="highs")
    return lp.fun / max(normal_forces.sum(), 1e-9)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--objects", required=True, help="folder of the built-in objects as OBJ")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "r.json")
        for obj, mesh in replay.meshes(args.objects).items():
            for movement in ["power", "precision", "close"]:
                for seed in args.seeds:
                    if replay.search(obj, movement, seed, out, []) != 0:
                        continue
                    result = json.load(open(out))
                    held = sum(o["held"] for o in replay.replay(result, mesh))
                    rows.append((residual(result, mesh), held, obj.split("/")[-1], movement, seed))
    rows.sort()
    for r, held, obj, movement, seed in rows:
        print(f"residual {r:.3f}  held in {held} of 6  {obj} {movement} seed {seed}")


if __name__ == "__main__":
    sys.exit(main())
