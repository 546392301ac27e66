"""Rigid-transform helpers of the simulations: quaternions (w, x, y, z as MuJoCo; a plan file writes
x, y, z, w), rotation matrices, 4x4 poses. Used by closing.py and replay.py."""
import math

import mujoco
import numpy as np


def quat_axis_angle(axis, ang):
    q = np.zeros(4)
    mujoco.mju_axisAngle2Quat(q, np.asarray(axis, float), float(ang))
    return q


def mat_of_quat(q):
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, np.asarray(q, float))
    return R.reshape(3, 3)


def quat_of_mat(R):
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.asarray(R, float).reshape(9))
    return q


def rz(phi):
    c, s = math.cos(phi), math.sin(phi)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def quat_wxyz(q_xyzw):
    x, y, z, w = q_xyzw
    q = np.array([w, x, y, z], float)
    return q / np.linalg.norm(q)


def pose_T(p):
    """Plan pose {xyz, quat_xyzw} -> 4x4."""
    T = np.eye(4)
    T[:3, :3] = mat_of_quat(quat_wxyz(p["quat_xyzw"]))
    T[:3, 3] = p["xyz"]
    return T


def T_of(pos, q):
    T = np.eye(4)
    T[:3, :3] = mat_of_quat(q)
    T[:3, 3] = pos
    return T


def inv(T):
    Ti = np.eye(4)
    Ti[:3, :3] = T[:3, :3].T
    Ti[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return Ti


def rot_angle(Ra, Rb):
    c = (np.trace(Ra.T @ Rb) - 1) / 2
    return math.acos(max(-1.0, min(1.0, c)))


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
