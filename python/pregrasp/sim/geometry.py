"""Rigid transforms of the replay (quaternions w, x, y, z as MuJoCo; a plan file writes x, y, z, w; 4x4 poses)
and the UR arms' forward kinematics (standard DH, the lengths of crates/robot/src/model.rs)."""
import math

import mujoco
import numpy as np

# UR standard DH lengths (m), as crates/robot/src/model.rs (UrModel::dh); checked against `pregrasp kin fk`
DH = {"ur3e": (0.15185, -0.24355, -0.2132, 0.13105, 0.08535, 0.0921),
      "ur5e": (0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996),
      "ur10e": (0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655),
      "ur16e": (0.1807, -0.4784, -0.36, 0.17415, 0.11985, 0.11655),
      "ur5": (0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823)}


def mat_of_quat(q):
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, np.asarray(q, float))
    return R.reshape(3, 3)


def quat(R):
    """Quaternion (w, x, y, z) of a rotation matrix."""
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.asarray(R, float).reshape(9))
    return q


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


def dh_fk(model, q):
    """Flange pose of a UR arm `model` (a key of DH) at joints q, in its base frame."""
    if model not in DH:
        raise ValueError(f"arm model {model!r} has no DH lengths here (known: {', '.join(DH)})")
    d1, a2, a3, d4, d5, d6 = DH[model]
    a = [0, a2, a3, 0, 0, 0]
    d = [d1, 0, 0, d4, d5, d6]
    al = [math.pi / 2, 0, 0, math.pi / 2, -math.pi / 2, 0]
    T = np.eye(4)
    for i in range(6):
        ct, st, ca, sa = math.cos(q[i]), math.sin(q[i]), math.cos(al[i]), math.sin(al[i])
        T = T @ np.array([[ct, -st * ca, st * sa, a[i] * ct], [st, ct * ca, -ct * sa, a[i] * st],
                          [0, sa, ca, d[i]], [0, 0, 0, 1.0]])
    return T
