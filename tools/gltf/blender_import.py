"""Imports a GLB in Blender headless and prints what it found (a manual check, not run by CI).

    apt-get install blender python3-numpy
    blender -b --factory-startup --python tools/gltf/blender_import.py -- scene.glb

Debian's Blender 3.4 glTF importer still uses numpy.bool, which numpy 1.24 removed; the alias
below restores it (a packaging mismatch, not something in the file).
"""
import sys

import numpy

numpy.bool = bool
import bpy  # noqa: E402

for path in sys.argv[sys.argv.index("--") + 1:]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    result = bpy.ops.import_scene.gltf(filepath=path)
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    armatures = [o for o in bpy.data.objects if o.type == "ARMATURE"]
    frames = [tuple(a.frame_range) for a in bpy.data.actions]
    print(f"{path}: {result} {len(meshes)} meshes, {len(armatures)} armatures, "
          f"{len(bpy.data.actions)} actions, frames {frames[:1]}")
