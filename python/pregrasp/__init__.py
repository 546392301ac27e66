"""pregrasp: dual-arm pre-grasp manipulation planning from Python.

A heavy, flat part lies on a table. pregrasp finds how one arm can rotate it about one of its
edges while the table carries its weight, until both grippers can take power grasps, and plans
every motion of both arms (the Rust library behind the ``pregrasp`` CLI; same plans, byte for
byte but ``timing_ms``).

>>> import pregrasp
>>> scene = pregrasp.Scene.load("chair_side.toml")
>>> plan = pregrasp.plan(scene)
>>> plan.status, plan.plans[0].segment("rot").q.shape

In a cell, :class:`Replanner` replans a plan each time the part is measured again:

>>> cell = pregrasp.Replanner(scene, plan)
>>> again = cell.replan(measured_pose)      # 4x4, brought onto the table first

Before the robot moves, :func:`simulate` replays a plan in MuJoCo (two Robotiq 2F-85 grippers, the part a
free body on the table, then a lift; ``pip install "pregrasp[sim]"``):

>>> result = pregrasp.simulate("plan.json", lift=0.05)
>>> result.verdict.passed, result.lift.rise_mm, [s.name for s in result.segments]

Errors: :class:`SceneError` (a scene or its mesh cannot be used), :class:`PlanFileError`
(a plan file cannot be read or written); both derive from :class:`PregraspError` and carry the
CLI's message, which names the file and the key.
"""

from __future__ import annotations

import os
from typing import Optional, Union

from . import _pregrasp as _ext
from ._pregrasp import (
    Plan,
    PlanEntry,
    PlanFileError,
    PregraspError,
    Replanner,
    Report,
    Scene,
    SceneError,
    Segment,
    __version__,
    default_robots,
)
from . import batch, kin
from .sim import SimResult, SimulationError, simulate

__all__ = [
    "Plan",
    "PlanEntry",
    "PlanFileError",
    "PregraspError",
    "Replanner",
    "Report",
    "Scene",
    "SceneError",
    "Segment",
    "SimResult",
    "SimulationError",
    "__version__",
    "axes",
    "batch",
    "check",
    "default_robots",
    "kin",
    "plan",
    "simulate",
    "write_examples",
]

PathLike = Union[str, "os.PathLike[str]"]


def _scene(scene_or_path: Union[Scene, PathLike]) -> Scene:
    if isinstance(scene_or_path, Scene):
        return scene_or_path
    return Scene.load(os.fspath(scene_or_path))


def plan(
    scene_or_path: Union[Scene, PathLike],
    *,
    threads: Optional[int] = None,
    max_plans: Optional[int] = None,
) -> Plan:
    """Plan a scene (a :class:`Scene` or the path of a scene file): Algorithms 1-3, every plan
    re-verified by the checker, as ``pregrasp plan`` does.

    ``threads``: worker threads for the candidates (default: all cores; the plan is the same
    for any number). ``max_plans``: keep at most this many plans, best first (default 3).
    The GIL is released while planning, so several threads can plan at once.
    Raises :class:`SceneError` for a scene that cannot be used.
    """
    if threads is not None and threads < 1:
        raise ValueError(f"threads must be >= 1, found {threads}")
    if max_plans is not None and max_plans < 1:
        raise ValueError(f"max_plans must be >= 1, found {max_plans}")
    return _ext.plan_scene(_scene(scene_or_path), threads, max_plans)


def axes(scene_or_path: Union[Scene, PathLike]) -> list:
    """Algorithm 1 on a scene: the rotation-axis candidates, best score first, as dicts with
    ``id``, ``axis`` (world endpoints at P_init), ``direction``, ``length``, ``theta_max``,
    ``score`` (``pregrasp axes --json``)."""
    return _ext.axes(_scene(scene_or_path))


def check(plan_or_path: Union[Plan, PathLike], *, mesh: Optional[PathLike] = None) -> Report:
    """Re-verify a plan (a :class:`Plan` or the path of a plan file) against every rule of
    the plan format, as ``pregrasp check`` does. ``mesh``: the part's mesh file when the plan
    does not carry it (a plan read from a file finds the mesh it names, as written or next to
    the file). Raises :class:`PlanFileError` for an unreadable plan file."""
    p = plan_or_path if isinstance(plan_or_path, Plan) else Plan.load(os.fspath(plan_or_path))
    return _ext.check_plan(p, None if mesh is None else os.fspath(mesh))


def write_examples(directory: PathLike, only: Optional[str] = None) -> list:
    """Write the built-in example scenes (chair, shelf and stool side) and their meshes into
    ``directory``, as ``pregrasp example write`` does; returns the scene file paths."""
    return [str(p) for p in _ext.write_examples(os.fspath(directory), only)]
