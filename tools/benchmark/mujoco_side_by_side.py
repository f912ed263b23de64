"""The Shadow hand gripping a sphere in MuJoCo, timed per step, next to Prehensile's own benchmark
of the same kind of scene, reported as a ratio of steps per second (issue 5, docs/PERFORMANCE.md).

The scene on both sides: the Shadow hand fixture (`assets/hands/shadow_hand/reach.xml`), the palm
held still, the fingers closed by stiff joint servos on a 4 cm sphere of 20 kg/m^3 (Prehensile's
built-in sphere and default density) pressed into the palm by gravity, contacts active and
settled before timing. MuJoCo runs the file as it is except for the visual meshes (`stls/` is not
in the repository; the meshes are visual only, except the forearm's convex collider, which is far
from the object) and the sphere body it adds. Prehensile's side is the criterion benchmark
`simulation_step/shadow_sphere_dt_*` (crates/prehensile-sim/benches/simulation.rs): the grasp
scenario's grip on the same sphere.

Run from the repository root (after `pip install mujoco==4.0.0`):
    python3 tools/benchmark/mujoco_side_by_side.py
It runs both (the cargo bench for the Shadow hand, then MuJoCo) and prints a table of median
microseconds per step, steps per second and the ratio, at dt 0.2 ms and 1 ms.
"""
import json
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

import mujoco
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
HAND = ROOT / "assets/hands/shadow_hand"
SPHERE_RADIUS = 0.04
DENSITY = 20.0
STEPS = {0.0002: 5000, 0.001: 1000}
REPEATS = 7


def stripped_scene(directory: pathlib.Path) -> pathlib.Path:
    """Copies of the MJCF files without meshes, plus a free sphere in the world."""
    for name in ["reach.xml", "shared.xml", "shared_asset.xml", "robot.xml"]:
        tree = ET.parse(HAND / name)
        for parent in tree.iter():
            for child in list(parent):
                if child.tag == "mesh" or (child.tag == "geom" and "mesh" in child.attrib):
                    parent.remove(child)
        if name == "reach.xml":
            world = tree.getroot().find("worldbody")
            body = ET.SubElement(world, "body", name="object", pos="0 0 0")
            ET.SubElement(body, "freejoint", name="object")
            ET.SubElement(
                body, "geom", type="sphere", size=str(SPHERE_RADIUS), density=str(DENSITY),
                friction="1 0.005 0.0001", condim="3",
            )
        tree.write(directory / name)
    return directory / "reach.xml"


def gripping(path: pathlib.Path, dt: float):
    """The model and data with the sphere in the palm and the fingers closed on it, settled."""
    model = mujoco.MjModel.from_xml_path(str(path))
    model.opt.timestep = dt
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    palm = model.body("robot0:palm").id
    rotation = data.xmat[palm].reshape(3, 3)
    # The palm's front faces its -y axis (the fingers flex that way); fingers extend along +z.
    front, along = -rotation[:, 1], rotation[:, 2]
    model.opt.gravity[:] = -9.81 * front  # presses the sphere into the palm
    centre = data.xpos[palm] + 0.08 * along + (0.0111 + SPHERE_RADIUS + 0.002) * front
    joint = model.joint("object").id
    address = model.jnt_qposadr[joint]
    data.qpos[address : address + 3] = centre
    data.qpos[address + 3 : address + 7] = [1, 0, 0, 0]
    # Close every finger: flexion joints to half their range, the rest to the middle.
    for a in range(model.nu):
        low, high = model.actuator_ctrlrange[a]
        name = model.actuator(a).name
        flexion = name[-2:] in ("J2", "J1") and not name.startswith("robot0:A_WR") or name.endswith("THJ3")
        data.ctrl[a] = low + 0.5 * (high - low) if flexion else 0.5 * (low + high)
        if name.startswith("robot0:A_WR"):
            data.ctrl[a] = 0.0
    for _ in range(int(3.0 / dt)):  # settled after about 2 s
        mujoco.mj_step(model, data)
    return model, data


def hand_contacts(model, data) -> int:
    sphere = model.body("object").id
    return sum(
        1
        for c in data.contact[: data.ncon]
        if sphere in (model.geom_bodyid[c.geom1], model.geom_bodyid[c.geom2])
    )


def mujoco_step_us(dt: float):
    with tempfile.TemporaryDirectory() as directory:
        model, data = gripping(stripped_scene(pathlib.Path(directory)), dt)
        start = data.qpos[model.jnt_qposadr[model.joint("object").id] :][:3].copy()
        times = []
        for _ in range(REPEATS):
            begin = time.perf_counter()
            for _ in range(STEPS[dt]):
                mujoco.mj_step(model, data)
            times.append((time.perf_counter() - begin) / STEPS[dt] * 1e6)
        end = data.qpos[model.jnt_qposadr[model.joint("object").id] :][:3]
        return statistics.median(times), hand_contacts(model, data), float(np.linalg.norm(end - start))


def prehensile_step_us(dt: float) -> float:
    name = f"shadow_sphere_dt_{dt * 1e3:g}ms"
    estimates = ROOT / f"target/criterion/simulation_step/{name}/new/estimates.json"
    return json.loads(estimates.read_text())["median"]["point_estimate"] / 1e3


def main():
    subprocess.run(
        ["cargo", "bench", "-p", "prehensile-sim", "--bench", "simulation", "--", "shadow_sphere"],
        cwd=ROOT, check=True,
    )
    print(f"MuJoCo {mujoco.__version__}, Shadow hand gripping a {SPHERE_RADIUS * 100:g} cm sphere")
    print("dt ms | MuJoCo µs/step  steps/s | Prehensile µs/step  steps/s | Prehensile/MuJoCo steps/s")
    for dt in STEPS:
        ours = prehensile_step_us(dt)
        theirs, contacts, drift = mujoco_step_us(dt)
        print(
            f"{dt * 1e3:5g} | {theirs:14.1f} {1e6 / theirs:8.0f} | {ours:18.1f} {1e6 / ours:8.0f} |"
            f" {theirs / ours:.2f}   (MuJoCo: {contacts} sphere contacts, sphere moved {drift * 1e3:.1f} mm while timed)"
        )


if __name__ == "__main__":
    sys.exit(main())
