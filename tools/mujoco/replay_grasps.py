"""Replays grasps found by `prehensile grasp` in MuJoCo, an engine independent of ours.

The Shadow hand (the default) is replayed in its own MJCF file; any other hand without ball joints
(`--hand human`) in the model `hand_mjcf.py` builds from `prehensile hands --json`, with the Shadow
file's finger servos (kp = 1 N·m/rad, ±0.9 N·m), so the two hands are replayed alike.

For each grasp result (JSON written by `prehensile grasp --hand assets/hands/shadow_hand/reach.xml
--out R.json`) and its object mesh, the same MJCF file is loaded with MjSpec and
  - the wrist joints are removed and the hand mount moved so that the palm sits exactly at the
    result's palm pose (`bones[0]`, object frame = world frame);
  - the object is added as a free body (its mesh, 0.2 kg) at the origin; MuJoCo collides a mesh
    as its convex hull, so a non-convex object (the torus, the mug) is split into convex parts by
    CoACD first (--hull-only: not);
  - every geom's friction is 1, the Shadow file's (--mu); the solver is the file's (pyramidal
    friction cones, impratio 1), or with --stiff-friction elliptic cones and impratio 10, which
    MuJoCo advises against the slow slip of its soft contacts (see world_options);
  - the hand starts at the result's joint angles; its own position actuators are commanded to the
    grasp angles plus a squeeze of 0.2 rad toward closing (tendon actuators: the tendon length of
    the grasp plus 0.2 times the tendon's coupling coefficients' sum);
  - 0.3 s without gravity lets the squeeze build, then a load of m*g along one of the six axis
    directions for 1 s; held = the object moved < 2 cm and turned < 30 degrees. Six runs per grasp.

Run from the repository root:
    pip install mujoco==4.0.0 numpy scipy pillow coacd==1.0.14 trimesh==5.2.0
    cargo build --release -p prehensile-cli
    cargo run --release -p prehensile-formats --example export_builtin_objects -- /tmp/objects
    python3 tools/mujoco/replay_grasps.py --objects /tmp/objects --seeds 1 2 3
    python3 tools/mujoco/replay_grasps.py --hand human --objects /tmp/objects --movements power
    python3 tools/mujoco/replay_grasps.py --objects /tmp/objects --movements power --stiff-friction
It searches the grasps itself (power, precision and close movements; --movements).
"""
import argparse
import itertools
import json
import os
import subprocess
import sys
import shutil
import tempfile

import mujoco
import numpy as np

import hand_mjcf

SHADOW = "assets/hands/shadow_hand/reach.xml"
HAND = SHADOW  # the hand replayed: --hand
CLI = "./target/release/prehensile"  # the build that searches: --cli
DESCRIPTION = None  # HAND as `prehensile hands --json` describes it, read once: description()
SQUEEZE = 0.2
MASS = 0.2
SETTLE = 0.3
LOAD = 1.0
DIRECTIONS = ["+x", "-x", "+y", "-y", "+z", "-z"]
CONVEX_PARTS = True  # split non-convex objects into convex parts: --hull-only turns it off
# Where the convex parts are cached: the repository's target folder, whatever the working
# directory (the Shadow scene is compiled from inside the hand's folder).
PARTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "target",
                     "mujoco_parts")
STIFF_FRICTION = False  # --stiff-friction: see world_options
MU = 1.0  # every geom's sliding friction: --mu


def quat_xyzw_to_wxyz(q):
    return np.array([q[3], q[0], q[1], q[2]])


def pose_matrix(pos, quat_wxyz):
    m = np.eye(4)
    r = np.zeros(9)
    mujoco.mju_quat2Mat(r, np.asarray(quat_wxyz, float))
    m[:3, :3] = r.reshape(3, 3)
    m[:3, 3] = pos
    return m


def matrix_pose(m):
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, m[:3, :3].flatten())
    return m[:3, 3].copy(), q


def build(result, mesh_path):
    """The scene (the Shadow file compiled inside its folder, so that its relative mesh paths
    resolve), every geom's sliding friction set to MU."""
    mesh_path = os.path.abspath(mesh_path)
    if HAND != SHADOW:
        model = build_generated(result, mesh_path)
    else:
        here = os.getcwd()
        os.chdir(os.path.dirname(HAND))
        try:
            model = build_here(result, mesh_path)
        finally:
            os.chdir(here)
    model.geom_friction[:, 0] = MU
    return model


def convex_parts(mesh_path):
    """The mesh as MuJoCo should collide it: MuJoCo collides each mesh geom as its convex hull,
    which fills the torus's hole and the mug's cup (and the fingers that grasp there end up
    inside the object). A closed mesh whose volume is under 90% of its hull's is split into
    convex parts by CoACD (PyPI `coacd`, threshold 0.03; about 5 s for the torus, 13 s for the
    mug, cached in PARTS). Returns [(OBJ file, volume)]; one part, the mesh itself, otherwise."""
    import coacd
    import trimesh
    mesh = trimesh.load(mesh_path, force="mesh")
    if not (mesh.is_watertight and mesh.volume < 0.9 * mesh.convex_hull.volume):
        return [(mesh_path, 1.0)]
    stem = os.path.splitext(os.path.basename(mesh_path))[0]
    folder = os.path.join(PARTS, f"{stem}-{len(mesh.faces)}-{mesh.volume:.9f}")
    if not os.path.isdir(folder):
        coacd.set_log_level("error")
        pieces = coacd.run_coacd(coacd.Mesh(mesh.vertices, mesh.faces), threshold=0.03)
        # Written to a folder of this process's own, then renamed into place: two replays run
        # at once both compute the parts, and the second rename finds the first's in place.
        os.makedirs(PARTS, exist_ok=True)
        scratch = tempfile.mkdtemp(prefix=f"{stem}-", dir=PARTS)
        for k, (v, f) in enumerate(pieces):
            trimesh.Trimesh(v, f).export(os.path.join(scratch, f"part{k:03}.obj"))
        try:
            os.rename(scratch, folder)
        except OSError:
            if not os.path.isdir(folder):
                raise
            shutil.rmtree(scratch)
    files = sorted(os.path.join(folder, f) for f in os.listdir(folder))
    return [(f, trimesh.load(f, force="mesh").convex_hull.volume) for f in files]


def add_object(spec, mesh_path):
    """The object: a free body with the mesh (its convex parts, see convex_parts), 0.2 kg in all
    (shared by volume); its friction is set with every other geom's in build()."""
    obj = spec.worldbody.add_body()
    obj.name = "object"
    obj.add_freejoint()
    parts = convex_parts(mesh_path) if CONVEX_PARTS else [(mesh_path, 1.0)]
    total = sum(volume for _, volume in parts)
    for k, (path, volume) in enumerate(parts):
        mesh = spec.add_mesh()
        mesh.name = f"object_mesh{k}"
        mesh.file = os.path.abspath(path)
        geom = obj.add_geom()
        geom.type = mujoco.mjtGeom.mjGEOM_MESH
        geom.meshname = mesh.name
        geom.mass = MASS * volume / total
        geom.friction = [1.0, 0.005, 0.0001]
        geom.contype = 1
        geom.conaffinity = 1


def world_options(spec):
    """No gravity until the load; with --stiff-friction, elliptic friction cones and impratio 10.

    MuJoCo's contacts are soft: at the default (pyramidal cones, impratio 1) an object whose load
    is within its friction limit still creeps, and a grasped object slowly slides out of the
    grip. MuJoCo's documentation recommends elliptic cones with impratio > 1 against this slip,
    and MuJoCo Menagerie's manipulation scenes set them; the Shadow file sets neither."""
    spec.option.gravity = [0, 0, 0]
    if STIFF_FRICTION:
        spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
        spec.option.impratio = 10


def description():
    """HAND as `prehensile hands --json` describes it (read on first use)."""
    global DESCRIPTION
    if DESCRIPTION is None:
        DESCRIPTION = hand_mjcf.describe(HAND)
    return DESCRIPTION


def build_generated(result, mesh_path):
    """A hand built from `prehensile hands --json`, its root bone fixed at the result's pose."""
    pose = result["bones"][0]["pose"]
    text = hand_mjcf.mjcf(description(), pose["position"], quat_xyzw_to_wxyz(pose["rotation_xyzw"]))
    spec = mujoco.MjSpec.from_string(text)
    add_object(spec, mesh_path)
    world_options(spec)
    return spec.compile()


def build_here(result, mesh_path):
    spec = mujoco.MjSpec.from_file(os.path.basename(HAND))
    for name in ["robot0:A_WRJ1", "robot0:A_WRJ0"]:
        spec.delete(spec.actuator(name))
    for t in list(spec.tendons):
        if "WRJ" in t.name:
            spec.delete(t)
    for s in list(spec.sensors):
        if "WRJ" in s.name:
            spec.delete(s)
    for name in ["robot0:WRJ1", "robot0:WRJ0"]:
        spec.delete(spec.joint(name))
    # The floor goes, and so do the mesh geoms and meshes: most visual meshes are not in the
    # repository (only the phalanges' are, for the tests), and the only mesh collider is the
    # forearm's.
    for g in list(spec.geoms):
        if g.name == "floor0" or g.type == mujoco.mjtGeom.mjGEOM_MESH:
            spec.delete(g)
    for m in list(spec.meshes):
        spec.delete(m)
    # Where the palm sits relative to the mount, from a compiled copy.
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    mount = model.body("robot0:hand mount").id
    palm = model.body("robot0:palm").id
    m_world = pose_matrix(data.xpos[mount], data.xquat[mount])
    p_world = pose_matrix(data.xpos[palm], data.xquat[palm])
    mount_to_palm = np.linalg.inv(m_world) @ p_world
    target = pose_matrix(result["bones"][0]["pose"]["position"],
                         quat_xyzw_to_wxyz(result["bones"][0]["pose"]["rotation_xyzw"]))
    pos, quat = matrix_pose(target @ np.linalg.inv(mount_to_palm))
    body = spec.body("robot0:hand mount")
    body.pos = pos
    body.quat = quat
    body.alt.type = mujoco.mjtOrientation.mjORIENTATION_QUAT
    add_object(spec, mesh_path)
    # With the palm welded to the world MuJoCo no longer filters its contacts with its child
    # bodies (the thumb base's box sits inside the palm's): exclude them as the free hand would.
    for child in spec.body("robot0:palm").bodies:
        exclude = spec.add_exclude()
        exclude.bodyname1 = "robot0:palm"
        exclude.bodyname2 = child.name
    world_options(spec)
    return spec.compile()


def closing_directions(movement, model):
    """Per joint name, the sign in which the result's movement closes the hand: its end angle
    minus its start angle (`prehensile hands --file HAND --json`; a build that does not give the
    start: the open angle, zero clamped into the joint's range); joints it moves less than 3
    degrees get 0."""
    details = {m["name"]: m for m in description()["movement_details"]}
    start = details[movement].get("start_angles_deg", {})
    out = {}
    for name, end_deg in details[movement]["end_angles_deg"].items():
        if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name) < 0:
            continue  # a degree of freedom the model holds fixed
        lo, hi = model.jnt_range[model.joint(name).id]
        begin = np.radians(start[name]) if name in start else np.clip(0.0, lo, hi)
        delta = np.radians(end_deg) - begin
        out[name] = float(np.sign(delta)) if abs(delta) > np.radians(3.0) else 0.0
    return out


def replay(result, mesh_path):
    angles = {j["name"]: j["angle"] for j in result["joints"]}
    closing = None
    outcomes = []
    for k, direction in enumerate(DIRECTIONS):
        model = build(result, mesh_path)
        data = mujoco.MjData(model)
        closing = closing or closing_directions(result["movement"], model)
        for name, a in angles.items():
            if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name) >= 0:
                data.qpos[model.jnt_qposadr[model.joint(name).id]] = a
        mujoco.mj_forward(model, data)
        # Squeeze past contact: each joint the movement closes is pushed 0.2 rad further in its
        # closing direction; joints the movement leaves alone (spread, twist) hold their angle.
        for i in range(model.nu):
            if model.actuator_trntype[i] != mujoco.mjtTrn.mjTRN_JOINT:
                continue
            j = model.actuator_trnid[i, 0]
            q = data.qpos[model.jnt_qposadr[j]]
            target = q + SQUEEZE * closing.get(model.joint(j).name, 0.0)
            lo, hi = model.actuator_ctrlrange[i]
            data.ctrl[i] = np.clip(target, lo, hi)
        obj = model.body("object").id
        steps = int(SETTLE / model.opt.timestep)
        for _ in range(steps):
            mujoco.mj_step(model, data)
        p0, q0 = data.xpos[obj].copy(), data.xquat[obj].copy()
        g = np.zeros(3)
        g[k // 2] = 9.81 if k % 2 == 0 else -9.81
        model.opt.gravity[:] = g
        for _ in range(int(LOAD / model.opt.timestep)):
            mujoco.mj_step(model, data)
        moved = float(np.linalg.norm(data.xpos[obj] - p0))
        dq = np.zeros(4)
        neg = np.zeros(4)
        mujoco.mju_negQuat(neg, q0)
        mujoco.mju_mulQuat(dq, data.xquat[obj], neg)
        turned = float(np.degrees(2 * np.arccos(min(1.0, abs(dq[0])))))
        outcomes.append({"direction": direction, "held": moved < 0.02 and turned < 30,
                         "moved_m": moved, "turned_degrees": turned})
    return outcomes


def search(obj, movement, seed, out, extra):
    p = subprocess.run([CLI, "grasp", "--hand", HAND, "--object", obj,
                        "--movement", movement, "--seed", str(seed), "--out", out] + extra,
                       capture_output=True, text=True)
    return p.returncode


def turned_shoulder(obj, degrees, tmp):
    """`prehensile grasp` options for the default shoulder of `obj` turned by `degrees` about the
    vertical through its centre of mass (none for 0). The default shoulder and the centre of mass
    are read off a search's result, which records both whether or not it found a grasp."""
    if degrees == 0:
        return []
    out = os.path.join(tmp, "default_shoulder.json")
    search(obj, "power", 1, out, ["--budget-ms", "1"])
    result = json.load(open(out))
    c, s = np.array(result["center_of_mass"]), np.array(result["shoulder"])
    a = np.radians(degrees)
    turn = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    x, y, z = c + turn @ (s - c)
    return ["--shoulder", f"{x:.9g},{y:.9g},{z:.9g}"]


def meshes(objects):
    """The objects replayed: name (as `prehensile grasp --object` takes it) -> mesh file, the
    built-in objects from the folder `objects` and the closed robosuite scans."""
    out = {name: os.path.join(objects, f"{name}.obj")
           for name in ["sphere", "box", "cylinder", "torus", "mug"]}
    for f in ["robosuite_lemon.stl", "robosuite_milk.stl", "robosuite_bread.stl",
              "robosuite_cereal.stl", "robosuite_can.obj"]:
        out[f"assets/objects/{f}"] = f"assets/objects/{f}"
    return out


def main():
    global HAND, CLI, CONVEX_PARTS, STIFF_FRICTION, MU
    ap = argparse.ArgumentParser()
    ap.add_argument("--objects", required=True, help="folder of the built-in objects as OBJ")
    ap.add_argument("--hand", default=SHADOW,
                    help="the Shadow hand's MJCF (default), or a hand name or file without ball "
                         "joints, replayed in the model hand_mjcf.py builds")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--shoulder-turns", type=float, nargs="+", default=[0.0],
                    help="shoulders: the default one turned by these degrees about the vertical "
                         "through the object's centre of mass (default: 0, the default shoulder)")
    ap.add_argument("--movements", nargs="+", default=["power", "precision", "close"])
    ap.add_argument("--cli", default=CLI,
                    help="the prehensile binary that searches (to compare builds side by side)")
    ap.add_argument("--grasp-args", default="",
                    help="more options for `prehensile grasp`, e.g. '--weights 5,1,0,1,2'")
    ap.add_argument("--hull-only", action="store_true",
                    help="collide each object as one convex hull instead of its convex "
                         "decomposition (the torus and the mug then lose their hole and cup)")
    ap.add_argument("--stiff-friction", action="store_true",
                    help="elliptic friction cones and impratio 10, MuJoCo's advice against slip "
                         "(default: the Shadow file's pyramidal cones, impratio 1)")
    ap.add_argument("--mu", type=float, default=MU,
                    help="sliding friction of every geom, hand and object (default 1, the "
                         "Shadow file's)")
    ap.add_argument("--require", type=float,
                    help="exit with status 1 if fewer than this share of the valid grasps hold "
                         "in >= 5 of 6 directions (CI uses it against regressions)")
    ap.add_argument("--keep", help="folder to keep each result JSON with its MuJoCo outcome in")
    args = ap.parse_args()
    HAND, CLI, CONVEX_PARTS = args.hand, args.cli, not args.hull_only
    hand_mjcf.CLI = args.cli  # the same build describes the hand it searched with
    STIFF_FRICTION, MU = args.stiff_friction, args.mu
    total = held6 = held5 = gravity = 0
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for obj, mesh in meshes(args.objects).items():
            for movement, turn, seed in itertools.product(args.movements, args.shoulder_turns,
                                                          args.seeds):
                out = os.path.join(tmp, "r.json")
                extra = args.grasp_args.split() + turned_shoulder(obj, turn, tmp)
                code = search(obj, movement, seed, out, extra)
                label = seed if turn == 0 else f"{seed}, shoulder turned {turn:+g} deg"
                if code != 0:
                    rows.append((obj, movement, label, "no valid grasp"))
                    continue
                result = json.load(open(out))
                outcomes = replay(result, mesh)
                n = sum(o["held"] for o in outcomes)
                if args.keep:
                    os.makedirs(args.keep, exist_ok=True)
                    result["mujoco"] = outcomes
                    turned = "" if turn == 0 else f"_turn{turn:+g}"
                    name = f"{obj.split('/')[-1].split('.')[0]}_{movement}_{seed}{turned}.json"
                    with open(os.path.join(args.keep, name), "w") as f:
                        json.dump(result, f)
                total += 1
                held6 += n == 6
                held5 += n >= 5
                gravity += outcomes[5]["held"]
                rows.append((obj, movement, label, f"held in {n} of 6 "
                             f"({' '.join(o['direction'] for o in outcomes if o['held'])}); "
                             f"epsilon {result['stability']['epsilon']:.3f}, "
                             f"{len(result['contacts'])} contacts, "
                             f"fingers {','.join(result['fingers_touching'])}"))
    for r in rows:
        print(f"{r[0].split('/')[-1]:<24} {r[1]:<10} seed {r[2]}: {r[3]}")
    print(f"{total} valid {description()['name']} grasps replayed in MuJoCo {mujoco.__version__}: "
          f"{held5} held in >= 5 of 6 directions, {held6} in all 6, {gravity} against gravity (-z)")
    if args.require is not None and not (total > 0 and held5 >= args.require * total):
        print(f"FAILED: {held5} of {total} held in >= 5 directions, {args.require:.0%} required")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
