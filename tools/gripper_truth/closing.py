#!/usr/bin/env python3
"""Ground truth of how the Robotiq 2F-85 closes on a bar, simulated with the MuJoCo Menagerie model.

    pip install mujoco numpy
    python3 tools/gripper_truth/closing.py <menagerie>

<menagerie> is a checkout of google-deepmind/mujoco_menagerie (a directory holding robotiq_2f85/2f85.xml)
or a (bare) git directory of it; from a git directory the files of robotiq_2f85/ at --rev (default HEAD)
are read with `git cat-file` into a temporary directory that is deleted afterwards. No mesh is copied
into this repository.

Writes crates/robot/data/gripper_truth/closing_2f85.{json,csv} (atomically, deterministic for the same
inputs, MuJoCo version and machine). See tools/gripper_truth/README.md for the frame, the grid and
every column.
"""
import argparse
import csv
import hashlib
import io
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

REPO_ROOT = Path(__file__).resolve().parents[2]
OUT_DIR = REPO_ROOT / "crates/robot/data/gripper_truth"
OUR_TABLE = REPO_ROOT / "crates/robot/data/robotiq_2f85.json"
SCRIPT = "tools/gripper_truth/closing.py"
MODEL_DIR = "robotiq_2f85"
MODEL_XML = "2f85.xml"

# ----------------------------------------------------------------------------------------------------
# Scene grid (G frame, metres / degrees)
POWER_Z = 0.115  # power point: G z of the palm-side grasp reference
BAR_LEN = 0.3  # along y, centred on the fingers
WIDTHS_MM = [15, 25, 35, 45, 55, 65, 75]  # along x (closing axis)
THICKS_MM = [15, 25, 35, 45]  # along z (approach)
DEPTHS_MM = [0, 5, 10, 15, 20, 25]  # bar top past the power point
TILTS_DEG = [0, 10, 20, 30]  # about the bar's own long axis (G y through the bar centre)
# tilted bars: a sub-grid (every w is not needed, the tilt mostly matters for the extreme widths)
TILTED_WIDTHS_MM = [15, 35, 55, 75]
TILTED_DEPTHS_MM = [0, 10, 25]

# Simulation
CTRL_CLOSED = 255.0
T_RAMP = 1.0  # s, ctrl ramps linearly 0 -> 255 (about 85 mm/s of gap; the real 2F-85 closes at 20-150 mm/s)
T_CAP = T_RAMP + 7.0  # s, simulated time cap (slow creeps and late snap-throughs, see README)
T_MIN = T_RAMP + 0.3  # s, never stop before
SETTLE_WIN = 0.25  # s, window of the settle test
SETTLE_TOL = 5e-5  # m: every tracked point (pad centres, tips) moved less than this over the window
SAMPLE_EVERY = 25  # steps between samples of the tracked points (0.05 s at dt = 0.002)
GRAVITY_G = (0.0, 0.0, 9.81)  # gripper pointing down at the table: gravity along +z of G
OPEN_TOL = 1e-5  # m: penetration tolerated at the open pose before a row is flagged
CURL_RAD = 0.1  # distal pitch above which a distal is called curled
# Free-air sweep
SWEEP_N = 20
SWEEP_T_CAP = 2.0
SWEEP_VTOL = 1e-5  # rad/s

LINKS = ["driver", "coupler", "spring_link", "follower", "pad"]  # Menagerie body names (pad incl. silicone_pad)
PROXIMAL = {"driver", "coupler", "spring_link"}
DISTAL = {"follower", "pad"}
SIDES = {"pos": "right", "neg": "left"}  # our side name (+x / -x finger in G) -> Menagerie prefix
SIGN = {"pos": 1.0, "neg": -1.0}


# ----------------------------------------------------------------------------------------------------
# Source
def git(args, cwd_git_dir, text=True):
    return subprocess.run(["git", "--git-dir", str(cwd_git_dir), *args], capture_output=True, check=True,
                          text=text).stdout


def sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def load_source(path, rev, tmp):
    """Returns (directory holding 2f85.xml, provenance dict)."""
    p = Path(path).resolve()
    prov = {"argument_kind": None, "commit": None, "robotiq_2f85_last_change": None, "robotiq_2f85_tree": None}
    if (p / MODEL_DIR / MODEL_XML).is_file():
        prov["argument_kind"] = "checkout"
        src = p / MODEL_DIR
        gd = subprocess.run(["git", "-C", str(p), "rev-parse", "--absolute-git-dir", "--show-toplevel"],
                            capture_output=True, text=True)
        lines = gd.stdout.split("\n")
        # only the checkout's own repository counts, not one that merely encloses the directory
        if gd.returncode == 0 and len(lines) > 1 and Path(lines[1]).resolve() == p:
            gdir = lines[0].strip()
            prov["commit"] = git(["rev-parse", "HEAD"], gdir).strip()
            dirty = subprocess.run(["git", "-C", str(p), "status", "--porcelain", "--", MODEL_DIR],
                                   capture_output=True, text=True).stdout.strip()
            prov["worktree_modified"] = bool(dirty)
            rev = "HEAD"
    else:
        gdir = p
        try:
            git(["rev-parse", "--git-dir"], gdir)
        except subprocess.CalledProcessError:
            sys.exit(f"{p}: neither a checkout holding {MODEL_DIR}/{MODEL_XML} nor a git directory")
        prov["argument_kind"] = "git directory (files read with git cat-file)"
        prov["commit"] = git(["rev-parse", f"{rev}^{{commit}}"], gdir).strip()
        src = Path(tmp) / MODEL_DIR
        listing = git(["ls-tree", "-r", "-z", prov["commit"], MODEL_DIR + "/"], gdir)
        for entry in filter(None, listing.split("\0")):
            meta, fpath = entry.split("\t", 1)
            _, kind, obj = meta.split()
            if kind != "blob" or fpath.endswith(".png"):
                continue
            out = Path(tmp) / fpath
            out.parent.mkdir(parents=True, exist_ok=True)
            out.write_bytes(git(["cat-file", "blob", obj], gdir, text=False))
    if prov["commit"]:
        prov["robotiq_2f85_last_change"] = git(["log", "-1", "--format=%H %cs", prov["commit"], "--", MODEL_DIR],
                                               gdir).strip()
        prov["robotiq_2f85_tree"] = git(["rev-parse", f"{prov['commit']}:{MODEL_DIR}"], gdir).strip()
    if not prov["commit"]:
        print("WARNING: no git commit for the Menagerie files; only their SHA-256 are recorded", file=sys.stderr)
    files = sorted(str(f.relative_to(src)) for f in src.rglob("*") if f.is_file() and f.suffix in (".xml", ".stl", ".obj"))
    prov["sha256"] = {f: sha256(src / f) for f in files if f == MODEL_XML or f.startswith("assets/")}
    return src, prov


# ----------------------------------------------------------------------------------------------------
# Geometry helpers
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


class Gripper:
    """Index of the compiled model: bodies, joints, finger geometry points, G frame."""

    def __init__(self, m):
        self.m = m
        name = lambda kind, n: mujoco.mj_name2id(m, kind, n)
        self.body = {}
        for s, pre in SIDES.items():
            for ln in LINKS:
                self.body[(s, ln)] = name(mujoco.mjtObj.mjOBJ_BODY, f"{pre}_{ln}")
            self.body[(s, "silicone_pad")] = name(mujoco.mjtObj.mjOBJ_BODY, f"{pre}_silicone_pad")
        assert min(self.body.values()) > 0, "Menagerie body names changed"
        self.bm = name(mujoco.mjtObj.mjOBJ_BODY, "base_mount")
        self.base = name(mujoco.mjtObj.mjOBJ_BODY, "base")
        self.jq = {}
        self.jv = {}
        for s, pre in SIDES.items():
            for j in ["driver", "coupler", "spring_link", "follower"]:
                jid = name(mujoco.mjtObj.mjOBJ_JOINT, f"{pre}_{j}_joint")
                assert jid >= 0
                self.jq[(s, j)] = m.jnt_qposadr[jid]
                self.jv[(s, j)] = m.jnt_dofadr[jid]
        # geom roles: link of each finger geom
        self.geom_side = {}
        self.geom_link = {}
        for g in range(m.ngeom):
            b = m.geom_bodyid[g]
            for (s, ln), bid in self.body.items():
                if b == bid:
                    self.geom_side[g] = s
                    self.geom_link[g] = "pad" if ln == "silicone_pad" else ln
        self.palm_geoms = {g for g in range(m.ngeom) if m.geom_bodyid[g] in (self.bm, self.base)}
        self.gripper_geoms = set(self.geom_side) | self.palm_geoms
        # finger geometry points per body (body frame): mesh convex-hull vertices (all vertices where the
        # mesh has no hull), box corners
        self.pts = {}
        for (s, ln), bid in self.body.items():
            P = []
            for g in range(m.ngeom):
                if m.geom_bodyid[g] != bid:
                    continue
                Rg, pg = mat_of_quat(m.geom_quat[g]), m.geom_pos[g]
                if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH:
                    mid = m.geom_dataid[g]
                    V = m.mesh_vert[m.mesh_vertadr[mid]:m.mesh_vertadr[mid] + m.mesh_vertnum[mid]]
                    ga = m.mesh_graphadr[mid]
                    if ga >= 0:
                        nv = m.mesh_graph[ga]
                        V = V[m.mesh_graph[ga + 2 + nv:ga + 2 + 2 * nv]]
                elif m.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX:
                    V = np.array([[a, b, c] for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)]) * m.geom_size[g]
                else:
                    raise ValueError(f"unexpected finger geom type {m.geom_type[g]}")
                P.append(V @ Rg.T + pg)
            self.pts[(s, ln)] = np.vstack(P)
        # pad contact face (pad body frame) from the two pad boxes
        boxes = [g for g in range(m.ngeom) if m.geom_bodyid[g] == self.body[("pos", "pad")]
                 and m.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX]
        assert len(boxes) == 2
        for g in boxes:
            assert np.allclose(m.geom_quat[g], [1, 0, 0, 0])
        lo = np.min([m.geom_pos[g] - m.geom_size[g] for g in boxes], axis=0)
        hi = np.max([m.geom_pos[g] + m.geom_size[g] for g in boxes], axis=0)
        self.pad_lo, self.pad_hi = lo, hi

    def setup_frame(self, d):
        """G frame from the open pose (d after mj_forward at qpos0)."""
        m = self.m
        Rbm, obm = d.xmat[self.bm].reshape(3, 3), d.xpos[self.bm].copy()
        # mounting face: lowest base_mount vertex along the base_mount z axis (all vertices, not hull)
        g_bm = [g for g in range(m.ngeom) if m.geom_bodyid[g] == self.bm and m.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH][0]
        mid = m.geom_dataid[g_bm]
        V = m.mesh_vert[m.mesh_vertadr[mid]:m.mesh_vertadr[mid] + m.mesh_vertnum[mid]]
        Vb = V @ mat_of_quat(m.geom_quat[g_bm]).T + m.geom_pos[g_bm]
        zface = Vb[:, 2].min()
        self.face_vertices = int(np.sum(Vb[:, 2] <= zface + 1e-4))
        # rotation about z putting the +x ("right") pad at +x
        prp = Rbm.T @ (d.xpos[self.body[("pos", "pad")]] - obm)
        phi = round(math.atan2(prp[1], prp[0]) / (math.pi / 2)) * (math.pi / 2)
        self.R_bm_G = rz(phi)
        self.p_bm_G = np.array([0.0, 0.0, zface])
        self.R_w_G = Rbm @ self.R_bm_G
        self.o_w_G = obm + Rbm @ self.p_bm_G
        # contact side of the pad boxes: the +/-y face nearer the gripper axis
        best = None
        for yf in (self.pad_lo[1], self.pad_hi[1]):
            c = self.to_G(d, ("pos", "pad"), [[0.0, yf, 0.5 * (self.pad_lo[2] + self.pad_hi[2])]])[0]
            if best is None or abs(c[0]) < best[0]:
                best = (abs(c[0]), yf)
        yf = best[1]
        zmid = 0.5 * (self.pad_lo[2] + self.pad_hi[2])
        ends = [self.to_G(d, ("pos", "pad"), [[0.0, yf, z]])[0][2] for z in (self.pad_lo[2], self.pad_hi[2])]
        zfar = self.pad_hi[2] if ends[1] > ends[0] else self.pad_lo[2]
        self.pad_face_local = np.array([0.0, yf, zmid])
        self.pad_tip_local = np.array([0.0, yf, zfar])

    def to_G(self, d, key, P):
        b = self.body[key]
        W = np.asarray(P, float) @ d.xmat[b].reshape(3, 3).T + d.xpos[b]
        return (W - self.o_w_G) @ self.R_w_G

    def pad_points(self, d, s):
        P = self.to_G(d, (s, "pad"), [self.pad_face_local, self.pad_tip_local])
        return P[0], P[1]

    def deepest(self, d):
        """(max z in G over all finger geometry points, side, link)."""
        best = (-1e9, None, None)
        zrow = self.R_w_G[:, 2]
        for (s, ln), P in self.pts.items():
            b = self.body[(s, ln)]
            z = (P @ (d.xmat[b].reshape(3, 3).T @ zrow)).max() + (d.xpos[b] - self.o_w_G) @ zrow
            if z > best[0]:
                best = (z, s, "pad" if ln == "silicone_pad" else ln)
        return best

    def deepest_side(self, d, s, links):
        zrow = self.R_w_G[:, 2]
        z = -1e9
        for (ss, ln), P in self.pts.items():
            if ss == s and (ln in links or (ln == "silicone_pad" and "pad" in links)):
                b = self.body[(ss, ln)]
                z = max(z, (P @ (d.xmat[b].reshape(3, 3).T @ zrow)).max() + (d.xpos[b] - self.o_w_G) @ zrow)
        return z

    def pitch(self, d, s):
        """Distal (pad) pitch about G y: 0 = pad axis along +z; > 0 = tip curled towards the other finger."""
        a_tip = self.R_w_G.T @ (d.xmat[self.body[(s, "pad")]].reshape(3, 3) @ (self.pad_tip_local - self.pad_face_local))
        return math.atan2(-SIGN[s] * a_tip[0], a_tip[2])

    def joints(self, d, s):
        return {j: float(d.qpos[self.jq[(s, j)]]) for j in ["driver", "coupler", "spring_link", "follower"]}


# ----------------------------------------------------------------------------------------------------
# Scenes
def bar_geometry(w, t, dep, tilt_deg):
    th = math.radians(tilt_deg)
    half_z = 0.5 * (w * math.sin(th) + t * math.cos(th))
    half_x = 0.5 * (w * math.cos(th) + t * math.sin(th))
    z_top = POWER_Z + dep
    return {"z_top": z_top, "z_center": z_top + half_z, "z_bottom": z_top + 2 * half_z, "half_extent_x": half_x}


def grid():
    rows = []
    for tilt in TILTS_DEG:
        ws = WIDTHS_MM if tilt == 0 else TILTED_WIDTHS_MM
        ds = DEPTHS_MM if tilt == 0 else TILTED_DEPTHS_MM
        for w in ws:
            for t in THICKS_MM:
                for dep in ds:
                    for table in (False, True):
                        rows.append((w, t, dep, tilt, table))
    return rows


def row_id(w, t, dep, tilt, table):
    return f"w{w:02d}_t{t:02d}_d{dep:02d}_a{tilt:02d}_{'table' if table else 'free'}"


class Scene:
    def __init__(self, xml):
        self.spec = mujoco.MjSpec.from_file(str(xml))
        self.spec.option.gravity = [0.0, 0.0, 0.0]
        m0 = self.spec.compile()
        d0 = mujoco.MjData(m0)
        mujoco.mj_forward(m0, d0)
        self.gr0 = Gripper(m0)
        self.gr0.setup_frame(d0)
        self.R_w_G, self.o_w_G = self.gr0.R_w_G, self.gr0.o_w_G
        wb = self.spec.worldbody
        self.bar = wb.add_geom(name="gt_bar", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.01, BAR_LEN / 2, 0.01])
        self.table = wb.add_geom(name="gt_table", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0.3, 0.3, 0.01])
        self.bar.rgba = [0.2, 0.5, 0.9, 1]
        self.table.rgba = [0.8, 0.8, 0.7, 1]

    def compile(self, w=None, t=None, dep=None, tilt=None, table=False, gravity=True):
        g = self.R_w_G @ np.array(GRAVITY_G) if gravity else np.zeros(3)
        self.spec.option.gravity = list(g)
        if w is None:
            for geom in (self.bar, self.table):
                geom.contype, geom.conaffinity = 0, 0
                geom.pos = list(self.o_w_G + self.R_w_G @ np.array([0, 0, 1.0]))
        else:
            bg = bar_geometry(w, t, dep, tilt)
            self.bar.size = [w / 2, BAR_LEN / 2, t / 2]
            self.bar.pos = list(self.o_w_G + self.R_w_G @ np.array([0.0, 0.0, bg["z_center"]]))
            self.bar.quat = list(quat_of_mat(self.R_w_G @ mat_of_quat(quat_axis_angle([0, 1, 0], math.radians(tilt)))))
            self.bar.contype, self.bar.conaffinity = 1, 1
            # plane normal = its local +z; turned to -z of G (facing the gripper)
            self.table.pos = list(self.o_w_G + self.R_w_G @ np.array([0.0, 0.0, bg["z_bottom"]]))
            self.table.quat = list(quat_of_mat(self.R_w_G @ mat_of_quat([0.0, 1.0, 0.0, 0.0])))
            self.table.contype, self.table.conaffinity = (1, 1) if table else (0, 0)
        m = self.spec.compile()
        gr = Gripper(m)
        gr.R_w_G, gr.o_w_G = self.R_w_G, self.o_w_G
        gr.R_bm_G, gr.p_bm_G = self.gr0.R_bm_G, self.gr0.p_bm_G
        gr.pad_face_local, gr.pad_tip_local = self.gr0.pad_face_local, self.gr0.pad_tip_local
        gr.bar = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "gt_bar")
        gr.table = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "gt_table")
        return m, gr


def contacts(d):
    n = d.ncon
    if n == 0:
        return np.zeros((0, 2), int), np.zeros(0)
    return np.array(d.contact.geom[:n]), np.array(d.contact.dist[:n])


def tracked(gr, d):
    P = []
    for s in SIDES:
        P.extend(gr.pad_points(d, s))
    return np.array(P)


def simulate_row(scene, spec_row):
    w_mm, t_mm, dep_mm, tilt, table = spec_row
    w, t, dep = w_mm / 1000, t_mm / 1000, dep_mm / 1000
    bg = bar_geometry(w, t, dep, tilt)
    row = {"id": row_id(*spec_row),
           "bar": {"width": w, "thickness": t, "depth_past_power_point": dep, "tilt_deg": float(tilt),
                   "z_top": bg["z_top"], "z_center": bg["z_center"], "z_bottom": bg["z_bottom"],
                   "half_extent_x": bg["half_extent_x"]},
           "table": table, "table_z": bg["z_bottom"] if table else None}
    m, gr = scene.compile(w, t, dep, tilt, table)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    # open-pose intersection test
    G, D = contacts(d)
    pen_bar, pen_table = 0.0, 0.0
    for (g1, g2), dist in zip(G, D):
        for a, b in ((g1, g2), (g2, g1)):
            if a in gr.gripper_geoms and b == gr.bar:
                pen_bar = max(pen_bar, -dist)
            if a in gr.gripper_geoms and b == gr.table:
                pen_table = max(pen_table, -dist)
    open_deep = gr.deepest(d)[0]
    row["open_penetration_bar"] = pen_bar
    row["open_penetration_table"] = pen_table if table else None
    flags = []
    if pen_bar > OPEN_TOL:
        flags.append("bar")
    if table and pen_table > OPEN_TOL:
        flags.append("table")
    if flags:
        row["status"] = "open_intersects_" + "_and_".join(flags)
        return row
    row["status"] = "simulated"

    dt = m.opt.timestep
    nmax = int(round(T_CAP / dt))
    nmin = int(round(T_MIN / dt))
    nwin = int(round(SETTLE_WIN / dt)) // SAMPLE_EVERY
    first = {s: None for s in SIDES}  # (t, link, dist)
    table_contact = False
    table_first_t = None
    table_links = set()
    snap_tmin = None
    max_deep = (open_deep, None, None, 0.0)
    tip_max = {s: gr.pad_points(d, s)[1][2] for s in SIDES}
    hist = [tracked(gr, d)]
    settled = False
    step = 0
    while step < nmax:
        d.ctrl[0] = CTRL_CLOSED * min(1.0, step * dt / T_RAMP)
        mujoco.mj_step(m, d)
        step += 1
        G, D = contacts(d)
        for (g1, g2), dist in zip(G, D):
            for a, b in ((g1, g2), (g2, g1)):
                if b == gr.bar and a in gr.geom_side:
                    s = gr.geom_side[a]
                    if first[s] is None or (first[s][0] == step * dt and dist < first[s][2]):
                        first[s] = (step * dt, gr.geom_link[a], dist)
                if b == gr.table and a in gr.geom_side:
                    table_contact = True
                    table_links.add(f"{gr.geom_side[a]}.{gr.geom_link[a]}")
                    if table_first_t is None:
                        table_first_t = step * dt
        if step == nmin:
            snap_tmin = tracked(gr, d)
        z, s, ln = gr.deepest(d)
        if z > max_deep[0]:
            max_deep = (z, s, ln, step * dt)
        for s in SIDES:
            tip_max[s] = max(tip_max[s], gr.pad_points(d, s)[1][2])
        if step % SAMPLE_EVERY == 0:
            hist.append(tracked(gr, d))
            if step >= nmin and len(hist) > nwin:
                moved = np.linalg.norm(hist[-1] - hist[-1 - nwin], axis=1).max()
                if moved < SETTLE_TOL:
                    settled = True
                    break
    t_end = step * dt
    k = min(nwin, len(hist) - 1)
    creep = np.linalg.norm(hist[-1] - hist[-1 - k], axis=1).max() / (k * SAMPLE_EVERY * dt)
    creep_since = float(np.linalg.norm(hist[-1] - snap_tmin, axis=1).max()) if snap_tmin is not None else 0.0

    # final state
    G, D = contacts(d)
    touching = {s: set() for s in SIDES}
    palm_bar = False
    fingers_touch = False
    table_end = False
    for (g1, g2), dist in zip(G, D):
        for a, b in ((g1, g2), (g2, g1)):
            if b == gr.bar and a in gr.geom_side:
                touching[gr.geom_side[a]].add(gr.geom_link[a])
            if b == gr.bar and a in gr.palm_geoms:
                palm_bar = True
            if b == gr.table and a in gr.geom_side:
                table_end = True
        if g1 in gr.geom_side and g2 in gr.geom_side and gr.geom_side[g1] != gr.geom_side[g2]:
            fingers_touch = True
    fingers = {}
    for s in SIDES:
        pc, tip = gr.pad_points(d, s)
        jt = gr.joints(d, s)
        f = {"driver_angle": jt["driver"], "follower_angle": jt["follower"], "spring_link_angle": jt["spring_link"],
             "coupler_angle": jt["coupler"], "distal_pitch": gr.pitch(d, s),
             "pad_center": list(pc), "tip": list(tip), "tip_z_max_during": tip_max[s],
             "tip_rise": tip_max[s] - tip[2],
             "deepest_z_end": gr.deepest_side(d, s, set(LINKS)),
             "distal_deepest_z_end": gr.deepest_side(d, s, DISTAL),
             "touching_bar_end": sorted(touching[s]),
             "first_touch_link": first[s][1] if first[s] else None,
             "first_touch_t": first[s][0] if first[s] else None}
        f["distal_curled"] = f["distal_pitch"] > CURL_RAD
        fingers[s] = f
    row["fingers"] = fingers
    pp, pn = fingers["pos"]["pad_center"], fingers["neg"]["pad_center"]
    row["pad_gap"] = pp[0] - pn[0]
    row["tip_gap"] = fingers["pos"]["tip"][0] - fingers["neg"]["tip"][0]
    z_end = gr.deepest(d)
    row["deepest_z_end"] = z_end[0]
    row["deepest_end_link"] = f"{z_end[1]}.{z_end[2]}"
    row["deepest_z_max"] = max_deep[0]
    row["deepest_max_link"] = f"{max_deep[1]}.{max_deep[2]}" if max_deep[1] else "open_pose"
    row["deepest_max_t"] = max_deep[3]
    firsts = [(v[0], v[2], s, v[1]) for s, v in first.items() if v]
    if firsts:
        t0, _, s0, l0 = min(firsts)
        row["first_touch"] = {"side": s0, "link": l0, "t": t0}
        prox = any(v and v[1] in PROXIMAL for v in first.values())
        row["mode"] = "encompassing" if prox else "pinch"
    else:
        row["first_touch"] = {"side": None, "link": None, "t": None}
        row["mode"] = "none"
    # a tip is under the bar if, in the bar's cross-section frame (u along the width, v along the thickness,
    # v > 0 towards the bottom face), it lies within the width (1 mm inboard) and beyond the bottom face
    Rb = mat_of_quat(quat_axis_angle([0, 1, 0], math.radians(tilt)))
    for s in SIDES:
        loc = Rb.T @ (np.array(fingers[s]["tip"]) - np.array([0.0, 0.0, bg["z_center"]]))
        fingers[s]["tip_inboard"] = w / 2 - abs(loc[0])
        fingers[s]["tip_under_bar"] = bool(abs(loc[0]) < w / 2 - 1e-3 and loc[2] > t / 2)
    row["caged"] = all(fingers[s]["tip_under_bar"] for s in SIDES)
    row["fingers_touch_each_other_end"] = fingers_touch
    row["palm_touches_bar_end"] = palm_bar
    if table:
        row["table_touched"] = table_contact
        row["table_touched_end"] = table_end
        row["table_first_touch_t"] = table_first_t
        row["table_min_clearance"] = bg["z_bottom"] - max_deep[0]
        row["table_touch_links"] = sorted(table_links)
    else:
        row["table_touch_links"] = None
        row["table_touched"] = None
        row["table_touched_end"] = None
        row["table_first_touch_t"] = None
        row["table_min_clearance"] = None
    row["settled"] = settled
    row["t_end"] = t_end
    row["creep_speed"] = creep
    row["creep_since_t_min"] = creep_since
    return row


# ----------------------------------------------------------------------------------------------------
# Free air
def free_air(scene):
    m, gr = scene.compile(gravity=False)
    out = []
    for k in range(SWEEP_N):
        d = mujoco.MjData(m)
        q_t = 0.8 * k / (SWEEP_N - 1)
        d.ctrl[0] = q_t * CTRL_CLOSED / 0.8
        mujoco.mj_forward(m, d)
        n = 0
        while n * m.opt.timestep < SWEEP_T_CAP:
            mujoco.mj_step(m, d)
            n += 1
            if n * m.opt.timestep > 0.2 and np.abs(d.qvel).max() < SWEEP_VTOL:
                break
        s = {}
        for side in SIDES:
            pc, tip = gr.pad_points(d, side)
            jt = gr.joints(d, side)
            s[side] = (pc, tip, jt, gr.pitch(d, side), gr.deepest_side(d, side, set(LINKS)),
                       gr.deepest_side(d, side, DISTAL))
        pc, tip, jt, pitch, deep, ddeep = s["pos"]
        out.append({"ctrl": float(d.ctrl[0]), "driver_target": q_t, "driver_angle": jt["driver"],
                    "spring_link_angle": jt["spring_link"], "follower_angle": jt["follower"],
                    "distal_pitch": pitch,
                    "pad_gap": pc[0] - s["neg"][0][0], "pad_face_x": pc[0], "pad_center_z": pc[2],
                    "tip_x": tip[0], "tip_z": tip[2], "distal_deepest_z": ddeep, "deepest_z": deep,
                    "asym_pad_x": pc[0] + s["neg"][0][0], "t_end": n * m.opt.timestep})
    return out


def compare_ours(sweep):
    """Residuals ours - Menagerie at equal pad gap (and at equal driver angle = our q)."""
    if not OUR_TABLE.is_file():
        return None, ["(no crates/robot/data/robotiq_2f85.json to compare)"]
    tab = json.loads(OUR_TABLE.read_text())["table"]
    gaps = np.array([r["gap"] for r in tab])
    order = np.argsort(gaps)
    col = lambda k: np.array([r[k] for r in tab])[order]
    g_s = gaps[order]
    qs = np.array([r["q"] for r in tab])
    qo = np.argsort(qs)
    res = []
    L = ["| driver q | gap mm | pad z M | pad z ours(gap) | d | tip z M (pad end / distal deepest) | tip z ours(gap) "
         "| d vs deepest | pad x ours(q) - M mm | pad z ours(q) - M mm |", "|" + "---|" * 10]
    for r in sweep:
        g = r["pad_gap"]
        inside = g_s[0] - 1e-9 <= g <= g_s[-1] + 1e-9
        e = {"driver_angle": r["driver_angle"], "pad_gap": g}
        if inside:
            pz = float(np.interp(g, g_s, col("pad_center_z")))
            tz = float(np.interp(g, g_s, col("tip_z")))
            e.update({"ours_pad_center_z_at_gap": pz, "ours_tip_z_at_gap": tz,
                      "res_pad_center_z_at_gap": pz - r["pad_center_z"],
                      "res_tip_z_vs_pad_end_at_gap": tz - r["tip_z"],
                      "res_tip_z_vs_distal_deepest_at_gap": tz - r["distal_deepest_z"]})
        q = r["driver_angle"]
        if qs.min() <= q <= qs.max():
            px = float(np.interp(q, qs[qo], np.array([x["pad_face_x"] for x in tab])[qo]))
            pzq = float(np.interp(q, qs[qo], np.array([x["pad_center_z"] for x in tab])[qo]))
            e.update({"res_pad_face_x_at_q": px - r["pad_face_x"], "res_pad_center_z_at_q": pzq - r["pad_center_z"]})
        res.append(e)
        f = lambda k, s=1e3: f"{e[k]*s:+.2f}" if k in e else "-"
        L.append(f"| {q:.3f} | {g*1e3:.2f} | {r['pad_center_z']*1e3:.2f} | {f('ours_pad_center_z_at_gap')} | "
                 f"{f('res_pad_center_z_at_gap')} | {r['tip_z']*1e3:.2f} / {r['distal_deepest_z']*1e3:.2f} | "
                 f"{f('ours_tip_z_at_gap')} | {f('res_tip_z_vs_distal_deepest_at_gap')} | "
                 f"{f('res_pad_face_x_at_q')} | {f('res_pad_center_z_at_q')} |")
    keys = ["res_pad_center_z_at_gap", "res_tip_z_vs_pad_end_at_gap", "res_tip_z_vs_distal_deepest_at_gap",
            "res_pad_face_x_at_q", "res_pad_center_z_at_q"]
    summ = {}
    for k in keys:
        v = np.array([e[k] for e in res if k in e])
        if len(v):
            summ[k] = {"n": int(len(v)), "max_abs": float(np.abs(v).max()), "mean": float(v.mean())}
            L.append(f"{k}: n={len(v)} mean {v.mean()*1e3:+.3f} mm, max |.| {np.abs(v).max()*1e3:.3f} mm")
    return {"rows": res, "summary": summ}, L


# ----------------------------------------------------------------------------------------------------
# Output
def rnd(x):
    if isinstance(x, dict):
        return {k: rnd(v) for k, v in x.items()}
    if isinstance(x, (list, tuple, np.ndarray)):
        return [rnd(v) for v in x]
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        v = round(float(x), 6)
        return 0.0 if v == 0 else v
    return x


def flatten(x, pre=""):
    out = {}
    if isinstance(x, dict):
        for k, v in x.items():
            out.update(flatten(v, f"{pre}{k}."))
    elif isinstance(x, list) and len(x) == 3 and all(isinstance(v, float) for v in x):
        for a, v in zip("xyz", x):
            out[f"{pre}{a}"] = v
    elif isinstance(x, list):
        out[pre[:-1]] = "+".join(str(v) for v in x)
    else:
        out[pre[:-1]] = x
    return out


def write_atomic(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    with os.fdopen(fd, "w", newline="") as f:
        f.write(text)
    os.chmod(tmp, 0o644)
    os.replace(tmp, path)


def dump_json(header, rows):
    parts = ["{"]
    items = sorted(header.items())
    for k, v in items:
        parts.append(f"{json.dumps(k)}: {json.dumps(rnd(v), sort_keys=True)},")
    parts.append('"rows": [')
    parts.append(",\n".join(json.dumps(rnd(r), sort_keys=True) for r in rows))
    parts.append("]}")
    return "\n".join(parts) + "\n"


def csv_text(rows):
    flat = [flatten(rnd(r)) for r in rows]
    cols = sorted({k for f in flat for k in f})
    buf = io.StringIO()
    wr = csv.writer(buf, lineterminator="\n")
    wr.writerow(cols)
    for f in flat:
        line = []
        for c in cols:
            v = f.get(c)
            if v is None:
                line.append("")
            elif isinstance(v, bool):
                line.append("true" if v else "false")
            elif isinstance(v, float):
                line.append(f"{v:.6f}")
            else:
                line.append(str(v))
        wr.writerow(line)
    return buf.getvalue()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("menagerie", help="mujoco_menagerie checkout or (bare) git directory")
    ap.add_argument("--rev", default="HEAD", help="revision to read from a git directory (default HEAD)")
    ap.add_argument("--out", default=str(OUT_DIR), help="output directory")
    ap.add_argument("--limit", type=int, default=0, help="simulate only the first N grid rows (testing)")
    a = ap.parse_args()
    t_start = time.time()
    with tempfile.TemporaryDirectory(prefix="gripper_truth_") as tmp:
        src, prov = load_source(a.menagerie, a.rev, tmp)
        scene = Scene(src / MODEL_XML)
        gr0 = scene.gr0
        m0, grx = scene.compile(gravity=False)
        d0 = mujoco.MjData(m0)
        mujoco.mj_forward(m0, d0)
        open_pts = {s: grx.pad_points(d0, s) for s in SIDES}
        open_deep = grx.deepest(d0)
        L = [f"menagerie commit {prov['commit']} (robotiq_2f85 last changed {prov['robotiq_2f85_last_change']}), "
             f"mujoco {mujoco.__version__}",
             f"G from base_mount frame: R = {np.round(gr0.R_bm_G, 6).tolist()}, origin = {np.round(gr0.p_bm_G, 6).tolist()} "
             f"(mounting face: {gr0.face_vertices} base_mount vertices within 0.1 mm of it)",
             f"G from Menagerie world: R = {np.round(scene.R_w_G, 6).tolist()}, origin = {np.round(scene.o_w_G, 6).tolist()}",
             f"pad contact face centre (pad body frame) {gr0.pad_face_local.round(6).tolist()}, tip {gr0.pad_tip_local.round(6).tolist()}",
             f"open: pad centre {np.round(open_pts['pos'][0], 5).tolist()} tip {np.round(open_pts['pos'][1], 5).tolist()} "
             f"gap {2e3*open_pts['pos'][0][0]:.2f} mm; deepest finger point z {open_deep[0]:.5f} ({open_deep[1]}.{open_deep[2]})"]
        print("\n".join(L), flush=True)

        sweep = free_air(scene)
        cmp, CL = compare_ours(sweep)
        last = sweep[-1]
        print(f"free-air closed (ctrl 255, no gravity): driver {last['driver_angle']:.4f}, pad centre z {last['pad_center_z']:.5f},"
              f" tip z {last['tip_z']:.5f}, distal deepest z {last['distal_deepest_z']:.5f}, pad gap {last['pad_gap']*1e3:.2f} mm")
        print("\n".join(CL), flush=True)

        specs = grid()
        if a.limit:
            specs = specs[:a.limit]
        rows = []
        for i, sr in enumerate(specs):
            t0 = time.time()
            r = simulate_row(scene, sr)
            rows.append(r)
            extra = ""
            if r["status"] == "simulated":
                fp = r["fingers"]["pos"]
                extra = (f"{r['mode']:12s}{' caged' if r['caged'] else '      '} first {r['first_touch']['link'] or '-':11s} "
                         f"pitch {fp['distal_pitch']:+.3f} tip z {fp['tip'][2]:.4f} rise {fp['tip_rise']*1e3:5.1f} mm "
                         f"gap {r['pad_gap']*1e3:6.2f} deep {r['deepest_z_max']:.4f} "
                         f"{'settled' if r['settled'] else 'creep %.2f mm/s' % (r['creep_speed']*1e3)}"
                         + (f" table {'TOUCH' if r['table_touched'] else 'clear'} {r['table_min_clearance']*1e3:+.1f} mm"
                            if r["table"] else ""))
            print(f"[{i+1}/{len(specs)}] {r['id']} {r['status']} {extra} ({time.time()-t0:.2f} s)", flush=True)
    rows.sort(key=lambda r: r["id"])
    header = {
        "generator": SCRIPT,
        "source": {"repo": "https://github.com/google-deepmind/mujoco_menagerie", "path": f"{MODEL_DIR}/{MODEL_XML}", **prov},
        "mujoco_version": mujoco.__version__,
        "numpy_version": np.__version__,
        "units": "metres, radians (angles named *_deg in degrees), seconds; positions in G",
        "frame": ("G = UR flange/tool0 frame: origin on the flange face where the gripper mounts (the lowest face of "
                  "Menagerie's base_mount mesh), +z approach (towards the fingertips), x closing axis (pads at +-x; "
                  "side 'pos' = Menagerie right_* finger at +x, 'neg' = left_* at -x), y finger width."),
        "G_from_base_mount": {"R": gr0.R_bm_G.round(9).tolist(), "origin": gr0.p_bm_G.tolist()},
        "G_from_menagerie_world": {"R": scene.R_w_G.round(9).tolist(), "origin": scene.o_w_G.tolist()},
        "points": {"pad_center": ("centre of the pad contact face: pad body frame point "
                                  f"{gr0.pad_face_local.round(6).tolist()} (the inner face of the two pad boxes, mid-length)"),
                   "tip": f"far (deepest at open) end of the pad contact face on its centre line: pad body frame point {gr0.pad_tip_local.round(6).tolist()}",
                   "deepest": "max G z over all finger geometry points: convex-hull vertices of every finger mesh "
                              "(driver, coupler, spring_link, follower, pad, silicone_pad) and the pad box corners"},
        "open_pose": {"pad_center": open_pts["pos"][0], "tip": open_pts["pos"][1], "deepest_z": open_deep[0],
                      "pad_gap": open_pts["pos"][0][0] - open_pts["neg"][0][0]},
        "grid": {"power_point_z": POWER_Z, "bar_length_y": BAR_LEN, "widths_mm": WIDTHS_MM, "thicknesses_mm": THICKS_MM,
                 "depths_past_power_point_mm": DEPTHS_MM, "tilts_deg": TILTS_DEG,
                 "tilted_widths_mm": TILTED_WIDTHS_MM, "tilted_depths_mm": TILTED_DEPTHS_MM,
                 "rule": ("tilt 0: all widths x thicknesses x depths; tilt 10/20/30: tilted_widths x thicknesses x "
                          "tilted_depths; each with and without table. z_top = power_point_z + depth is the bar's "
                          "point nearest the palm (min G z of the tilted cross-section); the bar is centred on x = 0, "
                          "y = 0; tilt is a rotation about +y of G through the bar centre; the table is a plane at "
                          "the bar's lowest point (z_bottom), normal -z of G"),
                 "rows": len(rows)},
        "simulation": {"timestep": float(m0.opt.timestep), "integrator": int(m0.opt.integrator),
                       "cone": int(m0.opt.cone), "impratio": float(m0.opt.impratio),
                       "gravity_G": list(GRAVITY_G), "ctrl": f"ramp 0 -> {CTRL_CLOSED} over t_ramp, then held",
                       "t_ramp": T_RAMP, "t_cap": T_CAP, "t_min": T_MIN,
                       "settle": (f"stop when every tracked point (both pad centres and tips) moved < {SETTLE_TOL} m over "
                                  f"the last {SETTLE_WIN} s (sampled every {SAMPLE_EVERY} steps), not before t_min; "
                                  "else stop at t_cap (settled = false; creep_speed = max tracked-point speed over "
                                  "the last window, m/s; creep_since_t_min = max tracked-point displacement between "
                                  "t_min and t_end, m)"),
                       "friction": ("MuJoCo rules: the pad boxes have priority 1, so pad contacts use the pad "
                                    "friction (0.7 / 0.6); other pairs the max of both geoms; the bar and the table "
                                    "have MuJoCo's default friction (1, 0.005, 0.0001)"),
                       "open_check": (f"at the open pose (qpos0) a row is not simulated if any gripper geom penetrates "
                                      f"the bar (or the table) by more than {OPEN_TOL} m (MuJoCo contacts: meshes "
                                      "collide as their convex hulls)"),
                       "mode": ("pinch: every finger's first bar contact is on its distal (follower or pad); "
                                "encompassing: a finger's first bar contact is on a proximal link (driver, coupler, "
                                "spring_link); none: no finger touched the bar"),
                       "curl_threshold_rad": CURL_RAD},
        "free_air": {"gravity": "off", "ctrl": "255 * k / 19, k = 0..19, each from the open pose until "
                     f"max |qvel| < {SWEEP_VTOL} rad/s (t > 0.2 s) or {SWEEP_T_CAP} s", "rows": sweep,
                     "compare_crates_robot_data_robotiq_2f85_json": cmp},
    }
    out = Path(a.out)
    write_atomic(out / "closing_2f85.json", dump_json(header, rows))
    write_atomic(out / "closing_2f85.csv", csv_text(rows))
    print(f"wrote {out/'closing_2f85.json'} and .csv: {len(rows)} rows in {time.time()-t_start:.1f} s")


if __name__ == "__main__":
    main()
