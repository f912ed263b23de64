"""The 16k-triangle scan the speed targets are measured on: the robosuite can (956 triangles,
assets/objects/robosuite_can.obj) subdivided twice, written as OBJ (15,296 triangles).

    pip install trimesh==5.2.0 numpy
    python3 tools/benchmark/make_can16k.py target/can16k.obj
"""
import sys

import trimesh


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "target/can16k.obj"
    mesh = trimesh.load("assets/objects/robosuite_can.obj", force="mesh", process=True)
    for _ in range(2):
        mesh = mesh.subdivide()
    mesh.export(out)
    print(f"{out}: {len(mesh.faces)} triangles")


if __name__ == "__main__":
    main()
