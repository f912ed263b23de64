"""The Shadow hand gripping a sphere in MuJoCo and in Prehensile, timed per step in alternating
blocks, reported as a ratio of steps per second (docs/PERFORMANCE.md).

The scene on both sides: the Shadow hand fixture (`assets/hands/shadow_hand/reach.xml`), the palm
held still, the fingers closed by stiff joint servos on a 4 cm sphere of 20 kg/m^3 (Prehensile's
built-in sphere and default density) pressed into the palm by gravity, contacts active and
settled before timing. MuJoCo runs the file as it is except for the visual meshes (`stls/` is not
in the repository; the meshes are visual only, except the forearm's convex collider, which is far
from the object) and the sphere body it adds. Prehensile's side is
`prehensile_sim::scenarios::held_still`, the scene of the criterion benchmark
`simulation_step/shadow_sphere_dt_*`, driven by `crates/prehensile-sim/examples/step_timing.rs`.

`--object mesh` gives MuJoCo the sphere as Prehensile has it, the built-in 960-triangle mesh
(MuJoCo collides a mesh geom as its convex hull, as Prehensile's rapier world does), instead of
MuJoCo's analytic sphere: the same scene geometry on both sides.

Run from the repository root (after `pip install mujoco==4.0.0`):
    python3 tools/benchmark/mujoco_side_by_side.py [--pairs N] [--object primitive|mesh]
        [--engine rapier|reduced]
The two engines take turns, N pairs of blocks per step length (default 30): STEPS steps of
Prehensile, then the same of MuJoCo, each timed as the median of blocks of 100 steps. The machine's
speed drifts by tens of percent within minutes (a shared 2-core machine), so each ratio comes
from timings a fraction of a second apart; the table reports the medians, and the ratio's median
with its quartiles, at dt 0.2 ms and 1 ms.
"""
import argparse
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

import mujoco

from step_timing_client import StepTiming
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
HAND = ROOT / "assets/hands/shadow_hand"
SPHERE_RADIUS = 0.04
DENSITY = 20.0
STEPS = {0.0002: 2000, 0.001: 1000}  # steps per block of each engine's turn


def sphere_mesh(directory: pathlib.Path) -> pathlib.Path:
    """The built-in sphere as Prehensile builds it, written as OBJ into `directory`."""
    subprocess.run(
        ["cargo", "run", "--release", "--quiet", "-p", "prehensile-formats", "--example",
         "export_builtin_objects", "--", str(directory)],
        cwd=ROOT, check=True, stdout=subprocess.DEVNULL,
    )
    return directory / "sphere.obj"


def stripped_scene(directory: pathlib.Path, mesh: pathlib.Path | None) -> pathlib.Path:
    """Copies of the MJCF files without the hand's meshes, plus a free sphere in the world: an
    analytic sphere, or the mesh `mesh`."""
    for name in ["reach.xml", "shared.xml", "shared_asset.xml", "robot.xml"]:
        tree = ET.parse(HAND / name)
        for parent in tree.iter():
            for child in list(parent):
                if child.tag == "mesh" or (child.tag == "geom" and "mesh" in child.attrib):
                    parent.remove(child)
        if name == "reach.xml":
            root = tree.getroot()
            world = root.find("worldbody")
            body = ET.SubElement(world, "body", name="object", pos="0 0 0")
            ET.SubElement(body, "freejoint", name="object")
            shape = {"type": "sphere", "size": str(SPHERE_RADIUS)}
            if mesh is not None:
                asset = ET.SubElement(root, "asset")
                ET.SubElement(asset, "mesh", name="object_mesh", file=str(mesh.resolve()))
                shape = {"type": "mesh", "mesh": "object_mesh"}
            ET.SubElement(
                body, "geom", **shape, density=str(DENSITY), friction="1 0.005 0.0001",
                condim="3",
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


def mujoco_step_us(model, data, steps: int) -> float:
    """Median microseconds per step over blocks of 100 steps (each block one call into MuJoCo's C
    library, so no Python overhead is counted against it)."""
    blocks = []
    for _ in range(max(1, steps // 100)):
        begin = time.perf_counter()
        mujoco.mj_step(model, data, nstep=100)
        blocks.append((time.perf_counter() - begin) / 100 * 1e6)
    return statistics.median(blocks)


def sphere_position(model, data):
    return data.qpos[model.jnt_qposadr[model.joint("object").id] :][:3].copy()


def prehensile(engine: str) -> StepTiming:
    """The step_timing example on `engine`, built and started once for every step length."""
    subprocess.run(
        ["cargo", "build", "--release", "-p", "prehensile-sim", "--example", "step_timing"],
        cwd=ROOT, check=True,
    )
    return StepTiming(
        ROOT / "target/release/examples/step_timing", HAND / "reach.xml", STEPS, cwd=ROOT,
        engine=engine,
    )


def quartiles(values):
    q = statistics.quantiles(values, n=4)
    return q[0], q[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--pairs", type=int, default=30, help="alternating blocks per step length")
    parser.add_argument("--object", choices=["primitive", "mesh"], default="primitive",
                        help="MuJoCo's sphere: its analytic sphere, or Prehensile's sphere mesh")
    parser.add_argument("--engine", choices=["rapier", "reduced"], default="reduced",
                        help="Prehensile's engine (prehensile simulate --engine)")
    arguments = parser.parse_args()
    pairs = arguments.pairs
    if pairs < 2:
        parser.error("--pairs must be at least 2")
    ours_engine = prehensile(arguments.engine)
    with tempfile.TemporaryDirectory() as directory:
        directory = pathlib.Path(directory)
        mesh = sphere_mesh(directory) if arguments.object == "mesh" else None
        path = stripped_scene(directory, mesh)
        scenes = {dt: gripping(path, dt) for dt in STEPS}
    starts = {dt: sphere_position(*scenes[dt]) for dt in STEPS}
    print(f"MuJoCo {mujoco.__version__}, Shadow hand gripping a {SPHERE_RADIUS * 100:g} cm sphere"
          f" ({'the 960-triangle mesh' if arguments.object == 'mesh' else 'analytic'} in MuJoCo),"
          f" {pairs} alternating pairs of blocks per step length")
    print("dt ms | MuJoCo µs/step  steps/s | Prehensile µs/step  steps/s |"
          " Prehensile/MuJoCo steps/s: median (quartiles)")
    for dt, steps in STEPS.items():
        ours, theirs = [], []
        for _ in range(pairs):
            ours.append(ours_engine.step_us(dt, steps))
            theirs.append(mujoco_step_us(*scenes[dt], steps))
        ratios = [t / o for t, o in zip(theirs, ours)]
        low, high = quartiles(ratios)
        model, data = scenes[dt]
        drift = float(np.linalg.norm(sphere_position(model, data) - starts[dt]))
        o, t = statistics.median(ours), statistics.median(theirs)
        print(
            f"{dt * 1e3:5g} | {t:14.1f} {1e6 / t:8.0f} | {o:18.1f} {1e6 / o:8.0f} |"
            f" {statistics.median(ratios):.2f} ({low:.2f}–{high:.2f})"
            f"   (MuJoCo: {hand_contacts(model, data)} sphere contacts, sphere moved"
            f" {drift * 1e3:.1f} mm while timed)"
        )
    ours_engine.close()


if __name__ == "__main__":
    sys.exit(main())
