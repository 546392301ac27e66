#!/usr/bin/env python3
"""Dynamic ground truth of pregrasp's rotation step: the MuJoCo Menagerie Robotiq 2F-85 pinches the part
at the support grasp G_s and turns it about its edge on the table, following the plan's `rot` segment.

    pip install mujoco numpy trimesh
    python3 tools/gripper_truth/replay.py --menagerie <menagerie> plan1.json [plan2.json ...]

For every plan of every file (or only --plans K ...), the squeeze force F is set to 0.5, 1.0, 1.5 and 2.0 x
N_min (pregrasp's minimum grip force for that plan, worst state, from `pregrasp physics --json`), and the
smallest force that holds, F*, is bisected in [0, 4 N_min] to 5 %. Writes
crates/physics/data/replay_truth/replay_2f85.{json,csv} (atomically, keys sorted, floats rounded).

Model, verdict and results: tools/gripper_truth/README.md, section "Replay of the rotation".
"""
import argparse
import datetime
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np
import trimesh

sys.path.insert(0, str(Path(__file__).resolve().parent))
from closing import (  # noqa: E402
    MODEL_DIR,
    MODEL_XML,
    csv_text,
    load_source,
    mat_of_quat as mat,
    quat_of_mat as quat,
    rnd,
    write_atomic,
)

REPO_ROOT = Path(__file__).resolve().parents[2]
OUT_DIR = REPO_ROOT / "crates/physics/data/replay_truth"
SCRIPT = "tools/gripper_truth/replay.py"
DEFAULT_PREGRASP = REPO_ROOT / "target/release/pregrasp"

# pregrasp's [physics] defaults (docs/physics.md), used when a plan carries no `physics` object
MU_PAD_DEFAULT = 0.8
MU_SUPPORT_DEFAULT = 0.4

MULTIPLIERS = [0.5, 1.0, 1.5, 2.0]
BISECT_HI = 4.0  # x N_min
BISECT_REL = 0.05  # stop when (hi - lo) <= BISECT_REL * hi

# verdict
POS_TOL = 0.005  # m, the part's grasped point G_s vs where the planned final pose puts it
ANG_TOL_DEG = 3.0
GAP_TOL = 0.01  # s: a pad "lost contact" if it touched no part geom for longer than this

# phases (simulated seconds)
T_SETTLE_OPEN = 0.2  # gripper held open (tau = TAU_OPEN), the part settles on the table
T_SPRING_CLOSE = 0.6  # tau = 0: the spring links close the fingers gently onto the part
T_RAMP = 0.3  # tau ramps to its target
T_CORRECT = 0.3  # one squeeze-correction window (force averaged over its last T_MEASURE)
T_MEASURE = 0.1
N_CORRECT = 4  # correction windows at most
T_HOLD = 1.0  # after the trajectory
TAU_OPEN = -1.0  # N (tendon force) holding the fingers open
SAMPLE_EVERY = 5  # steps between force/pose samples

GRIPPER_BODIES = ["base_mount", "base"] + [f"{s}_{ln}" for s in ("right", "left")
                                            for ln in ("driver", "coupler", "spring_link", "follower", "pad",
                                                       "silicone_pad")]
PAD_GEOMS = {"pos": ["right_pad1", "right_pad2"], "neg": ["left_pad1", "left_pad2"]}


# ----------------------------------------------------------------------------------------------------
# Small rigid-transform helpers (quaternions w, x, y, z as MuJoCo; the plan file writes x, y, z, w)
def quat_wxyz(q_xyzw):
    x, y, z, w = q_xyzw
    q = np.array([w, x, y, z], float)
    return q / np.linalg.norm(q)


def pose_T(p):
    """Plan pose {xyz, quat_xyzw} -> 4x4."""
    T = np.eye(4)
    T[:3, :3] = mat(quat_wxyz(p["quat_xyzw"]))
    T[:3, 3] = p["xyz"]
    return T


def T_of(pos, q):
    T = np.eye(4)
    T[:3, :3] = mat(q)
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


# ----------------------------------------------------------------------------------------------------
# Convex decomposition of an extruded outline (exact)
def decompose_extrusion(mesh, tol=1e-6):
    """Exact convex decomposition of a prism (a planar outline, holes allowed, extruded along z).

    The mesh's bottom-face triangles are merged greedily across shared edges while the union stays convex
    (Hertel-Mehlhorn: at most 4x the minimum number of pieces), and every convex polygon is extruded over
    the mesh's z range. The pieces tile the part exactly; `info` reports the area/volume check.
    Returns (list of (k, 3) vertex arrays, info dict). Raises ValueError if the mesh is not such a prism.
    """
    V = np.asarray(mesh.vertices, float)
    z0, z1 = V[:, 2].min(), V[:, 2].max()
    on = (np.abs(V[:, 2] - z0) < tol) | (np.abs(V[:, 2] - z1) < tol)
    if not on.all():
        raise ValueError("not an extrusion along z: vertices between the bottom and top faces")
    key = {}
    pts = []

    def k_of(i):
        kk = (round(V[i, 0] / tol), round(V[i, 1] / tol))
        if kk not in key:
            key[kk] = len(pts)
            pts.append(V[i, :2])
        return key[kk]

    polys = []
    for f in mesh.faces:
        if all(abs(V[i, 2] - z0) < tol for i in f):
            ids = [k_of(i) for i in f]
            a, b, c = (pts[i] for i in ids)
            if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0:
                ids = ids[::-1]  # counter-clockwise seen from +z
            polys.append(ids)
    P = np.array(pts)
    tri_area = sum(poly_area(P[p]) for p in polys)

    def convex(cycle):
        Q = P[cycle]
        n = len(Q)
        for i in range(n):
            a, b, c = Q[i - 1], Q[i], Q[(i + 1) % n]
            if (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) < -1e-12:
                return False
        return True

    changed = True
    while changed:
        changed = False
        edge = {}
        for pi, p in enumerate(polys):
            if p is None:
                continue
            for i in range(len(p)):
                edge[(p[i], p[(i + 1) % len(p)])] = pi
        # longest shared edges first (removing long diagonals gives fewer, fatter pieces); ties by ids
        shared = [(a, b) for (a, b) in edge if (b, a) in edge and a < b]
        shared.sort(key=lambda e: (-np.linalg.norm(P[e[0]] - P[e[1]]), e))
        for a, b in shared:
            pi, qi = edge.get((a, b)), edge.get((b, a))
            if pi is None or qi is None or pi == qi or polys[pi] is None or polys[qi] is None:
                continue
            p, q = polys[pi], polys[qi]
            if (a, b) not in zip(p, p[1:] + p[:1]) or (b, a) not in zip(q, q[1:] + q[:1]):
                continue
            i = p.index(a)
            pr = p[i + 1:] + p[:i + 1]  # b ... a
            j = q.index(b)
            qr = q[j + 1:] + q[:j + 1]  # a ... b
            merged = pr + qr[1:-1]
            if convex(merged):
                polys[pi], polys[qi] = merged, None
                for e in zip(merged, merged[1:] + merged[:1]):
                    edge[e] = pi
                changed = True
    polys = [p for p in polys if p is not None]
    pieces = []
    for p in polys:
        Q = P[p]
        pieces.append(np.vstack([np.c_[Q, np.full(len(Q), z0)], np.c_[Q, np.full(len(Q), z1)]]))
    area = sum(poly_area(P[p]) for p in polys)
    vol = area * (z1 - z0)
    info = {"method": "exact: Hertel-Mehlhorn merge of the STL's bottom-face triangles, each convex polygon "
                      "extruded over the part's thickness (the parts are extruded outlines)",
            "pieces": len(pieces), "bottom_triangles": int(sum(1 for f in mesh.faces if all(abs(V[i, 2] - z0) < tol for i in f))),
            "thickness": z1 - z0, "mesh_volume": float(mesh.volume), "pieces_volume": vol,
            "volume_rel_error": abs(vol - mesh.volume) / mesh.volume, "area_rel_error_vs_triangles": abs(area - tri_area) / tri_area}
    return pieces, info


def poly_area(Q):
    x, y = Q[:, 0], Q[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def decompose_coacd(mesh, threshold=0.02):
    """Fallback for a part that is not an extrusion: CoACD (pip install coacd)."""
    import coacd
    parts = coacd.run_coacd(coacd.Mesh(mesh.vertices, mesh.faces), threshold=threshold, seed=0)
    pieces = [np.asarray(v) for v, _ in parts]
    vol = sum(trimesh.Trimesh(v).convex_hull.volume for v in pieces)
    return pieces, {"method": f"coacd threshold {threshold}", "pieces": len(pieces), "mesh_volume": float(mesh.volume),
                    "pieces_volume": vol, "volume_rel_error": abs(vol - mesh.volume) / mesh.volume}


# ----------------------------------------------------------------------------------------------------
# Plans
def resolve_mesh(plan_path, mesh_rel, mesh_root):
    for base in ([Path(mesh_root)] if mesh_root else []) + [Path.cwd(), REPO_ROOT, Path(plan_path).resolve().parent]:
        p = base / mesh_rel
        if p.is_file():
            return p
    sys.exit(f"{plan_path}: mesh {mesh_rel} not found (use --mesh-root)")


def grip_force_analysis(pregrasp, plan_path, cwd):
    """`pregrasp physics <plan> --json`: one report per plan (n_max = the worst state's N_min)."""
    out = subprocess.run([str(pregrasp), "physics", str(Path(plan_path).resolve()), "--json"], capture_output=True,
                         text=True, cwd=str(cwd))
    if out.returncode not in (0, 2):
        sys.exit(f"pregrasp physics {plan_path} failed ({out.returncode}): {out.stderr}")
    return json.loads(out.stdout)


def rot_trajectory(plan):
    seg = [s for s in plan["segments"] if s["name"] == "rot"][0]
    ts = np.array([p["t"] for p in seg["points"]])
    poses = [pose_T(p["object_pose"]) for p in seg["points"]]
    return seg, ts, poses


def object_pose_at(ts, poses, t):
    """Object pose at plan time t: translation linear, rotation SLERP between the rot points."""
    if t <= ts[0]:
        return poses[0]
    if t >= ts[-1]:
        return poses[-1]
    i = int(np.searchsorted(ts, t, side="right")) - 1
    u = (t - ts[i]) / (ts[i + 1] - ts[i])
    T = np.eye(4)
    T[:3, 3] = (1 - u) * poses[i][:3, 3] + u * poses[i + 1][:3, 3]
    T[:3, :3] = mat(slerp(quat(poses[i][:3, :3]), quat(poses[i + 1][:3, :3]), u))
    return T


# ----------------------------------------------------------------------------------------------------
# Scene
class Replay:
    """One plan's scene: table, part (free body), 2F-85 on a free base welded to a mocap flange."""

    def __init__(self, gripper_xml, doc, plan, pieces, mass_props, mu_pad, mu_support, condim, torsion, dt, weld_solref,
                 noslip=0, impratio=None):
        self.doc, self.plan = doc, plan
        sp = mujoco.MjSpec.from_file(str(gripper_xml))
        sp.option.timestep = dt
        sp.option.noslip_iterations = noslip
        if impratio:
            sp.option.impratio = impratio
        sp.option.gravity = [0.0, 0.0, -9.81]
        # the gripper: a free base welded to a mocap body at the flange pose; weightless (the arm carries it)
        for b in GRIPPER_BODIES:
            sp.body(b).gravcomp = 1.0
        sp.body("base_mount").add_freejoint(name="gripper_free")
        tgt = sp.worldbody.add_body(name="flange_target", mocap=True)
        eq = sp.add_equality(name="flange_weld", type=mujoco.mjtEq.mjEQ_WELD, objtype=mujoco.mjtObj.mjOBJ_BODY,
                             name1="flange_target", name2="base_mount")
        eq.solref = list(weld_solref)
        eq.solimp = [0.99, 0.999, 0.001, 0.5, 2]
        del tgt
        # friction: pads mu_pad (priority 1 wins over the part), the rest of the gripper mu_pad too
        for g in sp.geoms:
            if g.name in PAD_GEOMS["pos"] + PAD_GEOMS["neg"]:
                g.friction = [mu_pad, torsion, 0.0001]
                g.condim = condim
            elif g.contype or g.conaffinity:
                g.friction = [mu_pad, 0.005, 0.0001]
        # force-controlled actuator on the same tendon: ctrl = tendon force (N on the `split` tendon, whose
        # length is the mean of the two driver angles, so each driver joint gets ctrl/2 N m)
        act = sp.actuator("fingers_actuator")
        act.gaintype = mujoco.mjtGain.mjGAIN_FIXED
        act.gainprm = [1.0] + [0.0] * 9
        act.biastype = mujoco.mjtBias.mjBIAS_NONE
        act.biasprm = [0.0] * 10
        act.ctrlrange = [-1000.0, 1000.0]
        act.forcerange = [-1000.0, 1000.0]
        # table: a plane at the support height (priority 2: its friction decides part-table contacts)
        sp.worldbody.add_geom(name="table", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[3, 3, 0.1],
                              pos=[0, 0, doc.get("support_height", 0.0)], friction=[mu_support, 0.005, 0.0001],
                              priority=2, condim=3, rgba=[0.8, 0.8, 0.7, 1])
        # the part
        T0 = pose_T(rot_trajectory(plan)[0]["points"][0]["object_pose"])
        part = sp.worldbody.add_body(name="part", pos=list(T0[:3, 3]), quat=list(quat(T0[:3, :3])))
        part.add_freejoint(name="part_free")
        part.explicitinertial = True
        part.mass = mass_props["mass"]
        part.ipos = list(mass_props["com"])
        part.fullinertia = list(mass_props["fullinertia"])
        for i, P in enumerate(pieces):
            hull = trimesh.Trimesh(P).convex_hull
            sp.add_mesh(name=f"piece{i}", uservert=list(np.asarray(hull.vertices).ravel()),
                        userface=list(np.asarray(hull.faces).ravel()))
            part.add_geom(name=f"part{i}", type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"piece{i}",
                          friction=[mu_support, 0.005, 0.0001], condim=3, mass=0, rgba=[0.75, 0.55, 0.3, 1])
        self.spec = sp
        self.m = sp.compile()
        m = self.m
        nid = lambda t, n: mujoco.mj_name2id(m, t, n)
        self.part_body = nid(mujoco.mjtObj.mjOBJ_BODY, "part")
        self.part_geoms = np.array([g for g in range(m.ngeom) if m.geom_bodyid[g] == self.part_body])
        self.pad = {s: np.array([nid(mujoco.mjtObj.mjOBJ_GEOM, n) for n in ns]) for s, ns in PAD_GEOMS.items()}
        self.table = nid(mujoco.mjtObj.mjOBJ_GEOM, "table")
        gb = {nid(mujoco.mjtObj.mjOBJ_BODY, b) for b in GRIPPER_BODIES}
        self.gripper_geoms = np.array([g for g in range(m.ngeom) if m.geom_bodyid[g] in gb and
                                       (m.geom_contype[g] or m.geom_conaffinity[g])])
        self.bm = nid(mujoco.mjtObj.mjOBJ_BODY, "base_mount")
        self.bm_off = m.body_pos[self.bm].copy()  # base_mount in G (0, 0, 0.007)
        self.jfree_g = m.jnt_qposadr[nid(mujoco.mjtObj.mjOBJ_JOINT, "gripper_free")]
        self.jfree_p = m.jnt_qposadr[nid(mujoco.mjtObj.mjOBJ_JOINT, "part_free")]
        self.jq = {j: [m.jnt_qposadr[nid(mujoco.mjtObj.mjOBJ_JOINT, f"{s}_{j}_joint")] for s in ("right", "left")]
                   for j in ("driver", "spring_link", "follower", "coupler")}
        # trajectory: flange = object_pose . G_s . precision_point^-1
        seg, self.ts, self.poses = rot_trajectory(plan)
        rob = [r for r in doc["robots"] if r["name"] == plan["supportive"]][0]
        self.T_obj_flange = pose_T(doc["grasps"]["support"]) @ inv(pose_T(rob["precision_point"]))
        self.seg = seg

    def flange_at(self, t_plan):
        return object_pose_at(self.ts, self.poses, t_plan) @ self.T_obj_flange

    def set_flange(self, d, T):
        d.mocap_pos[0] = T[:3, 3]
        d.mocap_quat[0] = quat(T[:3, :3])

    def pad_forces(self, d):
        """Per side (pos, neg): summed contact normal force between that side's pad boxes and the part, and whether
        it touches; plus the summed normal force of any other gripper geom on the part."""
        n = d.ncon
        out = {"pos": 0.0, "neg": 0.0, "other": 0.0}
        if n == 0:
            return out
        G = d.contact.geom[:n]
        f6 = np.zeros(6)
        for i in range(n):
            a, b = G[i]
            if b in self.part_geoms:
                a, b = b, a
            if a not in self.part_geoms:
                continue
            side = "pos" if b in self.pad["pos"] else "neg" if b in self.pad["neg"] else ("other" if b in self.gripper_geoms else None)
            if side:
                mujoco.mj_contactForce(self.m, d, i, f6)
                out[side] += f6[0]
        return out

    def touching(self, d):
        n = d.ncon
        if n == 0:
            return False, False
        G = d.contact.geom[:n]
        ip = np.isin(G, self.part_geoms)
        res = []
        for s in ("pos", "neg"):
            ig = np.isin(G, self.pad[s])
            res.append(bool(np.any((ip[:, 0] & ig[:, 1]) | (ip[:, 1] & ig[:, 0]))))
        return res[0], res[1]

    def fingers(self, d):
        """Finger joint angles [+x (right), -x (left)] (rad, Menagerie joints)."""
        return {j: [float(d.qpos[a]) for a in adr] for j, adr in self.jq.items()}

    def grip_offset(self, d):
        """The part in the gripper: distance (m) and angle (rad) of the part's G_s from where the plan puts it (the
        precision point), and the part's rotation and G_s point in the actual flange frame."""
        Tf = T_of(d.xpos[self.bm], d.xquat[self.bm]) @ inv(T_of(self.bm_off, [1, 0, 0, 0]))
        rel = inv(Tf) @ self.part_T(d)  # part in the flange frame
        rel_plan = inv(self.T_obj_flange)
        gs = pose_T(self.doc["grasps"]["support"])[:3, 3]
        p, p_plan = (rel @ np.r_[gs, 1])[:3], (rel_plan @ np.r_[gs, 1])[:3]
        return (float(np.linalg.norm(p - p_plan)), math.degrees(rot_angle(rel[:3, :3], rel_plan[:3, :3])),
                rel[:3, :3], p)

    def part_T(self, d):
        return T_of(d.xpos[self.part_body], d.xquat[self.part_body])

    def run(self, F, slow, calib, log=None):
        """Closes on the part with squeeze force F (N), follows rot `slow` times slower, holds T_HOLD.
        calib = (slope a, offset b) of measured pad force ~ a * tau + b, used to set and correct tau."""
        m = self.m
        d = mujoco.MjData(m)
        dt = m.opt.timestep
        T0 = self.flange_at(self.ts[0])
        Tbm = T0 @ T_of(self.bm_off, [1, 0, 0, 0])
        d.qpos[self.jfree_g:self.jfree_g + 3] = Tbm[:3, 3]
        d.qpos[self.jfree_g + 3:self.jfree_g + 7] = quat(Tbm[:3, :3])
        self.set_flange(d, T0)
        # the part: at the first rot pose, lowered by the plan's lift so that it rests on the table
        lift = self.doc.get("planner", {}).get("lift", 0.0) or 0.0
        d.qpos[self.jfree_p + 2] -= lift
        mujoco.mj_forward(m, d)
        a, b = calib
        steps = lambda T: int(round(T / dt))
        rec = {"F_cmd": F}

        def avg_force(nsteps, tau):
            acc = {"pos": 0.0, "neg": 0.0, "other": 0.0}
            k = 0
            for i in range(nsteps):
                d.ctrl[0] = tau
                mujoco.mj_step(m, d)
                if i >= nsteps - steps(T_MEASURE) and i % SAMPLE_EVERY == 0:
                    f = self.pad_forces(d)
                    for s in acc:
                        acc[s] += f[s]
                    k += 1
            return {s: v / max(k, 1) for s, v in acc.items()}

        # 1. open, the part settles; 2. spring-close; 3. ramp to tau; 4. correct tau on the measured force
        for _ in range(steps(T_SETTLE_OPEN)):
            d.ctrl[0] = TAU_OPEN
            mujoco.mj_step(m, d)
        f = avg_force(steps(T_SPRING_CLOSE), 0.0)
        tau = (F - b) / a
        n = steps(T_RAMP)
        for i in range(n):
            d.ctrl[0] = tau * (i + 1) / n
            mujoco.mj_step(m, d)
        hist = []
        for _ in range(N_CORRECT):
            f = avg_force(steps(T_CORRECT), tau)
            meas = 0.5 * (f["pos"] + f["neg"])
            hist.append((tau, meas))
            if abs(meas - F) <= max(0.01 * F, 0.05):
                break
            tau += (F - meas) / a
        rec["tau"] = tau
        rec["squeeze_iterations"] = len(hist)
        f = avg_force(steps(T_CORRECT), tau)
        rec["N_meas_pre"] = 0.5 * (f["pos"] + f["neg"])
        rec["N_meas_pre_sides"] = [f["pos"], f["neg"]]
        rec["other_gripper_force_pre"] = f["other"]
        rec["fingers_pre"] = self.fingers(d)
        grip_pre = self.grip_offset(d)
        rec["grip_offset_pre"], rec["grip_offset_pre_deg"] = grip_pre[0], grip_pre[1]
        # 5. the rotation, then hold
        T_rot = (self.ts[-1] - self.ts[0]) * slow
        n_rot, n_hold = steps(T_rot), steps(T_HOLD)
        gap = {"pos": 0.0, "neg": 0.0}
        gap_max = {"pos": 0.0, "neg": 0.0}
        lost_t = None
        Ns = []
        weld_err = 0.0
        for i in range(n_rot + n_hold):
            tp = self.ts[0] + min(i + 1, n_rot) * dt / slow
            Tf = self.flange_at(tp)
            self.set_flange(d, Tf)
            d.ctrl[0] = tau
            mujoco.mj_step(m, d)
            tp_s, tn_s = self.touching(d)
            for s, t_ in (("pos", tp_s), ("neg", tn_s)):
                gap[s] = 0.0 if t_ else gap[s] + dt
                gap_max[s] = max(gap_max[s], gap[s])
                if gap[s] > GAP_TOL and lost_t is None:
                    lost_t = (i + 1) * dt
            if i % SAMPLE_EVERY == 0:
                f = self.pad_forces(d)
                Ns.append((f["pos"], f["neg"], f["other"]))
                Tb = T_of(d.xpos[self.bm], d.xquat[self.bm]) @ inv(T_of(self.bm_off, [1, 0, 0, 0]))
                weld_err = max(weld_err, np.linalg.norm(Tb[:3, 3] - Tf[:3, 3]))
        Ns = np.array(Ns)
        Tp = self.part_T(d)
        Tplan = self.poses[-1]
        com_local = self.m.body_ipos[self.part_body]
        gs_h = np.r_[pose_T(self.doc["grasps"]["support"])[:3, 3], 1.0]  # G_s (the grasped point), object frame
        rec.update({
            "origin_err": float(np.linalg.norm(Tp[:3, 3] - Tplan[:3, 3])),
            "ang_err_deg": math.degrees(rot_angle(Tp[:3, :3], Tplan[:3, :3])),
            "com_err": float(np.linalg.norm(Tp[:3, :3] @ com_local + Tp[:3, 3] - Tplan[:3, :3] @ com_local - Tplan[:3, 3])),
            "pos_err": float(np.linalg.norm((Tp @ gs_h)[:3] - (Tplan @ gs_h)[:3])),
            "pad_gap_max": [gap_max["pos"], gap_max["neg"]],
            "contact_lost_t": lost_t,
            "N_meas_rot_min": float(Ns[:, :2].mean(axis=1).min()) if len(Ns) else 0.0,
            "N_meas_rot_mean": float(Ns[:, :2].mean()) if len(Ns) else 0.0,
            "N_meas_rot_max": float(Ns[:, :2].mean(axis=1).max()) if len(Ns) else 0.0,
            "other_gripper_force_rot_max": float(Ns[:, 2].max()) if len(Ns) else 0.0,
            "flange_tracking_err_max": weld_err,
            "t_rot": T_rot,
        })
        # where it slipped: the part in the gripper (at G_s), relative to where it sat before the rotation, and the
        # rotation axis on the table
        g = self.grip_offset(d)
        rec["grip_slip"] = float(np.linalg.norm(g[3] - grip_pre[3]))
        rvec = np.zeros(3)
        mujoco.mju_quat2Vel(rvec, quat(g[2] @ grip_pre[2].T), 1.0)
        rec["grip_slip_deg"] = math.degrees(float(np.linalg.norm(rvec)))
        rec["grip_slip_rotvec_G_deg"] = [math.degrees(v) for v in rvec]
        rec["fingers_end"] = self.fingers(d)
        T_init = self.poses[0]
        cand = [c for c in self.doc["candidates"] if c["id"] == self.plan["candidate"]][0]
        ax = [inv(T_init) @ np.r_[p, 1] for p in cand["axis"]]
        rec["axis_slide"] = float(max(np.linalg.norm(((Tp @ e)[:3] - (Tplan @ e)[:3])[:2]) for e in ax))
        rec["axis_height_final"] = [float((Tp @ e)[2]) for e in ax]
        holds_pose = rec["pos_err"] <= POS_TOL and rec["ang_err_deg"] <= ANG_TOL_DEG
        if lost_t is None and holds_pose:
            rec["verdict"] = "holds"
        elif lost_t is not None:
            rec["verdict"] = "drops"
        else:
            rec["verdict"] = "slips"
        if log:
            log(f"    F {F:8.3f} N (tau {tau:7.3f}): measured {rec['N_meas_pre']:8.3f} before, rot min/mean "
                f"{rec['N_meas_rot_min']:8.3f}/{rec['N_meas_rot_mean']:8.3f}; err {rec['pos_err']*1e3:6.1f} mm "
                f"{rec['ang_err_deg']:5.1f} deg, grip slip {rec['grip_slip']*1e3:5.1f} mm {rec['grip_slip_deg']:4.1f} deg, "
                f"(rotvec G {np.round(rec['grip_slip_rotvec_G_deg'], 1).tolist()}), axis slide {rec['axis_slide']*1e3:5.1f} mm, "
                f"followers {np.round(rec['fingers_pre']['follower'], 3).tolist()} -> "
                f"{np.round(rec['fingers_end']['follower'], 3).tolist()}, lost {lost_t} -> {rec['verdict']}")
        return rec

    def calibrate(self, slow):
        """(a, b) of the measured pad force ~ a * tau + b at the grasp, from tau = 1 and 3 (no rotation)."""
        pts = []
        for tau in (1.0, 3.0):
            m = self.m
            d = mujoco.MjData(m)
            T0 = self.flange_at(self.ts[0])
            Tbm = T0 @ T_of(self.bm_off, [1, 0, 0, 0])
            d.qpos[self.jfree_g:self.jfree_g + 3] = Tbm[:3, 3]
            d.qpos[self.jfree_g + 3:self.jfree_g + 7] = quat(Tbm[:3, :3])
            self.set_flange(d, T0)
            d.qpos[self.jfree_p + 2] -= self.doc.get("planner", {}).get("lift", 0.0) or 0.0
            mujoco.mj_forward(m, d)
            dt = m.opt.timestep
            nt = int(round((T_SETTLE_OPEN + T_SPRING_CLOSE + T_RAMP + T_CORRECT) / dt))
            acc, k = 0.0, 0
            for i in range(nt):
                t = (i + 1) * dt
                d.ctrl[0] = TAU_OPEN if t < T_SETTLE_OPEN else 0.0 if t < T_SETTLE_OPEN + T_SPRING_CLOSE else tau
                mujoco.mj_step(m, d)
                if i >= nt - int(T_MEASURE / dt) and i % SAMPLE_EVERY == 0:
                    f = self.pad_forces(d)
                    acc += 0.5 * (f["pos"] + f["neg"])
                    k += 1
            pts.append((tau, acc / k))
        a = (pts[1][1] - pts[0][1]) / (pts[1][0] - pts[0][0])
        return a, pts[0][1] - a * pts[0][0], pts


# ----------------------------------------------------------------------------------------------------
def mass_properties(mesh, mass, scale):
    """Uniform-density mass properties of the (scaled) closed mesh in the object frame."""
    m = mesh.copy()
    m.apply_scale(scale)
    vol = m.volume
    m.density = mass / vol
    I = m.moment_inertia  # about the centre of mass, axes of the object frame
    return {"mass": mass, "com": m.center_mass.tolist(), "volume": vol,
            "fullinertia": [I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]]}


def evaluate_plan(rp, n_min, slow, log):
    """The four multipliers, then the bisection of F* in [0, BISECT_HI * n_min]."""
    a, b, pts = rp.calibrate(slow)
    log(f"  calibration: measured pad force = {a:.3f} * tau + {b:.3f} N (tau 1 -> {pts[0][1]:.3f}, 3 -> {pts[1][1]:.3f})")
    calib = (a, b)
    runs = {}

    def trial(k):
        key = round(k, 6)
        if key not in runs:
            runs[key] = rp.run(k * n_min, slow, calib, log)
            runs[key]["multiplier"] = key
        return runs[key]["verdict"] == "holds"

    res = {str(k): None for k in MULTIPLIERS}
    for k in MULTIPLIERS:
        trial(k)
    held = sorted(k for k in runs if runs[k]["verdict"] == "holds")
    failed = sorted(k for k in runs if runs[k]["verdict"] != "holds")
    if not held:
        if trial(BISECT_HI):
            held = [BISECT_HI]
    lo = max([k for k in failed if not held or k < min(held)], default=0.0)
    hi = min(held) if held else None
    monotone = all(not (f > h) for f in failed for h in held)
    if hi is not None:
        while hi - lo > BISECT_REL * hi:
            mid = 0.5 * (lo + hi)
            if trial(mid):
                hi = mid
            else:
                lo = mid
    for k in MULTIPLIERS:
        res[str(k)] = runs[round(k, 6)]
    return {"calibration": {"slope": a, "offset": b, "points": pts},
            "F_star": None if hi is None else hi * n_min, "F_star_multiplier": hi, "F_star_lower": lo * n_min,
            "bisection_bracket": [lo, hi], "monotone_at_multipliers": monotone,
            "at": res, "trials": [runs[k] for k in sorted(runs)]}


def run_task(task):
    """One (plan, condim): the multipliers and the bisection; returns the output row."""
    gripper_xml, doc, k, pieces, mp, rep, example, condim, a, weld_solref = task
    a = argparse.Namespace(**a)
    plan = doc["plans"][k]
    n_min = rep["n_max"]
    ph = plan.get("physics") or {}
    mu_pad = ph.get("mu_pad", rep["settings"]["mu_pad"])
    mu_sup = ph.get("mu_support", rep["settings"]["mu_support"])
    mass = rep["part"]["mass"]
    tag = f"[{example} plan {k} condim {condim}]"
    log = lambda s_: print(f"{tag} {s_.strip()}", flush=True)
    torsion = mu_pad * a.torsion_radius if condim >= 4 else 0.0
    t0 = time.time()
    rp = Replay(gripper_xml, doc, plan, pieces, mp, mu_pad, mu_sup, condim, torsion, a.dt, weld_solref, a.noslip, a.impratio)
    log(f"  plan {k} (candidate {plan['candidate']}, supportive {plan['supportive']}), condim {condim}: "
        f"mass {mass} kg, N_min {n_min:.3f} N (worst state {rep['worst']}), mu_pad {mu_pad}, "
        f"mu_support {mu_sup}")
    if a.multipliers_only:
        a_, b_, pts = rp.calibrate(a.slow)
        ev = {"at": {str(m_): rp.run(m_ * n_min, a.slow, (a_, b_), log) for m_ in MULTIPLIERS},
              "calibration": {"slope": a_, "offset": b_, "points": pts}, "F_star": None}
    else:
        ev = evaluate_plan(rp, n_min, a.slow, log)
    wall = time.time() - t0
    rot = [s for s in plan["segments"] if s["name"] == "rot"][0]
    row = {"example": example, "plan": k, "candidate": plan["candidate"], "supportive": plan["supportive"],
           "condim": condim, "torsion": torsion, "mass": mass, "mu_pad": mu_pad, "mu_support": mu_sup,
           "N_min": n_min, "N_min_worst_state": rep["worst"],
           "N_min_worst_theta_deg": rep["states"][rep["worst"]]["theta_deg"],
           "grip_width": rot.get("grip_width"), "fingers_plan": rot.get("fingers"),
           "rot_duration_plan": rot["points"][-1]["t"], "F_star": ev["F_star"],
           "F_star_over_N_min": None if ev["F_star"] is None else ev["F_star"] / n_min,
           "calibration": ev["calibration"]}
    if "bisection_bracket" in ev:
        row.update({"F_star_lower": ev["F_star_lower"], "bisection_bracket": ev["bisection_bracket"],
                    "monotone_at_multipliers": ev["monotone_at_multipliers"],
                    "trials": [{kk: t[kk] for kk in ("multiplier", "F_cmd", "N_meas_pre", "verdict",
                                                      "pos_err", "ang_err_deg")} for t in ev["trials"]]})
    row["verdict"] = {k_: v["verdict"] for k_, v in ev["at"].items()}
    row["at"] = {k_: {kk: vv for kk, vv in v.items()} for k_, v in ev["at"].items()}
    log(f"  -> F* {row['F_star']} N ({row['F_star_over_N_min']} x N_min), verdicts {row['verdict']}, "
        f"{wall:.1f} s wall")
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("plans", nargs="+", help="plan files written by `pregrasp plan`")
    ap.add_argument("--menagerie", required=True, help="mujoco_menagerie checkout or (bare) git directory")
    ap.add_argument("--rev", default="HEAD", help="revision to read from a git directory (default HEAD)")
    ap.add_argument("--pregrasp", default=str(DEFAULT_PREGRASP), help="pregrasp binary (for `physics --json`)")
    ap.add_argument("--mesh-root", default=None, help="directory the plans' object.mesh paths are relative to "
                                                      "(default: try cwd, the repository root, the plan's folder)")
    ap.add_argument("--plan-index", type=int, nargs="*", default=None, help="only these plan indices of each file")
    ap.add_argument("--slow", type=float, default=5.0, help="time scaling of rot (default 5: 5x slower than planned)")
    ap.add_argument("--dt", type=float, default=0.001, help="MuJoCo timestep (s)")
    ap.add_argument("--condim", type=int, nargs="+", default=[3, 4], help="pad contact condims to run (3, 4 or 6)")
    ap.add_argument("--torsion-radius", type=float, default=0.0116,
                    help="with condim >= 4: the pads' torsional friction = mu_pad * this radius (m)")
    ap.add_argument("--noslip", type=int, default=10,
                    help="MuJoCo noslip_iterations (default 10; 0 = off: soft friction creeps, see README)")
    ap.add_argument("--impratio", type=float, default=None, help="override Menagerie's impratio (10)")
    ap.add_argument("--multipliers-only", action="store_true", help="no bisection")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes (one (plan, condim) each)")
    ap.add_argument("--out", default=str(OUT_DIR), help="output directory")
    ap.add_argument("--name", default="replay_2f85", help="output file stem")
    a = ap.parse_args()
    t_start = time.time()
    log = lambda s: print(s, flush=True)
    tasks = []
    weld_solref = (0.002, 1.0)
    with tempfile.TemporaryDirectory(prefix="replay_") as tmp:
        src, prov = load_source(a.menagerie, a.rev, tmp)
        decomp_infos = {}
        for plan_path in a.plans:
            doc = json.load(open(plan_path))
            if doc.get("status") != "planned":
                log(f"{plan_path}: status {doc.get('status')}, skipped")
                continue
            example = Path(doc["scene"]["file"]).stem
            mesh_path = resolve_mesh(plan_path, doc["object"]["mesh"], a.mesh_root)
            mesh = trimesh.load(str(mesh_path), force="mesh")
            scale = doc["object"].get("scale", 1.0)
            mesh_s = mesh.copy()
            mesh_s.apply_scale(scale)
            try:
                pieces, dinfo = decompose_extrusion(mesh_s)
            except ValueError:
                pieces, dinfo = decompose_coacd(mesh_s)
            decomp_infos[example] = dinfo
            log(f"{plan_path}: {example}, mesh {doc['object']['mesh']}, {dinfo['pieces']} convex pieces, "
                f"volume error {dinfo['volume_rel_error']:.2e}")
            reports = grip_force_analysis(a.pregrasp, plan_path, a.mesh_root or REPO_ROOT)
            idx = a.plan_index if a.plan_index is not None else range(len(doc["plans"]))
            for k in idx:
                rep = [r for r in reports if r["plan"] == k][0]
                for condim in a.condim:
                    tasks.append((str(src / MODEL_XML), doc, k, pieces, mass_properties(mesh, rep["part"]["mass"], scale),
                                  rep, example, condim, vars(a), weld_solref))
        if a.jobs > 1:
            import multiprocessing as mp_
            with mp_.get_context("fork").Pool(a.jobs) as pool:
                rows = pool.map(run_task, tasks, chunksize=1)
        else:
            rows = [run_task(t) for t in tasks]
    rows.sort(key=lambda r: (r["example"], r["plan"], r["condim"]))
    header = {
        "generator": SCRIPT,
        # Absolute paths are this machine's: recorded by their last component only.
        "args": [os.path.basename(a) if os.path.isabs(a) else a for a in sys.argv[1:]],
        "date": datetime.date.today().isoformat(),
        "source": {"repo": "https://github.com/google-deepmind/mujoco_menagerie", "path": f"{MODEL_DIR}/{MODEL_XML}", **prov},
        "mujoco_version": mujoco.__version__, "numpy_version": np.__version__, "trimesh_version": trimesh.__version__,
        "decomposition": decomp_infos,
        "units": "metres, kilograms, newtons, seconds; angles *_deg in degrees",
        "model": {
            "timestep": a.dt, "noslip_iterations": a.noslip, "integrator": "Euler (Menagerie)", "cone": "elliptic", "impratio": a.impratio or 10.0,
            "gravity": [0.0, 0.0, -9.81],
            "table": "plane at support_height, friction mu_support (priority 2), condim 3",
            "part": ("free body at the first rot object_pose lowered by planner.lift (resting on the table); mass = "
                     "pregrasp's mass, uniform density, inertia from the closed STL; collision = the convex pieces"),
            "pads": ("Menagerie's two pad boxes per finger, friction mu_pad (priority 1, so it decides pad-part "
                     "contacts); condim per row (3: no torsional friction at a contact point; 4: torsional coefficient "
                     "mu_pad * torsion_radius); the rest of the gripper friction mu_pad"),
            "gripper": ("Menagerie 2f85.xml; base_mount on a free joint welded (solref %s) to a mocap body at the flange "
                        "pose (G = Menagerie world frame); every gripper body gravity-compensated (the arm carries it); "
                        "fingers_actuator turned into a force actuator on its `split` tendon (gain 1, no bias, range "
                        "+-1000): ctrl = tendon force tau") % (list(weld_solref),),
            "flange_pose": "object_pose(t) . G_s . precision_point^-1 (translation linear, rotation SLERP in time)",
            "squeeze": ("open (tau %.1f) %.1f s; tau 0 (the spring links close the fingers) %.1f s; tau ramps to "
                        "(F - b)/a over %.1f s (a, b: calibration tau = 1, 3 at the grasp); then up to %d windows of %.1f s "
                        "each measuring the pad-part normal force (mean of both pads over the last %.1f s) and correcting "
                        "tau by (F - measured)/a until within 1 %%; tau then held constant through the rotation") %
                       (TAU_OPEN, T_SETTLE_OPEN, T_SPRING_CLOSE, T_RAMP, N_CORRECT, T_CORRECT, T_MEASURE),
            "time_scaling": a.slow, "hold": T_HOLD,
            "verdict": ("holds: final part pose within %.0f mm (pos_err: at the grasped point G_s; the errors at the centre of mass and the object-frame origin are reported as com_err, origin_err) and %.0f deg of the planned final "
                        "object_pose and neither pad's boxes out of contact with the part for more than %.0f ms; drops: a "
                        "pad lost contact; slips: contact kept but the pose is off") % (POS_TOL * 1e3, ANG_TOL_DEG, GAP_TOL * 1e3),
            "bisection": "F* = smallest holding force found, bisected in [0, %.0f N_min] until (hi - lo) <= %.0f %% of hi" %
                         (BISECT_HI, BISECT_REL * 100),
            "torsion_radius": a.torsion_radius,
        },
    }
    out = Path(a.out)
    text = "{\n" + "".join(f"{json.dumps(k)}: {json.dumps(rnd(v), sort_keys=True)},\n" for k, v in sorted(header.items()))
    text += '"rows": [\n' + ",\n".join(json.dumps(rnd(r), sort_keys=True) for r in rows) + "\n]}\n"
    json.loads(text)
    write_atomic(out / f"{a.name}.json", text)
    flat = [{kk: vv for kk, vv in r.items() if kk not in ("trials", "at", "calibration")} |
            {f"verdict_{m_}": r["at"][str(m_)]["verdict"] for m_ in MULTIPLIERS} |
            {f"pos_err_{m_}": r["at"][str(m_)]["pos_err"] for m_ in MULTIPLIERS} |
            {f"ang_err_deg_{m_}": r["at"][str(m_)]["ang_err_deg"] for m_ in MULTIPLIERS} |
            {f"N_meas_{m_}": r["at"][str(m_)]["N_meas_pre"] for m_ in MULTIPLIERS} for r in rows]
    for f in flat:
        f.pop("verdict", None)
    write_atomic(out / f"{a.name}.csv", csv_text(flat))
    log(f"wrote {out / (a.name + '.json')} and .csv: {len(rows)} rows in {time.time() - t_start:.1f} s")


if __name__ == "__main__":
    main()
