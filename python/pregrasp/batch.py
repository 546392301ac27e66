"""Many parts at once: every scene of a folder planned into plan files, viewer pages and a
summary (``summary.csv``, ``summary.json``, ``report.html``), the same as ``pregrasp batch``.

``backend="local"`` plans in this process on all cores (the Rust batch, rayon).
``backend="ray"`` makes one Ray task per scene (https://docs.ray.io): on a laptop
(``ray.init(num_cpus=2)``) or fanned out over a cluster (``ray.init(address="auto")``). Every
task calls this package, so it must be installed on every node, and the scene folder and
``out`` must be paths every node can read and write (a shared filesystem, mounted at the same
path; each task works in the caller's working directory), as for any batch of files on a
cluster. Either way the records and the summary files are the same, but for the
planning times.
"""

from __future__ import annotations

import json
import os
import sys
from typing import Iterable, List, Optional, Union

from . import _pregrasp as _ext

__all__ = ["run", "discover"]

PathLike = Union[str, "os.PathLike[str]"]


def discover(directory: PathLike, out: Optional[PathLike] = None) -> List[str]:
    """The scene files (``*.toml``) under ``directory``, sorted, ``out`` left out. Raises
    :class:`pregrasp.PregraspError` if it is not a folder or holds no scene."""
    return [
        str(p)
        for p in _ext.batch_discover(
            os.fspath(directory), None if out is None else os.fspath(out)
        )
    ]


def _scenes(source: Union[PathLike, Iterable[PathLike]], out: str):
    if isinstance(source, (str, os.PathLike)):
        directory = os.fspath(source)
        return directory, discover(directory, out)
    scenes = [os.fspath(s) for s in source]
    if not scenes:
        raise ValueError("no scene files given")
    directory = os.path.commonpath([os.path.dirname(os.path.abspath(s)) for s in scenes])
    return directory, [os.path.abspath(s) for s in scenes]


def run(
    source: Union[PathLike, Iterable[PathLike]],
    out: PathLike = "batch-out",
    *,
    backend: str = "local",
    max_plans: int = 3,
    threads: Optional[int] = None,
    title: Optional[str] = None,
    progress: bool = False,
) -> List[dict]:
    """Plan every scene of ``source`` (a folder, searched recursively, or a list of scene
    files) into ``out`` and write ``summary.csv``, ``summary.json`` and ``report.html`` there.

    Returns the summary records (dicts: ``scene``, ``status`` planned / no_plan / error,
    ``reason``, ``best_score``, ``theta_goal_deg``, ``plans``, ``grip_force``, ``check``,
    ``time_ms``, ``reused``, ``plan_file``, ``view_file``), in the order of the scenes. A scene
    that cannot be loaded is an ``error`` record, never the end of the batch; a scene whose
    plan is up to date (same scene text, mesh bytes and pregrasp version) is reused.

    ``backend``: ``"local"`` (``threads`` workers, default all cores) or ``"ray"`` (one task per
    scene; uses the running Ray instance, or starts a local one).
    """
    out_s = os.fspath(out)
    directory, scenes = _scenes(source, out_s)
    if backend == "local":
        records = json.loads(_ext.batch_run(directory, out_s, scenes, max_plans, threads))
    elif backend == "ray":
        records = _run_ray(directory, out_s, scenes, max_plans, progress)
    else:
        raise ValueError(f'backend must be "local" or "ray", found {backend!r}')
    _ext.batch_write_report(
        out_s, json.dumps(records), title or f"pregrasp batch: {directory}"
    )
    return records


def _plan_one(cwd: str, directory: str, out: str, scene: str, max_plans: int) -> dict:
    from pregrasp import _pregrasp

    # Work in the driver's directory (on a shared filesystem it exists on every node), so that
    # relative paths, and the messages that name them, are the same as in a local batch.
    os.chdir(cwd)
    return json.loads(_pregrasp.batch_plan_one(directory, out, scene, max_plans))


def _run_ray(directory: str, out: str, scenes: List[str], max_plans: int, progress: bool):
    try:
        import ray
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError(
            'backend="ray" needs Ray: pip install "pregrasp[ray]" (or pip install ray)'
        ) from e
    if not ray.is_initialized():
        ray.init()
    task = ray.remote(_plan_one)
    cwd = os.getcwd()
    os.makedirs(out, exist_ok=True)
    refs = [task.remote(cwd, directory, out, s, max_plans) for s in scenes]
    if progress:
        pending, done = list(refs), 0
        while pending:
            ready, pending = ray.wait(pending, num_returns=1)
            done += len(ready)
            print(f"\rplanned {done}/{len(refs)} scenes", end="", file=sys.stderr)
        print(file=sys.stderr)
    return ray.get(refs)
