"""Kinematics of the built-in arms (UR3e, UR5e, UR10e, UR16e, UR5): standard DH in the
controller's base frame, flange frame = tool0 (z out of the flange). Metres and radians."""

from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from . import _pregrasp as _ext

__all__ = ["fk", "ik"]


def fk(q: Sequence[float], model: str = "ur5e") -> np.ndarray:
    """Flange pose (4x4 homogeneous matrix, base frame) at joint angles ``q`` (6, rad)."""
    return _ext.fk([float(x) for x in np.asarray(q, dtype=float).ravel()], model)


def ik(pose, model: str = "ur5e", seed: Optional[Sequence[float]] = None) -> np.ndarray:
    """Every joint solution (K, 6) that puts the flange at ``pose`` (4x4, base frame), within
    the joint limits (with the +-2 pi alternates they allow), nearest to ``seed`` first;
    K = 0 when the pose is out of reach."""
    p = np.ascontiguousarray(pose, dtype=np.float64)
    s = None if seed is None else [float(x) for x in np.asarray(seed, dtype=float).ravel()]
    return _ext.ik(p, model, s)
