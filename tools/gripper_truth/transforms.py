"""Rigid-transform helpers of the simulations: quaternions (w, x, y, z as MuJoCo; a plan file writes
x, y, z, w), rotation matrices, 4x4 poses. Used by closing.py and replay.py. The pose helpers the
Python package's replay shares are its own (python/pregrasp/sim/geometry.py, loaded by path: numpy
and mujoco only); the rest are the tools' alone."""
import importlib.util
import math
from pathlib import Path

import mujoco
import numpy as np

_spec = importlib.util.spec_from_file_location(
    "pregrasp_sim_geometry", Path(__file__).resolve().parents[2] / "python/pregrasp/sim/geometry.py")
_geometry = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_geometry)
mat_of_quat = _geometry.mat_of_quat
quat_of_mat = _geometry.quat
quat_wxyz = _geometry.quat_wxyz
pose_T = _geometry.pose_T
T_of = _geometry.T_of
inv = _geometry.inv
rot_angle = _geometry.rot_angle


def quat_axis_angle(axis, ang):
    q = np.zeros(4)
    mujoco.mju_axisAngle2Quat(q, np.asarray(axis, float), float(ang))
    return q


def rz(phi):
    c, s = math.cos(phi), math.sin(phi)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def slerp(q0, q1, u):
    q0, q1 = np.asarray(q0, float), np.asarray(q1, float)
    d = float(q0 @ q1)
    if d < 0:
        q1, d = -q1, -d
    if d > 0.9995:
        q = q0 + u * (q1 - q0)
        return q / np.linalg.norm(q)
    th = math.acos(d)
    return (math.sin((1 - u) * th) * q0 + math.sin(u * th) * q1) / math.sin(th)
