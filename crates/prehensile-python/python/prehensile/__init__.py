"""Grasp poses for virtual hands, and physically simulated grasping.

The same library as the ``prehensile`` command-line tool (same defaults, same messages):

>>> import prehensile
>>> result = prehensile.grasp("human", "mug")
>>> result.valid, result.movement, result.joint_angles.shape
(True, 'power', (24,))

- :class:`Hand` and :class:`Object` load built-in models, files, or (objects) numpy arrays;
- :func:`grasp` searches a grasp (every option of ``prehensile grasp``);
- :class:`Planner` is the anytime planner for interactive loops;
- :func:`simulate` runs the Pollard & Zordan controller in the simulation (reduced-coordinate engine by default, rapier on request);
- :func:`batch` writes a resumable Parquet dataset (``prehensile batch``), and
  :mod:`prehensile.ray_batch` shards one over a Ray cluster;
- :func:`check` reports on a mesh file.

Searches and simulations release the GIL. Every error is a :class:`PrehensileError`, raised as
the subclass of its kind: :class:`ParameterError` (an argument's value or name),
:class:`FileFormatError`, :class:`HandError`, :class:`MeshError`, :class:`SearchError`,
:class:`SimulationError` and :class:`BatchError`. :func:`defaults` gives every function's
defaults as the library holds them.
"""
from ._prehensile import (
    BatchError,
    FileFormatError,
    GraspResultPy as GraspResult,
    Hand,
    HandError,
    MeshError,
    Object,
    ParameterError,
    Planner,
    PrehensileError,
    SearchError,
    SimulationError,
    __version__,
    batch,
    builtins,
    check,
    defaults,
    expand_objects,
    grasp,
    simulate,
)

__all__ = [
    "BatchError",
    "FileFormatError",
    "GraspResult",
    "Hand",
    "HandError",
    "MeshError",
    "Object",
    "ParameterError",
    "Planner",
    "PrehensileError",
    "SearchError",
    "SimulationError",
    "__version__",
    "batch",
    "builtins",
    "check",
    "defaults",
    "expand_objects",
    "grasp",
    "simulate",
]
