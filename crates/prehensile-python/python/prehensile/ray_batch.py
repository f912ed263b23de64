"""A grasp dataset across a Ray cluster: ``prehensile batch`` sharded by hand and object.

    python -m prehensile.ray_batch --hands human robot3 --objects 'scans/*.stl' \\
        --seeds 8 --out grasps [--address auto]

Each shard (one hand, one object, every movement, shoulder and seed) is a Ray task that runs
:func:`prehensile.batch` in a scratch folder on its worker and returns the finished part files;
the driver writes them into ``OUT/shard-HHHH-OOOOO/`` with a rename, so a shard is in the
dataset whole or not at all. The rows are the same as ``prehensile batch`` writes for the same
inputs (the search depends only on its inputs and seed), and ``pandas.read_parquet(OUT)`` reads
the folder as one table.

Resuming: run the same command again; finished shards are kept, the rest run. A shard whose task
fails (its worker died and Ray's retries ran out) is listed in ``OUT/_failed_shards.json`` and
the others go on; the command then exits with status 1 and says to run it again.

Hand and mesh files must be readable at the same path on every node (a shared file system, or
the same checkout); the results travel back to the driver through Ray.
"""
import argparse
import json
import os
import shutil
import sys
import tempfile

import prehensile

SCHEMA = "prehensile.ray_batch/1"


def _shard_name(hand_index, object_index):
    return f"shard-{hand_index:04d}-{object_index:05d}"


def _run_shard(hand, obj, settings):
    """Runs one shard in a scratch folder; returns {file name: bytes} of its dataset."""
    with tempfile.TemporaryDirectory(prefix="prehensile-shard-") as scratch:
        folder = os.path.join(scratch, "dataset")
        prehensile.batch(folder, hands=[hand], objects=[obj], **settings)
        out = {}
        for name in sorted(os.listdir(folder)):
            with open(os.path.join(folder, name), "rb") as f:
                out[name] = f.read()
        return out


def _write_shard(out, name, files):
    """Writes a shard's files under a dot-named folder, then renames it into place."""
    final = os.path.join(out, name)
    partial = os.path.join(out, "." + name + ".partial")
    shutil.rmtree(partial, ignore_errors=True)
    os.makedirs(partial)
    for file_name, data in files.items():
        with open(os.path.join(partial, file_name), "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
    os.rename(partial, final)


def run(hands, objects, out, movements=("auto",), shoulders=("default",), seeds=1, units="m",
        scale=1.0, up="z", friction=0.5, validity="holds", max_retries=2, progress=True,
        one_sided_patience=120):
    """Runs the batch on the connected Ray cluster (call ``ray.init`` first, or let this call it
    with its defaults). Returns a summary dict."""
    import ray

    if not ray.is_initialized():
        ray.init()
    objects = prehensile.expand_objects(list(objects))
    hands = list(hands)
    settings = dict(movements=list(movements), shoulders=list(shoulders), seeds=int(seeds),
                    units=units, scale=float(scale), up=up, friction=float(friction),
                    validity=validity, one_sided_patience=int(one_sided_patience))
    plan = dict(hands=hands, objects=objects, **settings)
    os.makedirs(out, exist_ok=True)
    manifest_path = os.path.join(out, "_manifest.json")
    if os.path.exists(manifest_path):
        with open(manifest_path) as f:
            found = json.load(f)
        if found.get("schema") != SCHEMA or found.get("plan") != plan:
            raise prehensile.PrehensileError(
                f"{out} holds a dataset made with other inputs; use another --out folder, or "
                "delete it to start over")
    else:
        strangers = [n for n in os.listdir(out) if not n.startswith(".")]
        if strangers:
            raise prehensile.PrehensileError(
                f"{out}: the folder is not empty ({strangers[0]} is there) and has no "
                "_manifest.json; choose an empty or new folder")
        with open(manifest_path + ".partial", "w") as f:
            json.dump({"schema": SCHEMA, "prehensile_version": prehensile.__version__,
                       "plan": plan}, f, indent=2)
        os.rename(manifest_path + ".partial", manifest_path)
    for name in os.listdir(out):
        if name.endswith(".partial"):
            shutil.rmtree(os.path.join(out, name), ignore_errors=True)

    task = ray.remote(max_retries=max_retries)(_run_shard)
    pending = {}
    already = 0
    for h, hand in enumerate(hands):
        for o, obj in enumerate(objects):
            name = _shard_name(h, o)
            if os.path.isdir(os.path.join(out, name)):
                already += 1
                continue
            pending[task.remote(hand, obj, settings)] = (name, hand, obj)
    total = len(hands) * len(objects)
    failed = []
    done = 0
    waiting = list(pending)
    while waiting:
        ready, waiting = ray.wait(waiting, num_returns=1)
        name, hand, obj = pending[ready[0]]
        try:
            _write_shard(out, name, ray.get(ready[0]))
        except (ray.exceptions.RayError, prehensile.PrehensileError) as e:
            failed.append({"shard": name, "hand": hand, "object": obj, "error": str(e)})
        done += 1
        if progress:
            print(f"\r{already + done}/{total} shards ({len(failed)} failed)", end="",
                  file=sys.stderr, flush=True)
    if progress and pending:
        print(file=sys.stderr)
    failed_path = os.path.join(out, "_failed_shards.json")
    if failed:
        with open(failed_path, "w") as f:
            json.dump(failed, f, indent=2)
    elif os.path.exists(failed_path):
        os.remove(failed_path)
    return {"shards": total, "already_done": already, "ran": done - len(failed),
            "failed": failed}


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m prehensile.ray_batch", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hands", nargs="+", default=["human"])
    ap.add_argument("--objects", nargs="+", default=list(prehensile.builtins()["objects"]))
    ap.add_argument("--movements", nargs="+", default=["auto"])
    ap.add_argument("--shoulders", nargs="+", default=["default"])
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--out", default="prehensile-dataset")
    ap.add_argument("--units", default="m", choices=["m", "cm", "mm"])
    ap.add_argument("--scale", type=float, default=1.0)
    ap.add_argument("--up", default="z", choices=["x", "y", "z"])
    ap.add_argument("--friction", type=float, default=0.5)
    ap.add_argument("--validity", default="holds", choices=["holds", "strict", "thesis"])
    ap.add_argument("--one-sided-patience", type=int, default=120,
                    help="steps to look past a power grasp whose contacts push from one side")
    ap.add_argument("--address", default=None,
                    help="Ray cluster address (e.g. auto); default: start a local one")
    ap.add_argument("--num-cpus", type=int, default=None, help="CPUs of a local cluster")
    args = ap.parse_args(argv)
    import ray

    ray.init(address=args.address, num_cpus=args.num_cpus)
    try:
        summary = run(args.hands, args.objects, args.out, args.movements, args.shoulders,
                      args.seeds, args.units, args.scale, args.up, args.friction, args.validity,
                      one_sided_patience=args.one_sided_patience)
    except prehensile.PrehensileError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(f"{summary['shards']} shards in {args.out}: this run finished {summary['ran']}, "
          f"{summary['already_done']} were already there, {len(summary['failed'])} failed")
    if summary["failed"]:
        print(f"see {os.path.join(args.out, '_failed_shards.json')}; run the same command again "
              "to retry them", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
