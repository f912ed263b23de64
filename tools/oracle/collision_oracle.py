"""Independent answers for the capsule collision tests, computed once with libigl and committed.

For each mesh, random capsules at metre scale with centimetre sizes are placed near the surface.
For each we record:
  - `distance`: the distance from the capsule's segment to the surface, as the minimum of
    libigl's point-to-mesh distance (AABB tree) over 2001 points evenly spaced on the segment. The
    distance along the segment is 1-Lipschitz, so this over-estimates the true value by at most
    half the spacing (<= 25 micrometres for segments up to 10 cm); it never under-estimates.
  - `inside`: libigl's generalized winding number of the first endpoint > 0.5.
  - `touches`: inside or distance <= radius.
Cases whose distance is within 60 micrometres of the radius are dropped as undecidable here.

trimesh is used only to load and weld the meshes and to sample the surface. Its own
`proximity.closest_point` was tried first and found wrong by up to 113 micrometres on the
sub-millimetre triangles of robosuite_can.obj (it put a point lying on triangle 409 that far from
the mesh), so it is not trusted for distances.

Run from the repository root:
    pip install trimesh==5.2.0 libigl==2.6.3 rtree scipy numpy pillow
    cargo run -p prehensile-formats --example export_builtin_objects -- /tmp/builtin
    python3 tools/oracle/collision_oracle.py /tmp/builtin crates/prehensile-core/tests/data/collision_oracle.json
"""
import json
import sys

import igl
import numpy as np
import trimesh

SAMPLES = 2001
CASES_PER_MESH = 150
MARGIN = 60e-6


def load(path, scale=1.0):
    mesh = trimesh.load(path, force="mesh", process=True, skip_materials=True)
    # Weld by position only, as Prehensile does (OBJ texture seams split vertices otherwise).
    mesh.merge_vertices(merge_tex=True, merge_norm=True)
    mesh.apply_scale(scale)
    assert mesh.is_watertight, path
    return mesh


def cases(mesh, rng, n):
    out = []
    points, faces = trimesh.sample.sample_surface(mesh, n * 3, seed=int(rng.integers(1 << 31)))
    normals = mesh.face_normals[faces]
    for p, nrm in zip(points, normals):
        if len(out) >= n:
            break
        centre = p + nrm * rng.uniform(-0.03, 0.03)
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        length = rng.uniform(0.0, 0.05)
        a = centre - direction * length / 2
        b = centre + direction * length / 2
        radius = rng.uniform(0.005, 0.015)
        t = np.linspace(0.0, 1.0, SAMPLES)[:, None]
        samples = a + (b - a) * t
        vertices = np.ascontiguousarray(mesh.vertices, dtype=np.float64)
        faces = np.ascontiguousarray(mesh.faces, dtype=np.int64)
        squared = igl.point_mesh_squared_distance(samples, vertices, faces)[0]
        distance = float(np.sqrt(squared.min()))
        winding = igl.winding_number(vertices, faces, np.array([a]))
        inside = bool(winding[0] > 0.5)
        if abs(distance - radius) < MARGIN:
            continue
        out.append(
            {
                "a": a.tolist(),
                "b": b.tolist(),
                "radius": radius,
                "distance": distance,
                "inside": inside,
                "touches": inside or distance <= radius,
            }
        )
    return out


def main():
    builtin_dir, out_path = sys.argv[1], sys.argv[2]
    rng = np.random.default_rng(20261122)
    meshes = {
        "mug.obj": (f"{builtin_dir}/mug.obj", 1.0),
        "torus.obj": (f"{builtin_dir}/torus.obj", 1.0),
        "box.obj": (f"{builtin_dir}/box.obj", 1.0),
        "robosuite_can.obj": ("assets/objects/robosuite_can.obj", 1.0),
        "pybullet_bunny.obj": ("assets/objects/pybullet_bunny.obj", 0.05),
    }
    result = {
        "generator": "tools/oracle/collision_oracle.py with libigl 2.6.3 (trimesh for loading)",
        "samples_per_segment": SAMPLES,
        "meshes": {},
    }
    for name, (path, scale) in meshes.items():
        mesh = load(path, scale)
        result["meshes"][name] = {"scale": scale, "cases": cases(mesh, rng, CASES_PER_MESH)}
        c = result["meshes"][name]["cases"]
        print(name, len(c), "cases,", sum(x["touches"] for x in c), "touching,", sum(x["inside"] for x in c), "inside")
    with open(out_path, "w") as f:
        json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()
