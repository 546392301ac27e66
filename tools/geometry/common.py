"""Shared helpers: reading files from bare git mirrors, rigid transforms."""
import io
import subprocess

import numpy as np
import trimesh


def git_show(repo, path, rev="HEAD"):
    return subprocess.run(["git", "-C", repo, "show", f"{rev}:{path}"],
                          capture_output=True, check=True).stdout


def git_head(repo):
    return subprocess.run(["git", "-C", repo, "rev-parse", "HEAD"],
                          capture_output=True, check=True, text=True).stdout.strip()


def git_last_change(repo, paths):
    out = subprocess.run(["git", "-C", repo, "log", "-1", "--format=%H %cs", "--", *paths],
                         capture_output=True, check=True, text=True).stdout.strip()
    return out


def load_stl(repo, path):
    data = git_show(repo, path)
    m = trimesh.load(io.BytesIO(data), file_type="stl", process=True)
    m.merge_vertices()
    return m


def rotx(a):
    c, s = np.cos(a), np.sin(a)
    T = np.eye(4); T[1, 1] = c; T[1, 2] = -s; T[2, 1] = s; T[2, 2] = c
    return T


def roty(a):
    c, s = np.cos(a), np.sin(a)
    T = np.eye(4); T[0, 0] = c; T[0, 2] = s; T[2, 0] = -s; T[2, 2] = c
    return T


def rotz(a):
    c, s = np.cos(a), np.sin(a)
    T = np.eye(4); T[0, 0] = c; T[0, 1] = -s; T[1, 0] = s; T[1, 1] = c
    return T


def trans(x, y, z):
    T = np.eye(4); T[:3, 3] = (x, y, z)
    return T


def urdf_origin(xyz, rpy):
    """URDF <origin>: translation, then fixed-axis roll-pitch-yaw (R = Rz(y) Ry(p) Rx(r))."""
    return trans(*xyz) @ rotz(rpy[2]) @ roty(rpy[1]) @ rotx(rpy[0])


def apply(T, P):
    P = np.asarray(P, float)
    return P @ T[:3, :3].T + T[:3, 3]


def r6(x):
    """Round nested floats to 6 decimals (and kill -0.0)."""
    if isinstance(x, (list, tuple, np.ndarray)):
        return [r6(v) for v in x]
    v = round(float(x), 6)
    return 0.0 if v == 0 else v
