#!/usr/bin/env python3
"""Robotiq 2F-85 finger linkage (underactuated, 2 DoF per finger) and convex finger pieces, from the
MuJoCo Menagerie model `robotiq_2f85/` (2f85.xml + assets/*.stl).

usage: derive_fingers.py <mujoco_menagerie repo> [--rev COMMIT]
  The repository may be a bare clone (files are read with `git show COMMIT:path`); COMMIT defaults to
  PINNED below (any commit whose robotiq_2f85/ holds the same files gives the same output).
Writes crates/robot/data/robotiq_2f85_fingers.json (linkage, sampled poses, pieces) and
crates/robot/data/robotiq_2f85_finger_vertices.json (test data: the mesh vertices the pieces must hold).
Needs: numpy scipy trimesh rtree mujoco (pip).

Frames. G = UR flange (tool0): origin on the flange face, +z approach, x closing (pads at ±x), y the
finger width; the data describe the +x finger (the other is its mirror x -> -x). The Menagerie model's
world frame is G up to a turn about z (its origin is the underside of `base_mount`, which sits on the
flange): the turn is chosen so the finger named `right_*` lies at +x. Each link frame L has the body's
origin and G's axes at the zero pose (L = body frame turned by R0, the bodies' common orientation at
qpos = 0); a link pose is [x, z, phi]: translation (x, 0, z) in G and rotation phi about G's +y. Every
Menagerie finger joint axis is G's -y, so a joint angle theta (MuJoCo's sign) turns its link by
phi = -theta about +y.
"""
import io
import subprocess
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
import trimesh
from scipy.spatial import ConvexHull, HalfspaceIntersection, cKDTree
from scipy import ndimage

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import git_show, r6  # noqa: E402
from derive import dump  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DATA = os.path.join(ROOT, "crates", "robot", "data")
SUB = "robotiq_2f85/"
# google-deepmind/mujoco_menagerie, "Improve 2f85 grasp stability by adding some armature to joints."
# (2024-02-15): the last upstream change to robotiq_2f85/ in the snapshot used; the meshes are unchanged
# since the initial launch (1b93125c, 2022-09-07).
PINNED = "a9f3e331238e5ca82923dfbeb93f4589af97b011"

# our robotiq_2f85.json / derive_gripper.MENAGERIE: gap (m) -> pad centre z (m), tips open / closed
TABLE = [(0.0852, 0.1416), (0.0700, 0.1467), (0.0533, 0.1507), (0.0356, 0.1534), (0.0172, 0.1547),
         (0.0, 0.1547)]
TIP_OPEN, TIP_CLOSED = 0.1603, 0.1735

LINKS = ["driver", "coupler", "spring_link", "follower", "pad"]
ALIASES = {"driver": "outer_knuckle", "coupler": "outer_finger", "spring_link": "inner_knuckle",
           "follower": "finger_tip (distal phalanx)", "pad": "pad + silicone_pad"}

# convex pieces
TARGET = 0.0009        # split while a piece's excess exceeds this (m); goal 1 mm
TAU = 0.0005           # cuts are ranked by the excess above this, summed over the boundary
MAX_PIECES = 8         # per link (reported if exceeded)
MAX_CELLS = 64         # over-segmentation budget per link
SEG_TARGETS = [0.0009, 0.0007, 0.0005]  # over-segmentation snapshots (cell excess, m)
OVERLAP = 0.0001       # each side of a cut keeps the points within this of the plane (m)
OUT = 2e-6             # piece planes moved outward by this before rounding (doubled as needed)
THIN = np.radians(3.0) # least angle between two kept facet normals of a stored piece
MIN_SEP = 2e-5         # stored piece vertices are at least this far apart (robust hulls downstream)
SEARCH_STEP = 0.0005   # boundary sampling while searching cuts (m)
FINAL_STEP = 0.0002    # boundary sampling of the reported excess (m)
SURF_STEP = 0.0001     # surface sampling of the reference meshes (distance tree, voxel shell)
PITCH = 0.0002         # voxel pitch of the inside test
FILL_R = 0.0031        # through-holes up to this radius (pin bores, screw holes) count as solid


# ----------------------------------------------------------------------------------------------
# loading

def load(repo, rev):
    """(MjModel, xml text, {mesh name: trimesh in its body frame (scaled)})."""
    import mujoco
    xml = git_show(repo, SUB + "2f85.xml", rev).decode()
    root = ET.fromstring(xml)
    comp = root.find("compiler")
    meshdir = comp.get("meshdir", "") if comp is not None else ""
    files = {}
    for mesh in root.iter("mesh"):
        f = mesh.get("file")
        if f:
            files[f] = git_show(repo, SUB + (meshdir + "/" if meshdir else "") + f, rev)
    assets = dict(files)   # MuJoCo's asset dict is keyed by the file attribute
    m = mujoco.MjModel.from_xml_string(xml, assets)
    meshes = {}
    for k in range(m.nmesh):
        name = m.mesh(k).name
        fname = [f for f in files if os.path.splitext(os.path.basename(f))[0] == name]
        assert len(fname) == 1, name
        t = trimesh.load(io.BytesIO(files[fname[0]]), file_type="stl", process=True)
        t.merge_vertices()
        t = trimesh.Trimesh(t.vertices * m.mesh_scale[k], t.faces, process=True)
        meshes[name] = t
    return m, meshes


def quat_mat(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def body_meshes(m, meshes, body, skip=()):
    """Visual meshes of a body and of its rigidly attached children (no joint, not in `skip`), in the
    body frame, and the geoms of every class (visual group 2, collision group 3)."""
    import mujoco
    out, visual, collision = [], [], []
    bodies = [body]
    for b in range(m.nbody):
        if m.body_parentid[b] == body and m.body_jntnum[b] == 0 and b != body and b not in skip:
            bodies.append(b)
    for b in bodies:
        # child pose in body frame (one level, as in 2f85.xml: silicone_pad in pad)
        Tb = np.eye(4)
        if b != body:
            Tb[:3, :3] = quat_mat(m.body_quat[b]); Tb[:3, 3] = m.body_pos[b]
        for g in range(m.ngeom):
            if m.geom_bodyid[g] != b:
                continue
            if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH:
                name = m.mesh(m.geom_dataid[g]).name
                (visual if m.geom_group[g] == 2 else collision).append(name)
                if m.geom_group[g] == 2:
                    t = meshes[name].copy(); t.apply_transform(Tb)
                    out.append(t)
            else:
                collision.append(f"{['plane','hfield','sphere','capsule','ellipsoid','cylinder','box'][m.geom_type[g]]}"
                                 f" size {np.round(m.geom_size[g], 6).tolist()} at {np.round(m.geom_pos[g], 6).tolist()}")
    return out, visual, collision


# ----------------------------------------------------------------------------------------------
# planar kinematics in G's x-z plane.  rot(phi) = rotation about +y by phi acting on (x, z).

def rot(phi):
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, s], [-s, c]])


def ang(v):
    """Angle of a planar vector (x, z) in the rot() sense: rot(phi) @ (1, 0) has ang = phi."""
    return float(np.arctan2(-v[1], v[0]))


def circle_meet(P, rp, Q, rq, side):
    """Intersection of circles (P, rp), (Q, rq): the one with sign(cross(Q - P, X - P)) == side."""
    d = Q - P; L = np.linalg.norm(d)
    a = (rp * rp - rq * rq + L * L) / (2 * L)
    h2 = rp * rp - a * a
    if h2 < -1e-12:
        raise ValueError("loop does not close")
    h = np.sqrt(max(h2, 0.0))
    u = d / L; w = np.array([-u[1], u[0]])
    X = P + a * u + h * w
    if np.sign(u[0] * (X - P)[1] - u[1] * (X - P)[0]) != side and h > 0:
        X = P + a * u - h * w
    return X


def cross2(a, b):
    return float(a[0] * b[1] - a[1] * b[0])


class Linkage:
    """The +x finger: pivots A (driver), B (spring_link) on the base; the driver carries the coupler
    joint C at Cd; the coupler meets the follower's frame origin D at Dc (the `connect` equality);
    the spring_link carries the follower joint E at Es; in the follower frame E is at Ef; the pad frame
    is at Pf in the follower frame (parallel to it). All in link frames (x, z)."""

    def __init__(self, p):
        self.__dict__.update({k: np.asarray(v, float) if isinstance(v, (list, tuple, np.ndarray)) else v
                              for k, v in p.items()})
        self.lc = np.linalg.norm(self.Dc); self.lf = np.linalg.norm(self.Ef)
        self.ls = np.linalg.norm(self.Es); self.lk = np.linalg.norm(self.Cd + self.Dc)
        # branches, from the zero pose (all joint angles 0)
        C0 = self.A + self.Cd; E0 = self.B + self.Es; D0 = E0 - self.Ef
        self.side_D = np.sign(cross2(E0 - C0, D0 - C0))
        self.side_E = np.sign(cross2(self.B - D0, E0 - D0))

    def solve(self, td, ts):
        """Joint angles (driver, coupler, spring_link, follower) from driver and spring_link angles."""
        C = self.A + rot(-td) @ self.Cd
        E = self.B + rot(-ts) @ self.Es
        D = circle_meet(C, self.lc, E, self.lf, self.side_D)
        phic = ang(D - C) - ang(self.Dc)
        phif = ang(D - E) - ang(-self.Ef)
        tc = _wrap(-phic - td); tf = _wrap(-phif - ts)
        return np.array([td, tc, ts, tf])

    def parallel(self, td):
        """Spring-held mode (coupler at its limit 0): the driver and coupler move as one crank A->D."""
        D = self.A + rot(-td) @ (self.Cd + self.Dc)
        E = circle_meet(D, self.lf, self.B, self.ls, self.side_E)
        ts = _wrap(-(ang(E - self.B) - ang(self.Es)))
        return self.solve(td, ts)

    def poses(self, q):
        """Link poses [x, z, phi] in G for joint angles q = (driver, coupler, spring_link, follower)."""
        td, tc, ts, tf = q
        C = self.A + rot(-td) @ self.Cd
        E = self.B + rot(-ts) @ self.Es
        phif = -(ts + tf)
        D = E + rot(phif) @ (-self.Ef)
        P = D + rot(phif) @ self.Pf
        return {"driver": [*self.A, -td], "coupler": [*C, -(td + tc)], "spring_link": [*self.B, -ts],
                "follower": [*D, phif], "pad": [*P, phif]}


def _wrap(a):
    return float((a + np.pi) % (2 * np.pi) - np.pi)


def pose_T(p):
    """4x4 of a planar pose [x, z, phi]."""
    x, z, phi = p
    c, s = np.cos(phi), np.sin(phi)
    T = np.eye(4); T[0, 0] = c; T[0, 2] = s; T[2, 0] = -s; T[2, 2] = c; T[0, 3] = x; T[2, 3] = z
    return T


class MjFinger:
    """MuJoCo's own forward kinematics of the +x finger with the loop closed numerically: the
    `connect` equality (follower anchor == coupler anchor) is solved by Gauss-Newton over two free
    joints, the others fixed."""

    def __init__(self, m, prefix, R0, eq):
        import mujoco
        self.mj = mujoco
        self.m = m; self.d = mujoco.MjData(m); self.R0 = R0
        self.jq = {n: m.jnt_qposadr[m.joint(prefix + n + "_joint").id] for n in ["driver", "coupler", "spring_link", "follower"]}
        self.bid = {n: m.body(prefix + n).id for n in LINKS}
        self.eq = eq  # (body1, anchor1, body2, anchor2)

    def _set(self, q):
        self.d.qpos[:] = 0
        for n, v in zip(["driver", "coupler", "spring_link", "follower"], q):
            self.d.qpos[self.jq[n]] = v
        self.mj.mj_kinematics(self.m, self.d)

    def residual(self, q):
        self._set(q)
        b1, a1, b2, a2 = self.eq
        p1 = self.d.xpos[b1] + self.d.xmat[b1].reshape(3, 3) @ a1
        p2 = self.d.xpos[b2] + self.d.xmat[b2].reshape(3, 3) @ a2
        return p1 - p2

    def close(self, q, free):
        """Solve the loop for the joints `free` (two indices into q), the others fixed."""
        q = np.array(q, float)
        for _ in range(50):
            r = self.residual(q)
            if np.linalg.norm(r) < 1e-14:
                break
            J = np.zeros((3, len(free)))
            for k, i in enumerate(free):
                dq = q.copy(); dq[i] += 1e-7
                J[:, k] = (self.residual(dq) - r) / 1e-7
            q[free] -= np.linalg.lstsq(J, r, rcond=None)[0]
        return q, float(np.linalg.norm(self.residual(q)))

    def poses(self, q):
        """Link poses [x, z, phi] in G (G = world turned by Rg about z) from MuJoCo's xpos/xmat."""
        self._set(q)
        out = {}
        for n in LINKS:
            b = self.bid[n]
            p = self.Rg @ self.d.xpos[b]
            R = self.Rg @ self.d.xmat[b].reshape(3, 3) @ self.R0.T
            assert abs(p[1]) < 1e-9 and abs(R[1, 1] - 1) < 1e-9, (n, p, R)
            out[n] = [p[0], p[2], float(np.arctan2(R[0, 2], R[0, 0]))]
        return out


def setup(m, meshes):
    """The +x finger: G rotation, link frames, linkage parameters, link meshes (link frames)."""
    import mujoco
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    # the finger whose driver lies at +x after the turn Rg about z; Menagerie calls it "right"
    sides = [p for p in ("right_", "left_") if m.body(p + "driver").id >= 0]
    best = None
    for p in sides:
        x, y = d.xpos[m.body(p + "driver").id][:2]
        a = np.arctan2(y, x)
        if best is None or abs(a) < abs(best[1]):
            best = (p, a)
    prefix, a = best
    a = -a
    Rg = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    Rg[np.abs(Rg) < 1e-12] = 0.0
    bid = {n: m.body(prefix + n).id for n in LINKS}
    R0 = Rg @ d.xmat[bid["driver"]].reshape(3, 3)
    for n in LINKS:
        assert np.allclose(Rg @ d.xmat[bid[n]].reshape(3, 3), R0, atol=1e-12), n
    jid = {n: m.joint(prefix + n + "_joint").id for n in ["driver", "coupler", "spring_link", "follower"]}
    for n, j in jid.items():
        axis = R0 @ m.jnt_axis[j]
        assert np.allclose(axis, [0, -1, 0], atol=1e-12), (n, axis)
    for n in ["driver", "coupler", "spring_link"]:
        assert np.allclose(m.jnt_pos[jid[n]], 0), n
    for n in ["coupler", "follower", "pad"]:
        assert np.allclose(m.body_quat[bid[n]], [1, 0, 0, 0]), n
    assert m.body_parentid[bid["coupler"]] == bid["driver"]
    assert m.body_parentid[bid["follower"]] == bid["spring_link"]
    assert m.body_parentid[bid["pad"]] == bid["follower"]
    eq = None
    for k in range(m.neq):
        if m.eq_type[k] == mujoco.mjtEq.mjEQ_CONNECT and {m.eq_obj1id[k], m.eq_obj2id[k]} == {bid["follower"], bid["coupler"]}:
            b1, b2 = m.eq_obj1id[k], m.eq_obj2id[k]
            a1, a2 = m.eq_data[k][0:3].copy(), m.eq_data[k][3:6].copy()
            if b1 != bid["follower"]:
                b1, b2, a1, a2 = b2, b1, a2, a1
            eq = (b1, a1, b2, a2)
    assert eq is not None and np.allclose(eq[1], 0), "connect anchor must be the follower's origin"
    xz = lambda v: [float(v[0]), float(v[2])]
    g = lambda b: Rg @ d.xpos[b]
    for v in (g(bid["driver"]), g(bid["spring_link"])):
        assert abs(v[1]) < 1e-12
    params = {
        "A": xz(g(bid["driver"])), "B": xz(g(bid["spring_link"])),
        "Cd": xz(R0 @ m.body_pos[bid["coupler"]]),
        "Dc": xz(R0 @ eq[3]),
        "Es": xz(R0 @ (m.body_pos[bid["follower"]] + m.jnt_pos[jid["follower"]])),
        "Ef": xz(R0 @ m.jnt_pos[jid["follower"]]),
        "Pf": xz(R0 @ m.body_pos[bid["pad"]]),
    }
    for v in [R0 @ m.body_pos[bid["coupler"]], R0 @ eq[3], R0 @ m.jnt_pos[jid["follower"]], R0 @ m.body_pos[bid["pad"]]]:
        assert abs(v[1]) < 1e-12
    ranges = {n: [float(m.jnt_range[j][0]), float(m.jnt_range[j][1])] for n, j in jid.items()}
    extra = {n: {"stiffness": float(m.jnt_stiffness[j]), "springref": float(m.qpos_spring[m.jnt_qposadr[j]])}
             for n, j in jid.items() if m.jnt_stiffness[j] > 0}
    # link meshes in link frames (visual meshes; collision geoms listed for the record)
    link_mesh, geoms = {}, {}
    for n in LINKS:
        parts, vis, col = body_meshes(m, meshes, bid[n], skip=set(bid.values()))
        t = trimesh.util.concatenate(parts)
        t.apply_transform(np.block([[R0, np.zeros((3, 1))], [np.zeros((1, 3)), np.ones((1, 1))]]))
        link_mesh[n] = (t, parts)
        geoms[n] = {"visual": vis, "collision": col}
    fk = MjFinger(m, prefix, R0, eq)
    fk.Rg = Rg
    return dict(prefix=prefix, Rg=Rg, R0=R0, params=params, ranges=ranges, springs=extra,
                link_mesh=link_mesh, geoms=geoms, fk=fk, bid=bid)


def kinematics(S, L):
    """Closed form vs MuJoCo; pad centre / tips vs our table; sampled poses."""
    lk = Linkage(S["params"])
    fk = S["fk"]
    padV = S["link_mesh"]["pad"][0].vertices
    xface = padV[:, 0].min()
    face = padV[padV[:, 0] <= xface + 1e-6]
    pad_c = np.array([xface, 0.5 * (face[:, 2].min() + face[:, 2].max())])
    follV = S["link_mesh"]["follower"][0].vertices

    def extras(P):
        Tp = pose_T(P["pad"]); Tf = pose_T(P["follower"])
        c = Tp[:3, :3] @ np.array([pad_c[0], 0, pad_c[1]]) + Tp[:3, 3]
        tip = max((follV @ Tf[:3, :3].T + Tf[:3, 3])[:, 2].max(), (padV @ Tp[:3, :3].T + Tp[:3, 3])[:, 2].max())
        facex = (padV @ Tp[:3, :3].T + Tp[:3, 3])[:, 0].min()
        return {"pad_center": [c[0], c[2]], "pad_face_x": facex, "gap": 2 * facex, "tip_z": tip}

    worst = {"pose": 0.0, "closure": 0.0}

    def sample(q_mj, mode):
        """One sample from MuJoCo's FK (loop closed), compared with the closed form."""
        P = fk.poses(q_mj)
        q_cf = lk.solve(q_mj[0], q_mj[2])
        Pc = lk.poses(q_cf)
        dev = max(max(abs(a - b) for a, b in zip(P[n], Pc[n])) for n in LINKS)
        dev = max(dev, float(np.abs(q_cf - q_mj).max()))
        worst["pose"] = max(worst["pose"], dev)
        return {"mode": mode, "q": r6(q_mj), "links": {n: r6(P[n]) for n in LINKS},
                **{k: r6(v) for k, v in extras(P).items()}}, dev

    # spring-held (parallel) mode: coupler at 0, driver 0..0.8 in 20 steps
    lo, hi = S["ranges"]["driver"]
    par = []
    q = np.zeros(4)
    for td in np.linspace(lo, hi, 21):
        q[0] = td; q[1] = 0.0
        q, res = fk.close(q, [2, 3])
        worst["closure"] = max(worst["closure"], res)
        qc = lk.parallel(td)
        worst["pose"] = max(worst["pose"], float(np.abs(qc - q).max()))
        s, dev = sample(q.copy(), "parallel")
        par.append(s)
    # blocked proximal phalanx: spring_link held where the parallel mode had it at driver angle t0,
    # the driver turns on by dt (coupler leaves its limit, the follower curls)
    blocked = []
    for t0 in (0.0, 0.2, 0.4, 0.6):
        qp = lk.parallel(t0)
        for dt in (0.05, 0.1, 0.2, 0.3, 0.4):
            td = t0 + dt
            if td > hi + 1e-12:
                continue
            q = qp.copy(); q[0] = td
            q, res = fk.close(q, [1, 3])
            worst["closure"] = max(worst["closure"], res)
            ok = all(S["ranges"][n][0] - 1e-9 <= v <= S["ranges"][n][1] + 1e-9
                     for n, v in zip(["driver", "coupler", "spring_link", "follower"], q))
            if not ok:
                continue
            s, dev = sample(q.copy(), "blocked")
            s["blocked_at_driver"] = r6(t0)
            blocked.append(s)
    return lk, par, blocked, worst, pad_c, extras


# ----------------------------------------------------------------------------------------------
# convex pieces

def tri_samples(T, step):
    """Points on the triangles T (n, 3, 3), deterministic, no point of a triangle farther than
    step / sqrt(2) from one: rows parallel to the longest edge, <= step apart, each sampled <= step
    apart (ends included, so the vertices are samples)."""
    T = np.asarray(T, float)
    if len(T) == 0:
        return np.zeros((0, 3))
    e = np.stack([np.linalg.norm(T[:, (i + 1) % 3] - T[:, i], axis=1) for i in range(3)], axis=1)
    k = np.argmax(e, axis=1)
    idx = (k[:, None] + np.arange(3)[None, :]) % 3            # longest edge P0 -> P1, P2 opposite
    T = np.take_along_axis(T, idx[:, :, None], axis=1)
    P0, P1, P2 = T[:, 0], T[:, 1], T[:, 2]
    Lb = np.linalg.norm(P1 - P0, axis=1)
    area2 = np.linalg.norm(np.cross(P1 - P0, P2 - P0), axis=1)
    h = np.where(Lb > 0, area2 / np.maximum(Lb, 1e-300), 0.0)
    nr = np.ceil(h / step).astype(int) + 1                    # rows (j = 0 .. nr-1; 1 row = the edge)
    tri = np.repeat(np.arange(len(T)), nr)
    j = np.arange(len(tri)) - np.repeat(np.cumsum(nr) - nr, nr)
    f = np.where(nr[tri] > 1, j / np.maximum(nr[tri] - 1, 1), 0.0)
    a = P0[tri] + f[:, None] * (P2[tri] - P0[tri])
    b = P1[tri] + f[:, None] * (P2[tri] - P1[tri])
    npt = np.ceil(Lb[tri] * (1 - f) / step).astype(int) + 1
    row = np.repeat(np.arange(len(tri)), npt)
    i = np.arange(len(row)) - np.repeat(np.cumsum(npt) - npt, npt)
    g = np.where(npt[row] > 1, i / np.maximum(npt[row] - 1, 1), 0.0)
    return a[row] + g[:, None] * (b[row] - a[row])


class Surface:
    """The reference solid of a link and distances to its surface. Voxels (PITCH) of the lattice samples
    (SURF_STEP) form the shell; dilated by one voxel and hole-filled, the solid. With `fill_radius`,
    small through-holes are filled too (pin bores at the joints, the follower's screw holes): in every
    voxel slice across x, y and z, the regions enclosed by the solid with area <= pi fill_radius^2.
    The dilated shell counts as outside (its points lie within ~0.4 mm of the surface). Distances:
    a Euclidean distance transform of the shell and hole-cap voxels, interpolated (searching, error
    <~0.2 mm), or the k-d tree of the surface samples and cap-voxel centres refined by exact closest
    points on the mesh (reporting)."""

    def __init__(self, mesh, fill_radius=0.0, step=SURF_STEP, pitch=PITCH):
        self.mesh = mesh
        S = np.unique(np.round(tri_samples(mesh.triangles, step), 9), axis=0)
        self.pitch = pitch
        self.lo = mesh.bounds[0] - 4 * pitch
        shape = np.ceil((mesh.bounds[1] + 4 * pitch - self.lo) / pitch).astype(int) + 1
        shell = np.zeros(shape, bool)
        ijk = np.floor((S - self.lo) / pitch).astype(int)
        shell[tuple(ijk.T)] = True
        thick = ndimage.binary_dilation(shell)
        solid = ndimage.binary_fill_holes(thick)
        fill = np.zeros(shape, bool)
        if fill_radius > 0:
            amax = np.pi * (fill_radius / pitch) ** 2
            for ax in range(3):
                for k in range(shape[ax]):
                    sl = np.take(solid, k, axis=ax)
                    holes = ndimage.binary_fill_holes(sl) & ~sl
                    if not holes.any():
                        continue
                    lab, n = ndimage.label(holes)
                    size = ndimage.sum(holes, lab, np.arange(1, n + 1))
                    keep = np.isin(lab, 1 + np.nonzero(size <= amax)[0])
                    idx = [slice(None)] * 3; idx[ax] = k
                    fill[tuple(idx)] |= keep
            fill &= ~solid
        full = solid | fill
        cap = fill & ndimage.binary_dilation(~full)
        C = self.lo + (np.argwhere(cap) + 0.5) * pitch
        self.fill = fill
        self.fill_volume = float(fill.sum() * pitch ** 3)
        self.fill_parts = int(ndimage.label(fill)[1]) if fill.any() else 0
        self.tree = cKDTree(np.vstack([S, C]))
        self.cap_tree = cKDTree(C) if len(C) else None
        self.edt = ndimage.distance_transform_edt(~(shell | cap), sampling=pitch)
        self.interior = full & ~thick

    def _vox(self, grid, X):
        ijk = np.floor((X - self.lo) / self.pitch).astype(int)
        ok = np.all((ijk >= 0) & (ijk < np.array(grid.shape)), axis=1)
        res = np.zeros(len(X), bool)
        res[ok] = grid[tuple(ijk[ok].T)]
        return res

    def inside(self, X):
        return self._vox(self.interior, X)

    def fast(self, X):
        """Approximate excess per point (distance transform; 0 inside)."""
        c = ((X - self.lo) / self.pitch - 0.5).T
        d = ndimage.map_coordinates(self.edt, c, order=1, mode="nearest")
        d[self.inside(X)] = 0.0
        return d

    def excess(self, X):
        """Per point: distance to the surface (k-d tree of the samples) if outside the solid, else 0."""
        d = np.zeros(len(X))
        out = ~self.inside(X)
        if out.any():
            d[out] = self.tree.query(X[out])[0]
        return d

    def exact(self, X):
        """Distance to the mesh if outside it (trimesh signed distance; exact), capped by the distance to
        the nearest hole-cap voxel centre; 0 inside the mesh or a filled hole."""
        if len(X) == 0:
            return np.zeros(0)
        sd = trimesh.proximity.signed_distance(self.mesh, X)   # > 0 inside
        d = np.maximum(-sd, 0.0)
        if self.cap_tree is not None:
            d = np.minimum(d, self.cap_tree.query(X)[0])
            d[self._vox(self.fill, X)] = 0.0
        return d


class Cutter:
    """Cells of a link = convex regions (half-spaces n.x <= c); a cell's piece = the convex hull of the
    link's surface clipped to the region (mesh vertices inside + edge/cut-plane crossings)."""

    def __init__(self, mesh, surf):
        self.V = mesh.vertices
        E = mesh.edges_unique
        self.a, self.b = self.V[E[:, 0]], self.V[E[:, 1]]
        self.surf = surf

    def points(self, region):
        keep = np.ones(len(self.V), bool)
        for n, c in region:
            keep &= self.V @ n <= c + 1e-12
        pts = [self.V[keep]]
        for i, (n, c) in enumerate(region):
            da, db = self.a @ n - c, self.b @ n - c
            x = (da * db) < 0
            t = da[x] / (da[x] - db[x])
            X = self.a[x] + t[:, None] * (self.b[x] - self.a[x])
            ok = np.ones(len(X), bool)
            for j, (m, d) in enumerate(region):
                if j != i:
                    ok &= X @ m <= d + 1e-12
            pts.append(X[ok])
        return np.vstack(pts)

    def piece(self, region):
        return _hull(self.points(region))

    def score(self, h, step=SEARCH_STEP):
        """(excess above TAU summed over the boundary samples x step^2, max excess) of one piece alone
        (approximate distances); (0, 0) for an empty piece."""
        if h is None:
            return 0.0, 0.0
        X = np.vstack([tri_samples(h.points[h.simplices], step), h.points[h.vertices]])
        e = self.surf.fast(X)
        return float(np.maximum(e - TAU, 0).sum() * step * step), float(e.max())


def _dirs(mesh):
    """Cut normals: every 15 deg in the x-z plane, y, four y-diagonals, and the normals of the mesh's 12
    largest planar facets (directions within 3 deg of one already listed are dropped)."""
    out = [np.array([np.cos(a), 0.0, np.sin(a)]) for a in np.radians(np.arange(0, 180, 15))]
    out.append(np.array([0.0, 1.0, 0.0]))
    s = np.sqrt(0.5)
    out += [np.array(v) for v in ([s, s, 0.0], [s, -s, 0.0], [0.0, s, s], [0.0, s, -s])]
    if len(mesh.facets):
        order = np.argsort(-mesh.facets_area, kind="stable")[:12]
        for k in order:
            n = np.asarray(mesh.facets_normal[k], float)
            if all(abs(n @ m) < np.cos(np.radians(3)) for m in out):
                out.append(n / np.linalg.norm(n))
    return out


def best_cut(cut, region, dirs):
    """The plane splitting the cell that minimises the two pieces' summed excess above TAU (ties: the
    larger maximum): normals `dirs`, offsets every 0.5 mm, then every 0.1 mm around the 4 best."""
    P = cut.points(region)
    cands = []

    def trial(n, c):
        s1, m1 = cut.score(cut.piece(region + [(n, c + OVERLAP)]))
        s2, m2 = cut.score(cut.piece(region + [(-n, -c + OVERLAP)]))
        cands.append((round(s1 + s2, 15), round(max(m1, m2), 9), len(cands), n, c))

    for n in dirs:
        pr = P @ n
        lo, hi = pr.min(), pr.max()
        for c in np.arange(lo + 0.0003, hi - 0.0003 + 1e-12, 0.0005):
            trial(n, float(c))
    if not cands:
        return None
    for _, _, _, n, c in sorted(cands, key=lambda t: t[:3])[:4]:
        for dc in np.arange(-0.0004, 0.00041, 0.0001):
            if abs(dc) > 1e-12:
                trial(n, c + dc)
    best = min(cands, key=lambda t: t[:3])
    return best


def union_samples(hulls, step):
    """Boundary samples of the union of the hulls: each hull's samples not inside another hull."""
    out = []
    for i, h in enumerate(hulls):
        X = np.vstack([tri_samples(h.points[h.simplices], step), h.points[h.vertices]])
        keep = np.ones(len(X), bool)
        for j, g in enumerate(hulls):
            if j != i:
                keep &= (X @ g.equations[:, :3].T + g.equations[:, 3]).max(axis=1) > -1e-9
        out.append(X[keep])
    return np.vstack(out)


def measure(surf, hulls, step=FINAL_STEP, exact=True):
    """Excess of the union (largest distance of a boundary point outside the link to the link's surface)
    and the worst point: boundary samples every `step`, k-d tree distances, the candidates within
    0.25 mm of the maximum refined with exact closest points (`exact`)."""
    X = union_samples(hulls, step)
    e = surf.excess(X)
    if exact:
        cand = e >= e.max() - 0.00025
        e = e.copy(); e[cand] = surf.exact(X[cand])
        e[~cand] = np.minimum(e[~cand], e[cand].max())  # below the refined maximum anyway
    i = int(np.argmax(e))
    return float(e[i]), X[i]


def _hull(P):
    """Convex hull of P; a degenerate point set (a sliver cell: coplanar or collinear points) is
    thickened by 0.1 um along x, y and z first. None for fewer than 4 points."""
    if len(P) < 4:
        return None
    try:
        return ConvexHull(P)
    except Exception:
        try:
            return ConvexHull(np.vstack([P + 1e-7 * e for e in np.vstack([np.eye(3), -np.eye(3)])]))
        except Exception:
            return None


def _split(cut, region, dirs):
    """Best cut of a cell (best_cut); where no plane lowers its excess (a ring, a hole) the cell is
    halved across its longest extent among `dirs` instead, so the over-segmentation always progresses."""
    b = best_cut(cut, region, dirs)
    if b is not None:
        n, c = b[3], b[4]
        h0 = cut.piece(region)
        s0 = cut.score(h0)
        if b[0] < s0[0] - 1e-15 or b[1] < s0[1] - 1e-4:
            return n, c
    P = cut.points(region)
    spans = [(np.ptp(P @ n), k) for k, n in enumerate(dirs)]
    _, k = max(spans, key=lambda t: (round(t[0], 9), -t[1]))
    n = dirs[k]
    return n, float(0.5 * ((P @ n).min() + (P @ n).max()))


def agglomerate(cut, pts, order):
    """Merge pieces (point sets) while some merged hull (the hull of both point sets; any two pieces,
    not only neighbours) stays within TARGET: `order` "least" takes the merge of least excess first,
    "largest" the one of largest merged volume. Then a piece whose points all lie in the others is
    dropped. Returns (points, hulls, own excesses)."""
    pts = [P for P in pts if _hull(P) is not None]
    hulls = [_hull(P) for P in pts]
    own = [cut.score(h)[1] for h in hulls]
    uid = list(range(len(pts)))
    nxt = len(pts)
    cache = {}
    while len(pts) > 1:
        best = None
        for i in range(len(pts)):
            for j in range(i + 1, len(pts)):
                key = (uid[i], uid[j])
                if key not in cache:
                    h = _hull(np.vstack([pts[i], pts[j]]))
                    cache[key] = (cut.score(h)[1], h)
                e, h = cache[key]
                if e > TARGET:
                    continue
                rank = (round(e, 9), i, j) if order == "least" else (-round(h.volume, 15), i, j)
                if best is None or rank < best[0]:
                    best = (rank, e, i, j, h)
        if best is None:
            break
        _, e, i, j, h = best
        P = np.vstack([pts[i], pts[j]])
        for k in (j, i):
            del pts[k], hulls[k], own[k], uid[k]
        pts.append(P); hulls.append(h); own.append(e); uid.append(nxt); nxt += 1
    k = 0
    while k < len(pts) and len(pts) > 1:
        inside = np.zeros(len(pts[k]), bool)
        for m, g in enumerate(hulls):
            if m != k:
                inside |= (pts[k] @ g.equations[:, :3].T + g.equations[:, 3]).max(axis=1) <= -1e-9
        if inside.all():
            del pts[k], hulls[k], own[k]
        else:
            k += 1
    return pts, hulls, own


def decompose(name, mesh, log):
    """Convex pieces of one link.
    (1) Over-segmentation: the cell with the largest (approximate) excess is cut by a plane (_split);
        snapshots when every cell is within each of SEG_TARGETS (at most MAX_CELLS cells).
    (2) Agglomeration of each snapshot, both merge orders (agglomerate).
    The variant with the fewest pieces wins (ties: the smaller union excess, approximate; then the
    earlier variant). Pieces may overlap; each holds the mesh vertices of its cell(s)."""
    surf = Surface(mesh, FILL_R)
    log(f"  {name}: {surf.fill_parts} small hole(s) filled ({surf.fill_volume*1e9:.1f} mm^3)")
    cut = Cutter(mesh, surf)
    dirs = _dirs(mesh)
    cells = [[]]
    sc = [cut.score(cut.piece([]))]
    snaps = []
    for target in SEG_TARGETS:
        while True:
            todo = [i for i in np.argsort([-m for _, m in sc], kind="stable") if sc[i][1] > target]
            if not todo or len(cells) >= MAX_CELLS:
                break
            i = int(todo[0])
            n, c = _split(cut, cells[i], dirs)
            new = [r for r in (cells[i] + [(n, c + OVERLAP)], cells[i] + [(-n, -c + OVERLAP)])
                   if len(cut.points(r)) > 0]
            cells[i:i + 1] = new
            sc[i:i + 1] = [cut.score(cut.piece(r)) for r in new]
        if max(m for _, m in sc) <= TARGET:
            snaps.append((target, list(cells)))
    variants = []
    for target, cl in snaps:
        for order in ("least", "largest"):
            pts, hulls, own = agglomerate(cut, [cut.points(r) for r in cl], order)
            e = measure(surf, hulls, SEARCH_STEP, exact=False)[0]
            log(f"  {name}: cells within {target*1e3:.1f} mm: {len(cl)}; merged ({order} first): "
                f"{len(hulls)} pieces, excess ~{e*1e3:.2f} mm")
            variants.append(((len(hulls), round(e, 5), len(variants)), pts, hulls))
    if not variants:
        raise SystemExit(f"{name}: no decomposition within {TARGET*1e3:.1f} mm in {MAX_CELLS} cells")
    _, pts, hulls = min(variants, key=lambda v: v[0])
    return surf, cut, pts, hulls


def finalize(name, mesh, cut, pts, hulls, log):
    """Pieces as stored: every mesh vertex is given to a piece (a vertex of a dropped sliver cell joins
    the piece it widens least); each piece's hull facet normals are thinned to THIN apart (largest
    facets first; each plane at the support of the piece's points), its planes are moved out by OUT (doubled until every point of the piece lies >= 1 um
    inside the piece rounded to 6 decimals, its vertices thinned to MIN_SEP apart) and its vertices
    recomputed."""
    V = np.unique(np.round(mesh.vertices, 12), axis=0)
    pts = [np.asarray(P) for P in pts]

    def depth(h, X):   # > 0 inside
        return -(X @ h.equations[:, :3].T + h.equations[:, 3]).max(axis=1)

    D = np.array([depth(h, V) for h in hulls])
    orphan = D.max(axis=0) < -1e-9
    for v in V[orphan]:
        # a vertex of a dropped sliver cell: the piece that takes it with the least excess
        tries = [(cut.score(_hull(np.vstack([P, v])))[1], k) for k, P in enumerate(pts)]
        k = min(tries)[1]
        pts[k] = np.vstack([pts[k], v]); hulls[k] = _hull(pts[k])
    if orphan.any():
        log(f"  {name}: {int(orphan.sum())} vertices outside every piece joined the piece they widen least")
    out = []
    for P, h in zip(pts, hulls):
        # facet normals thinned to THIN apart (largest facets first), each plane at the support of
        # the piece's points: an outer approximation without clusters of near-coincident vertices
        tri = h.points[h.simplices]
        area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        kept = []
        for i in np.argsort(-area, kind="stable"):
            nrm = h.equations[i, :3]
            if all(nrm @ m < np.cos(THIN) for m in kept):
                kept.append(nrm)
        Nk = np.array(kept)
        eq = np.c_[Nk, -(P @ Nk.T).max(axis=0)]
        inner = h.points[h.vertices].mean(axis=0)
        for k in range(12):
            hs = eq.copy(); hs[:, 3] -= OUT * 2 ** k           # every plane moved out by OUT 2^k
            try:
                Q = _sparse(np.round(HalfspaceIntersection(hs, inner).intersections, 6), MIN_SEP)
                g = ConvexHull(Q)
            except Exception:
                continue
            if depth(g, P).min() >= 1e-6:
                break
        else:
            raise SystemExit(f"{name}: a piece cannot be rounded")
        out.append(Q[g.vertices])
    return out


def _sparse(Q, r):
    """Q without vertices closer than r to an earlier kept one (lexicographic order): the hull shrinks
    by at most r, which the outward offset covers (checked)."""
    Q = Q[np.lexsort(Q.T[::-1])]
    tree = cKDTree(Q)
    keep = np.ones(len(Q), bool)
    for i in range(len(Q)):
        if keep[i]:
            for j in tree.query_ball_point(Q[i], r):
                if j > i:
                    keep[j] = False
    return Q[keep]


def test_vertices(mesh, pieces, cap=1500):
    """Test data: the deduplicated mesh vertices (6 decimals) — all of them if <= cap, else the hull
    vertices and those within 1 mm of the pieces' boundary, topped up / cut by depth inside."""
    V = np.unique(np.round(mesh.vertices, 6), axis=0)
    if len(V) <= cap:
        return V, len(V)
    hs = [ConvexHull(Q) for Q in pieces]
    dep = np.max([-(V @ h.equations[:, :3].T + h.equations[:, 3]).max(axis=1) for h in hs], axis=0)
    must = np.zeros(len(V), bool)
    must[ConvexHull(V).vertices] = True
    must |= dep <= 0.001
    order = np.lexsort((dep, ~must))
    return V[np.sort(order[:cap])], int(must.sum())


def check_inside(pieces, V, tol=1e-6):
    """Largest distance outside the union of the pieces over V (0 if all inside, by facet planes: a
    lower bound of the distance, exact for the containment test at tol)."""
    worst = np.full(len(V), np.inf)
    for Q in pieces:
        h = ConvexHull(Q)
        worst = np.minimum(worst, (V @ h.equations[:, :3].T + h.equations[:, 3]).max(axis=1))
    return float(max(worst.max(), 0.0))


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    rev = PINNED
    if "--rev" in sys.argv:
        rev = sys.argv[sys.argv.index("--rev") + 1]
        args = [a for a in args if a != rev]
    if len(args) != 1:
        sys.exit(__doc__)
    repo = args[0]
    commit = subprocess.run(["git", "-C", repo, "rev-parse", rev + "^{commit}"], capture_output=True,
                            check=True, text=True).stdout.strip()
    L = []

    def log(s):
        print(s, flush=True)
        L.append(s)

    m, meshes = load(repo, commit)
    S = setup(m, meshes)
    p = S["params"]
    log(f"Menagerie robotiq_2f85 at {commit}; +x finger = Menagerie's '{S['prefix'][:-1]}' finger; "
        f"G = model frame turned by {np.degrees(np.arctan2(S['Rg'][1, 0], S['Rg'][0, 0])):.1f} deg about z")
    lk, par, blocked, worst, pad_c, extras = kinematics(S, L)
    log(f"closed-form linkage vs MuJoCo FK (loop closed, residual <= {worst['closure']:.1e} m): "
        f"max deviation {worst['pose']:.1e} (m / rad)")
    # residuals vs our table (robotiq_2f85.json, derived from the ROS description and aligned to Menagerie)
    res = []
    log("| gap mm | table pad z | Menagerie pad z (this model) | residual mm |")
    log("|---|---|---|---|")
    fine = [lk.parallel(t) for t in np.linspace(S["ranges"]["driver"][0], S["ranges"]["driver"][1], 801)]
    fgap, fpz, ftip = [], [], []
    for q in fine:
        e = extras(lk.poses(q))
        fgap.append(e["gap"]); fpz.append(e["pad_center"][1]); ftip.append(e["tip_z"])
    fgap, fpz, ftip = map(np.array, (fgap, fpz, ftip))
    for g, z in TABLE:
        zz = float(np.interp(g, fgap[::-1], fpz[::-1]))
        res.append({"gap": g, "table_pad_z": z, "pad_z": r6(zz), "residual_mm": round((zz - z) * 1e3, 3)})
        log(f"| {g*1e3:.1f} | {z*1e3:.1f} | {zz*1e3:.2f} | {(zz-z)*1e3:+.2f} |")
    tip_open = float(ftip[0]); tip_closed = float(ftip.max())
    log(f"open (driver 0): gap {fgap[0]*1e3:.2f} mm, pad centre z {fpz[0]*1e3:.2f} (table 141.6, "
        f"{(fpz[0]-0.1416)*1e3:+.2f}), tip z {tip_open*1e3:.2f} (table 160.3, {(tip_open-TIP_OPEN)*1e3:+.2f})")
    log(f"closed: pads touch (gap 0) at driver {float(np.interp(0.0, fgap[::-1], np.linspace(0, 0.8, 801)[::-1])):.4f} rad, "
        f"pad centre z {float(np.interp(0.0, fgap[::-1], fpz[::-1]))*1e3:.2f} (table 154.7); deepest tip z over the stroke "
        f"{tip_closed*1e3:.2f} (table 173.5, {(tip_closed-TIP_CLOSED)*1e3:+.2f}); at driver 0.8: gap {fgap[-1]*1e3:.2f} mm, "
        f"pad z {fpz[-1]*1e3:.2f}, tip z {ftip[-1]*1e3:.2f}")
    log(f"parallel mode: follower tilt (pad angle) {min(s['links']['pad'][2] for s in par):.4f} .. "
        f"{max(s['links']['pad'][2] for s in par):.4f} rad")
    # mirror symmetry (the -x finger is the +x one turned by pi about z in Menagerie; = mirror x -> -x
    # where the links are symmetric in y)
    sym = {}
    for n in LINKS:
        t = S["link_mesh"][n][0]
        Vm = t.vertices * np.array([1, -1, 1])
        sym[n] = float(trimesh.proximity.closest_point(t, Vm)[1].max())
    log("y-mirror asymmetry of the link meshes (mm): " + ", ".join(f"{n} {v*1e3:.3f}" for n, v in sym.items()))

    # pieces
    links_out, verts_out = [], []
    log("| link | meshes | pieces | piece vertices | test vertices | excess mm (holes filled) | worst point (link frame, mm) | excess mm (raw mesh) | filled holes |")
    log("|---|---|---|---|---|---|---|---|---|")
    rows = []
    for n in LINKS:
        t, parts = S["link_mesh"][n]
        surf, cut, pts, hulls = decompose(n, t, log)
        pieces = finalize(n, t, cut, pts, hulls, log)
        ph = [ConvexHull(Q) for Q in pieces]
        e, at = measure(surf, ph)
        raw = Surface(t, 0.0)
        e_raw, _ = measure(raw, ph)
        V, must = test_vertices(t, pieces)
        out = check_inside(pieces, V)
        out_all = check_inside(pieces, np.unique(np.round(t.vertices, 12), axis=0))
        if out > 1e-6 or out_all > 1e-6:
            raise SystemExit(f"{n}: a mesh vertex lies {max(out, out_all)*1e3:.4f} mm outside the pieces")
        rows.append(f"| {n} | {'+'.join(S['geoms'][n]['visual'])} | {len(pieces)} | {sum(len(Q) for Q in pieces)} | "
                    f"{len(V)} | {e*1e3:.2f} | ({at[0]*1e3:.1f}, {at[1]*1e3:.1f}, {at[2]*1e3:.1f}) | {e_raw*1e3:.2f} | "
                    f"{surf.fill_parts} ({surf.fill_volume*1e9:.0f} mm^3) |")
        log(rows[-1])
        links_out.append({
            "name": n, "alias": ALIASES[n],
            "meshes": S["geoms"][n]["visual"], "collision_geoms": S["geoms"][n]["collision"],
            "mesh_vertices": int(len(np.unique(np.round(t.vertices, 12), axis=0))),
            "pieces": [r6(Q) for Q in pieces],
            "excess_mm": round(e * 1e3, 3), "excess_at": r6(at),
            "raw_excess_mm": round(e_raw * 1e3, 3),
            "filled_holes": {"count": surf.fill_parts, "volume_mm3": round(surf.fill_volume * 1e9, 1)},
            "y_mirror_asymmetry_mm": round(sym[n] * 1e3, 3)})
        verts_out.append({"name": n, "vertices": r6(V)})
    log("\n".join(["", "summary:"] + rows))

    lin = {
        "coordinates": "q = (driver, coupler, spring_link, follower): MuJoCo joint angles (rad) of right_driver_joint, "
                       "right_coupler_joint, right_spring_link_joint, right_follower_joint. Two are independent; the natural "
                       "pair is (driver, spring_link) (both pivots on the base); coupler and follower follow from the loop.",
        "axes": "every joint axis is G's -y: a joint angle theta turns its link by phi = -theta about +y; "
                "rot(phi) (x, z) = (x cos phi + z sin phi, -x sin phi + z cos phi)",
        "base": {"driver_pivot": r6(p["A"]), "spring_link_pivot": r6(p["B"])},
        "driver": {"frame_origin": "driver pivot A", "coupler_joint": r6(p["Cd"]), "length": r6(np.linalg.norm(p["Cd"]))},
        "coupler": {"frame_origin": "coupler joint C", "follower_point": r6(p["Dc"]), "length": r6(lk.lc)},
        "spring_link": {"frame_origin": "spring_link pivot B", "follower_joint": r6(p["Es"]), "length": r6(lk.ls)},
        "follower": {"frame_origin": "D, the point the coupler holds (MuJoCo `connect` anchor 0 0 0)",
                     "follower_joint": r6(p["Ef"]), "length": r6(lk.lf)},
        "pad": {"frame_in_follower": r6(p["Pf"]), "angle": "the follower's",
                "contact_face_x": r6(pad_c[0]), "contact_face_center": r6([pad_c[0], 0.0, pad_c[1]]),
                "contact_face_note": "pad frame; the +x finger's pad faces -x; gap = 2 x (pad face x in G)"},
        "ground_length": r6(np.linalg.norm(np.subtract(p["A"], p["B"]))),
        "parallel_crank_length": r6(lk.lk),
        "ranges": {k: r6(v) for k, v in S["ranges"].items()},
        "springs": S["springs"],
        "equations": [
            "C = A + rot(-driver) Cd                      (coupler joint, G)",
            "E = B + rot(-spring_link) Es                 (follower joint, G)",
            "D: |D - C| = |Dc| and |D - E| = |Ef|, the branch with sign(cross(E - C, D - C)) = %+d  (loop closure)" % lk.side_D,
            "coupler angle:  phi_c = ang(D - C) - ang(Dc),  coupler = -phi_c - driver     (ang(v) = atan2(-v.z, v.x))",
            "follower angle: phi_f = ang(D - E) - ang(-Ef), follower = -phi_f - spring_link",
            "poses [x, z, phi] in G: driver [A, -driver]; coupler [C, phi_c]; spring_link [B, -spring_link]; "
            "follower [D, phi_f]; pad [D + rot(phi_f) Pf, phi_f]",
            "parallel (spring-held) mode: coupler = 0 (its upper limit: MuJoCo's spring on spring_link, stiffness 0.05 "
            "towards 2.62 rad, keeps it there until the proximal link is stopped): D = A + rot(-driver)(Cd + Dc); "
            "E: |E - B| = |Es|, |E - D| = |Ef|, the branch with sign(cross(B - D, E - D)) = %+d; spring_link = -(ang(E - B) - ang(Es))" % lk.side_E,
            "blocked (adaptive) mode: spring_link fixed where the proximal link was stopped, driver turns on: "
            "coupler < 0 leaves its limit and the follower curls (pad turns towards -x, tip towards the palm)"],
    }
    fingers = {
        "generator": "tools/geometry/derive_fingers.py",
        "source": {"repo": "https://github.com/google-deepmind/mujoco_menagerie", "commit": commit,
                   "files": ["robotiq_2f85/2f85.xml"] + [f"robotiq_2f85/assets/{k}.stl" for k in sorted(meshes)],
                   "license": "BSD-2-Clause (robotiq_2f85/LICENSE, Copyright (c) 2013, ROS-Industrial)"},
        "frame": "G = UR flange/tool0: origin on the flange face (the underside of Menagerie's base_mount), +z approach, "
                 "x closing (pads at +-x), y finger width. Data for the +x finger (Menagerie's 'right' finger); the -x finger "
                 "is its mirror x -> -x (Menagerie turns it by pi about z; the links are y-symmetric, see y_mirror_asymmetry_mm).",
        "link_frames": "each link frame has its Menagerie body's origin and G's axes at q = 0; a pose [x, z, phi] is the "
                       "translation (x, 0, z) and the rotation phi about G's +y (finger.rs convention). Pieces and vertices "
                       "are in the link frames.",
        "units": "m, rad",
        "linkage": lin,
        "samples": {"parallel": par, "blocked": blocked,
                    "note": "from MuJoCo's forward kinematics with the connect equality solved (Gauss-Newton, residual "
                            "<= %.0e m); the closed form above reproduces them within %.0e. tip_z = deepest z of the "
                            "follower and pad meshes; pad_center = pad contact face centre (x, z) in G; gap = 2 pad_face_x."
                            % (max(worst["closure"], 1e-15), max(worst["pose"], 1e-15))},
        "table_residuals": {"pad_center": res, "tip_open": {"table": TIP_OPEN, "model": r6(tip_open)},
                            "tip_closed_max": {"table": TIP_CLOSED, "model": r6(tip_closed)}},
        "pieces_method": "convex polytopes (vertex lists) per link frame; every visual-mesh vertex lies in their union "
                         "(>= 1 um deep before rounding); excess = largest distance from the union's boundary (sampled every "
                         "%.1f mm; points outside the link only) to the link's surface, with through-holes of radius <= %.1f mm "
                         "(pin bores, screw holes) counted as solid; raw_excess_mm without that fill" % (FINAL_STEP * 1e3, FILL_R * 1e3),
        "links": links_out,
    }
    vertices = {"generator": "tools/geometry/derive_fingers.py", "source": fingers["source"],
                "frame": "link frames of robotiq_2f85_fingers.json", "links": verts_out}
    dump(os.path.join(DATA, "robotiq_2f85_fingers.json"), fingers)
    dump(os.path.join(DATA, "robotiq_2f85_finger_vertices.json"), vertices)
    print("wrote crates/robot/data/robotiq_2f85_fingers.json, crates/robot/data/robotiq_2f85_finger_vertices.json")


if __name__ == "__main__":
    main()
