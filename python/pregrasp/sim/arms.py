"""The flange pose of a plan's arm at its joints, for the replay: the UR arms by their DH parameters
(`geometry.dh_fk`), an arm described by a URDF (`robots[].urdf` of the plan file) by its joint chain from
`base_link` to `tool_link`, read here with the standard library: the replay's own kinematics, not the planner's.

URDF conventions: a joint's `<origin xyz rpy>` places its frame in its parent link's (rotation
Rz(yaw) Ry(pitch) Rx(roll)); a revolute or continuous joint then turns about `<axis>` (default x) by its value, a
prismatic one slides along it; a fixed joint is its origin alone. The planner drives six of the chain's moving
joints (`robots[].joint_names`, in that order) and holds the others at `urdf.held`."""

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from .geometry import DH, dh_fk


class ArmError(ValueError):
    """An arm the replay cannot place: an unknown model, a description it cannot read or follow."""


def _floats(text, n, default, where):
    if text is None:
        return np.array(default, float)
    try:
        v = np.array([float(x) for x in text.split()], float)
    except ValueError:
        raise ArmError(f"{where}: not numbers: {text!r}") from None
    if v.shape != (n,) or not np.all(np.isfinite(v)):
        raise ArmError(f"{where}: expected {n} finite numbers, found {text!r}")
    return v


def _rpy(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def _axis_angle(axis, angle):
    x, y, z = axis
    c, s = math.cos(angle), math.sin(angle)
    C = 1 - c
    return np.array([[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
                     [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
                     [z * x * C - y * s, z * y * C + x * s, c + z * z * C]])


class UrdfChain:
    """The joints from `base_link` to `tool_link` of the description in `path`, base first."""

    def __init__(self, path, base_link, tool_link):
        where = str(path)
        try:
            root = ET.parse(path).getroot()
        except (OSError, ET.ParseError) as e:
            raise ArmError(f"{where}: cannot read the robot description ({e})") from None
        by_child = {}
        for j in root.iter("joint"):
            child, parent = j.find("child"), j.find("parent")
            if child is None or parent is None:
                continue
            by_child[child.get("link")] = j
        joints = []
        link = tool_link
        while link != base_link:
            j = by_child.get(link)
            if j is None:
                raise ArmError(f"{where}: no chain of joints from {base_link!r} to {tool_link!r} "
                               f"(link {link!r} has no parent joint)")
            joints.append(j)
            link = j.find("parent").get("link")
            if len(joints) > len(by_child):
                raise ArmError(f"{where}: the joints from {tool_link!r} loop")
        self.joints = []
        for j in reversed(joints):
            name, kind = j.get("name"), j.get("type")
            jw = f"{where}: joint {name!r}"
            o = j.find("origin")
            xyz = _floats(o.get("xyz") if o is not None else None, 3, [0, 0, 0], f"{jw} origin xyz")
            rpy = _floats(o.get("rpy") if o is not None else None, 3, [0, 0, 0], f"{jw} origin rpy")
            T = np.eye(4)
            T[:3, :3] = _rpy(*rpy)
            T[:3, 3] = xyz
            a = j.find("axis")
            axis = _floats(a.get("xyz") if a is not None else None, 3, [1, 0, 0], f"{jw} axis")
            if kind not in ("fixed", "revolute", "continuous", "prismatic"):
                raise ArmError(f"{jw}: type {kind!r} cannot be followed")
            if kind != "fixed":
                norm = float(np.linalg.norm(axis))
                if norm == 0:
                    raise ArmError(f"{jw}: zero axis")
                axis = axis / norm
            self.joints.append((name, kind, T, axis))

    def moving(self):
        """The names of the chain's moving joints, base first."""
        return [name for name, kind, _, _ in self.joints if kind != "fixed"]

    def fk(self, values):
        """The tool link's pose in the base link's frame, each moving joint at `values[name]`."""
        T = np.eye(4)
        for name, kind, origin, axis in self.joints:
            T = T @ origin
            if kind == "fixed":
                continue
            M = np.eye(4)
            if kind == "prismatic":
                M[:3, 3] = axis * values[name]
            else:
                M[:3, :3] = _axis_angle(axis, values[name])
            T = T @ M
        return T


def scene_folder(doc, plan_path):
    """Candidate folders of the scene file the plan was made from: as the plan says it (from the working directory),
    and by `scene.file_from_plan` from the plan file's folder."""
    scene = doc.get("scene") or {}
    out = []
    if scene.get("file"):
        out.append(Path(scene["file"]).parent)
    if plan_path and scene.get("file_from_plan"):
        out.append((Path(plan_path).resolve().parent / scene["file_from_plan"]).parent)
    if plan_path:
        out.append(Path(plan_path).resolve().parent)
    return out


def arm_fk(robot, doc, plan_path=None):
    """`fk(q)`: the flange pose of the plan's `robot` (an entry of `robots`) at its six joints `q`, in the arm's base
    frame. Raises ArmError for an arm the replay cannot place, or one carrying another gripper than the 2F-85 (the
    replay's gripper)."""
    name, model = robot.get("name"), robot.get("model")
    if robot.get("gripper") is not None:
        raise ArmError(f"robot {name!r}: gripper {robot['gripper']!r}; the replay models the Robotiq 2F-85 only")
    if model in DH:
        return lambda q: dh_fk(model, q)
    if model != "urdf" or not robot.get("urdf"):
        raise ArmError(f"robot {name!r}: model {model!r} is neither a UR arm ({', '.join(DH)}) nor a description")
    u = robot["urdf"]
    rel = Path(u["file"])
    tries = [rel] if rel.is_absolute() else [folder / rel for folder in scene_folder(doc, plan_path)] + [rel]
    path = next((p for p in tries if p.is_file()), None)
    if path is None:
        raise ArmError(f"robot {name!r}: description {u['file']} not found (tried {', '.join(map(str, tries))})")
    chain = UrdfChain(path, u["base_link"], u["tool_link"])
    driven = list(robot.get("joint_names") or [])
    held = {k: float(v) for k, v in (u.get("held") or {}).items()}
    unknown = [j for j in chain.moving() if j not in driven and j not in held]
    if len(driven) != 6 or unknown or any(j not in chain.moving() for j in driven):
        raise ArmError(f"robot {name!r}: joints {driven} and held {sorted(held)} are not the moving joints "
                       f"{chain.moving()} of {path} between {u['base_link']!r} and {u['tool_link']!r}")

    def fk(q):
        values = dict(held)
        values.update(zip(driven, (float(v) for v in q)))
        return chain.fk(values)
    return fk


def placed_arms(doc, plan_path=None):
    """`arm_fk` of every robot of the plan file `doc`, by name."""
    return {r.get("name"): arm_fk(r, doc, plan_path) for r in doc.get("robots") or []}
