"""Independent answers for the grasp-stability tests, computed once with scipy's Qhull and committed.

For each case (a set of contacts: point, inward unit normal, capsule radius) the script builds the
grasp wrench space itself with numpy, as GraspIt! does (Ferrari-Canny L1):
  - each contact's friction cone is linearized by `edges` forces n + mu (cos t t1 + sin t t2), with
    t1 the object's z axis projected on the contact's tangent plane (its x axis on a nearly
    horizontal surface) and t2 = n x t1 (the convention Prehensile uses; rotating the edges
    changes the linearized cone, so both must use the same one);
  - a soft pad adds the two wrenches (n, +-mu * patch * radius * n) of torsion about the normal;
  - torques are about the centre `c` and divided by the scale `L`.
scipy.spatial.ConvexHull (Qhull, option Qt) gives the facets n.x + b <= 0. Then
  - force closure: every facet has -b > 1e-7;
  - epsilon = min(-b) with force closure, else 0;
  - load ratio along each of +x,-x,+y,-y,+z,-z: for a load along d the hand applies (-d, 0), and
    the ratio is min over facets with n.w > 0 of (-b) / (n.w).
A hull that Qhull cannot build because the wrenches are flat counts as no force closure.

Cases: hand-made grasps (pinch, tripod, flat palm, wrap around a cylinder) and random contact
sets on spheres, boxes and cylinders with random mu, edges and patch.

Further cases come from grasp results given after the output file (`prehensile grasp --out R.json`):
their contacts, friction, centre of mass and torque scale, with the default cone (8 edges, patch
0.5). The committed file includes the Shadow hand's power grasp of the mug (170 wrenches), on
which the first hull, without joggling, was not convex.

Run from the repository root:
    pip install scipy numpy
    ./target/release/prehensile grasp --hand assets/hands/shadow_hand/reach.xml --object mug \
        --movement power --out /tmp/shadow-mug.json
    python3 tools/oracle/stability_oracle.py crates/prehensile-core/tests/data/stability_oracle.json \
        /tmp/shadow-mug.json
"""
import json
import sys

import numpy as np
from scipy.spatial import ConvexHull, QhullError


def tangents(n):
    up = np.array([0.0, 0.0, 1.0]) - n * n[2]
    if up @ up <= 1e-12:
        up = np.array([1.0, 0.0, 0.0]) - n * n[0]
    t1 = up / np.linalg.norm(up)
    return t1, np.cross(n, t1)


def wrenches(contacts, mu, edges, patch, center, scale):
    out = []
    for c in contacts:
        p = np.array(c["point"])
        n = np.array(c["normal"])
        t1, t2 = tangents(n)
        for j in range(edges):
            ang = 2 * np.pi * j / edges
            f = n + mu * (np.cos(ang) * t1 + np.sin(ang) * t2)
            out.append(np.concatenate([f, np.cross(p - center, f) / scale]))
        if patch > 0:
            tor = n * (mu * patch * c["radius"])
            for s in (1.0, -1.0):
                out.append(np.concatenate([n, (np.cross(p - center, n) + s * tor) / scale]))
    return np.array(out)


def measures(w):
    try:
        hull = ConvexHull(w, qhull_options="Qt")
    except QhullError:
        return False, 0.0, [0.0] * 6
    normals, b = hull.equations[:, :6], hull.equations[:, 6]
    eps = float(np.min(-b))
    if eps < 1e-7:
        return False, 0.0, [0.0] * 6
    loads = []
    for k in range(6):
        d = np.zeros(6)
        d[k // 2] = -1.0 if k % 2 == 0 else 1.0
        along = normals @ d
        mask = along > 1e-12
        loads.append(float(np.min(-b[mask] / along[mask])))
    return True, eps, loads


def contact(p, n, r=0.008):
    n = np.asarray(n, float)
    return {"point": list(map(float, p)), "normal": list(map(float, n / np.linalg.norm(n))), "radius": r}


def handmade():
    cases = []
    cases.append(("pinch", [contact([0.03, 0, 0], [-1, 0, 0]), contact([-0.03, 0, 0], [1, 0, 0])]))
    cases.append(("flat palm", [contact([x, 0.01, 0.03], [0, 0, -1]) for x in (-0.02, -0.01, 0, 0.01)]))
    tri = []
    for i in range(3):
        a = 2 * np.pi * i / 3
        p = np.array([0.03 * np.cos(a), 0.03 * np.sin(a), 0.005 * i])
        tri.append(contact(p, -p * [1, 1, 0]))
    cases.append(("tripod", tri))
    wrap = []
    for i in range(7):
        a = -0.6 * np.pi + i * 0.2 * np.pi
        p = np.array([0.025 * np.cos(a), 0.025 * np.sin(a), -0.03 + 0.01 * i])
        wrap.append(contact(p, -p * [1, 1, 0], r=0.009))
    wrap.append(contact([-0.025, 0, 0.0], [1, 0, 0], r=0.015))
    cases.append(("wrap around a cylinder", wrap))
    return cases


def random_cases(rng, count):
    cases = []
    for k in range(count):
        shape = ["sphere", "box", "cylinder"][k % 3]
        m = int(rng.integers(2, 12))
        cs = []
        for _ in range(m):
            if shape == "sphere":
                d = rng.normal(size=3)
                d /= np.linalg.norm(d)
                p, n = 0.04 * d, -d
            elif shape == "box":
                axis = int(rng.integers(0, 3))
                sgn = rng.choice([-1.0, 1.0])
                p = rng.uniform(-0.03, 0.03, size=3)
                p[axis] = 0.03 * sgn
                n = np.zeros(3)
                n[axis] = -sgn
            else:
                a = rng.uniform(0, 2 * np.pi)
                p = np.array([0.025 * np.cos(a), 0.025 * np.sin(a), rng.uniform(-0.05, 0.05)])
                n = -p * [1, 1, 0]
            cs.append(contact(p, n, r=float(rng.uniform(0.005, 0.015))))
        cases.append((f"random {shape} {k}", cs))
    return cases


def from_results(paths):
    cases = []
    for path in paths:
        r = json.load(open(path))
        cs = [{"point": c["point"], "normal": c["normal"], "radius": c["radius"]} for c in r["contacts"]]
        cases.append((f"{r['hand']} {r['movement']} grasp of {r['object']}", cs, r["friction"],
                      np.array(r["center_of_mass"]), r["stability"]["torque_scale"]))
    return cases


def record(name, cs, mu, edges, patch, center, scale):
    w = wrenches(cs, mu, edges, patch, center, scale)
    fc, eps, loads = measures(w)
    return {
        "name": name, "contacts": cs, "friction": mu, "cone_edges": edges,
        "torsion_patch": patch, "center": list(map(float, center)), "scale": scale,
        "force_closure": fc, "epsilon": eps, "load_ratio": loads,
    }


def main(out, results):
    rng = np.random.default_rng(2015)
    cases = []
    for name, cs in handmade() + random_cases(rng, 40):
        for mu, edges, patch in [(0.5, 8, 0.5), (float(rng.uniform(0.2, 1.2)), int(rng.integers(3, 12)), float(rng.uniform(0, 1)))]:
            center = rng.uniform(-0.005, 0.005, size=3)
            pts = np.array([c["point"] for c in cs])
            scale = float(np.max(np.linalg.norm(pts - center, axis=1)))
            cases.append(record(name, cs, mu, edges, patch, center, scale))
    for name, cs, mu, center, scale in from_results(results):
        cases.append(record(name, cs, mu, 8, 0.5, center, scale))
    closed = sum(c["force_closure"] for c in cases)
    with open(out, "w") as f:
        json.dump({"source": "tools/oracle/stability_oracle.py (scipy.spatial.ConvexHull, Qhull Qt)",
                   "cases": cases}, f, indent=1)
    print(f"{len(cases)} cases, {closed} in force closure -> {out}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
