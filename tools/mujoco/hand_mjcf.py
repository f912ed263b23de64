"""An MJCF model of any hand Prehensile reads, for replaying its grasps in MuJoCo.

From `prehensile hands --json` (a built-in hand, or `--file` a hand file): one body per bone at
its rest frame in its parent's, its capsules as capsule geoms (density of water), one hinge joint
per degree of freedom about the joint's own axis with its limits (a two-axis joint's abduction
listed first, so that MuJoCo composes R = R(abduction)·R(flexion) as Prehensile does), and a
position servo per joint with the Shadow hand file's finger actuation (kp = 1 N·m/rad, force
range ±0.9 N·m) and joint defaults (damping 0.1, armature 0.001), so that both hands are replayed
with the same strength. Hand geoms collide with the object, not with each other (the Shadow file's
collision class does the same). A degree of freedom whose limits are one angle gets no joint. Ball
joints are refused: Prehensile's are rotation vectors, which no chain of MuJoCo hinges reproduces.

    python3 tools/mujoco/hand_mjcf.py human > /tmp/human.xml   # a hand name or file
"""
import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

CLI = "./target/release/prehensile"
KP = 1.0
FORCE = 0.9


def describe(hand):
    """`prehensile hands --json` for a hand file or a built-in name."""
    is_file = os.path.exists(hand)
    args = [CLI, "hands", "--json"] + (["--file", hand] if is_file else [])
    hands = json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)
    if is_file:
        return hands[0]
    for h in hands:
        if h["name"] == hand:
            return h
    raise SystemExit(f"no built-in hand '{hand}' (have {', '.join(h['name'] for h in hands)})")


def fmt(values):
    return " ".join(f"{v:.9g}" for v in values)


def mjcf(hand, root_position=(0, 0, 0), root_quat_wxyz=(1, 0, 0, 0)):
    """The MJCF text of `hand` (the `hands --json` entry), its root body at the given pose and
    fixed there (no free joint)."""
    joints = hand["joints"]
    if any(j["kind"] == "ball" for j in joints):
        raise SystemExit(f"hand '{hand['name']}' has ball joints, which this model cannot copy")
    root = ET.Element("mujoco", model=hand["name"])
    ET.SubElement(root, "compiler", angle="radian")
    ET.SubElement(root, "option", timestep="0.002", iterations="20")
    default = ET.SubElement(root, "default")
    ET.SubElement(default, "joint", limited="true", damping="0.1", armature="0.001")
    ET.SubElement(default, "geom", contype="1", conaffinity="0", friction="1 0.005 0.001",
                  density="1000", condim="3")
    world = ET.SubElement(root, "worldbody")
    bodies = {}
    actuated = []
    for j in joints:
        parent = world if j["parent"] is None else bodies[j["parent"]]
        if j["parent"] is None:
            pos, quat = root_position, root_quat_wxyz
        else:
            x, y, z, w = j["rest_rotation_xyzw"]
            pos, quat = j["rest_position"], (w, x, y, z)
        body = ET.SubElement(parent, "body", name=j["bone"], pos=fmt(pos), quat=fmt(quat))
        bodies[j["bone"]] = body
        # MuJoCo applies a body's joints in the order listed, the first nearest the parent.
        order = list(range(len(j["dofs"])))[::-1]
        for k in order:
            lo, hi = (v * 3.141592653589793 / 180 for v in j["limits_deg"][k])
            if hi - lo < 1e-9:
                continue  # a degree of freedom held at one angle (e.g. the middle's abduction)
            ET.SubElement(body, "joint", name=j["dofs"][k], type="hinge",
                          axis=fmt(j["axes"][k]), range=fmt([lo, hi]))
            actuated.append((j["dofs"][k], lo, hi))
        for c in j["capsules"]:
            if sum((a - b) ** 2 for a, b in zip(c["a"], c["b"])) < 1e-12:
                ET.SubElement(body, "geom", type="sphere", pos=fmt(c["a"]),
                              size=f"{c['radius']:.9g}")
            else:
                ET.SubElement(body, "geom", type="capsule", fromto=fmt(c["a"] + c["b"]),
                              size=f"{c['radius']:.9g}")
        if not j["capsules"]:
            ET.SubElement(body, "inertial", pos="0 0 0", mass="0.001",
                          diaginertia="1e-7 1e-7 1e-7")
    actuators = ET.SubElement(root, "actuator")
    for name, lo, hi in actuated:
        ET.SubElement(actuators, "position", name=f"A_{name}", joint=name, kp=f"{KP}",
                      ctrllimited="true", ctrlrange=fmt([lo, hi]), forcelimited="true",
                      forcerange=fmt([-FORCE, FORCE]))
    return ET.tostring(root, encoding="unicode")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit("usage: hand_mjcf.py HAND (a built-in name or a hand file)")
    print(mjcf(describe(sys.argv[1])))
