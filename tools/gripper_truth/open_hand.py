#!/usr/bin/env python3
"""Independent open-hand test: is the fully open Robotiq 2F-85 (MuJoCo Menagerie model, its own meshes) inside
the part at a plan's grasps? Checked with MuJoCo's collision engine, not with pregrasp's models.

    pip install mujoco numpy trimesh
    python3 tools/gripper_truth/open_hand.py plans --menagerie <menagerie> plan1.json [...] [--plan-index 0 1]
    python3 tools/gripper_truth/open_hand.py sweep --menagerie <menagerie> --pregrasp <binary> \
        [--family frame ladder ...] [--per-family 5] [--first-seed 1] [--hard]
    python3 tools/gripper_truth/open_hand.py selftest --menagerie <menagerie>

For every plan: four states of an open hand (the support pinch G_s at the end of sup1, part at P_init; the power
grasps at the end of mas1 and of sup2, part at P_obj; the start of sup2's retreat, the opened pinch hand at P_obj),
each also with the flange moved back 0-20 mm (0.5 mm steps) along the flange z (the approach / retreat line). The
flange pose is the UR forward kinematics of the segment's joints (pregrasp.sim.geometry.dh_fk). The gripper is Menagerie's
2F-85 at its open pose (finger joints settled under the unmodified actuator at ctrl 0); the part is replay_part's
convex decomposition of the plan's mesh. Depth = the deepest penetration of any gripper geom into any part piece
(`mujoco.mj_geomDistance`, negative distance), cross-checked by the depth of the geom's vertices inside the part mesh
(trimesh). Rule (docs/plan-format.md, rule 2): at most 0.5 mm inside.

`plans` writes crates/physics/data/replay_truth/open_hand_2f85_plans.{json,csv}; `sweep` generates parts
(`pregrasp example generate`), plans each with its hand-placed grasps and with `[grasps] mode = "auto"`, and writes
crates/physics/data/replay_truth/open_hand_2f85.{json,csv}. README: tools/gripper_truth/README.md, section
"Open-hand test".
"""
import argparse
import datetime
import json
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np
import scipy
import trimesh
from scipy.spatial import ConvexHull

sys.path.insert(0, str(Path(__file__).resolve().parent))
from plan_replay import DEFAULT_PREGRASP, OUT_DIR, REPO_ROOT  # noqa: E402
from pregrasp_sim.geometry import DH, dh_fk  # noqa: E402
from plan_sweep import EXIT_NO_PLAN, EXIT_PLANNED, git_commit, plan_scene, scene_mesh, sha256  # noqa: E402
from replay import resolve_mesh  # noqa: E402
from replay_part import decompose_coacd, decompose_extrusion  # noqa: E402
from source import MODEL_DIR, MODEL_XML, load_source  # noqa: E402
from tables import csv_text, dump_json, write_atomic  # noqa: E402
from transforms import inv, pose_T  # noqa: E402
from transforms import quat_of_mat as quat  # noqa: E402

SCRIPT = "tools/gripper_truth/open_hand.py"
THRESHOLD = 0.0005  # m: an open-hand link may be at most this deep inside the part
APPROACH = 0.020  # m: the last straight approach / first straight retreat checked
STEP = 0.0005  # m between the sampled offsets
EDGE_STEP = 0.0005  # m between the points sampled on the part's edges (real-mesh depth)
DISTMAX = 0.02  # m: mj_geomDistance looks no farther (a clearer geom reads depth -20 mm)
SETTLE_T = 1.0  # s: the open fingers settle under the actuator's ctrl 0 (gravity off)
TOUCH = 1e-4  # m: a link this close counts as touching (links_touching)
VERTEX_CHECK_BELOW = -1e-4  # m: geoms this deep by mj_geomDistance also get the vertex depth
SIX = ("frame", "ladder", "u_frame", "panel", "stool", "h_frame")
# the states checked: (row name, segment whose joints place the flange, its point (-1 last, 0 first), arm role,
# which grasp, part pose)
STATES = (("sup1_support", "sup1", -1, "supportive", "support", "initial"),
          ("mas1_power", "mas1", -1, "master", "power", "goal"),
          ("sup2_power", "sup2", -1, "supportive", "power", "goal"),
          ("sup2_retreat_start", "sup2", 0, "supportive", "support", "goal"))


def Tz(s):
    T = np.eye(4)
    T[2, 3] = s
    return T


class OpenHand:
    """The Menagerie 2F-85 fixed at its own world frame (= the flange frame G, README "Frame G"), fingers open, and
    a part as a mocap body of convex mesh pieces placed in G."""

    def __init__(self, src):
        self.xml = str(Path(src) / MODEL_XML)
        sp = mujoco.MjSpec.from_file(self.xml)
        sp.option.gravity = [0.0, 0.0, 0.0]
        m = sp.compile()
        d = mujoco.MjData(m)
        d.ctrl[:] = 0.0  # Menagerie's open command
        for _ in range(int(round(SETTLE_T / m.opt.timestep))):
            mujoco.mj_step(m, d)
        self.qpos_open = d.qpos.copy()
        self.open_joints = {mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_JOINT, j): float(d.qpos[m.jnt_qposadr[j]])
                            for j in range(m.njnt)}
        self.open_qvel_max = float(np.abs(d.qvel).max())

    def model(self, pieces):
        """(model, data, gripper geoms [(id, name, kind)], part geom ids) with the part's pieces (object frame)."""
        sp = mujoco.MjSpec.from_file(self.xml)
        sp.option.gravity = [0.0, 0.0, 0.0]
        part = sp.worldbody.add_body(name="part", mocap=True)
        for i, P in enumerate(pieces):
            hull = trimesh.Trimesh(P).convex_hull
            sp.add_mesh(name=f"piece{i}", uservert=list(np.asarray(hull.vertices).ravel()),
                        userface=list(np.asarray(hull.faces).ravel()))
            part.add_geom(name=f"part{i}", type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"piece{i}", contype=0,
                          conaffinity=0, mass=0)
        m = sp.compile()
        d = mujoco.MjData(m)
        d.qpos[:] = self.qpos_open
        pid = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, "part")
        part_geoms = [g for g in range(m.ngeom) if m.geom_bodyid[g] == pid]
        grip = []
        for g in range(m.ngeom):
            if m.geom_bodyid[g] == pid:
                continue
            body = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, m.geom_bodyid[g])
            name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g)
            if m.geom_contype[g] or m.geom_conaffinity[g]:
                grip.append((g, name or body, "collision"))
            elif body.endswith("_pad") or body.endswith("_silicone_pad"):
                # the pads' own meshes (visual only in Menagerie, which collides the pads as two boxes)
                grip.append((g, f"{body}_mesh", "pad_mesh"))
        return m, d, grip, part_geoms


class PartCheck:
    """One part: its pieces in MuJoCo and its mesh for the vertex depth."""

    def __init__(self, hand, mesh, pieces):
        self.mesh = mesh
        self.tris = np.asarray(mesh.triangles, float)
        self.halfspaces = []
        for P in pieces:
            h = ConvexHull(np.asarray(P, float))
            self.halfspaces.append((h.equations[:, :3], h.equations[:, 3]))
        self.m, self.d, self.grip, self.part_geoms = hand.model(pieces)
        self.pid = mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_BODY, "part")
        self.mocap = self.m.body_mocapid[self.pid]
        m = self.m
        self.verts, self.faces = {}, {}
        # the part's vertices and points along its edges, every EDGE_STEP (object frame)
        self.edge_pts = edge_points(np.asarray(mesh.vertices, float), np.asarray(mesh.faces))
        self.link_pts = {}
        for g, _, _ in self.grip:
            if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH:
                k = m.geom_dataid[g]
                self.verts[g] = m.mesh_vert[m.mesh_vertadr[k]:m.mesh_vertadr[k] + m.mesh_vertnum[k]].astype(float)
                self.faces[g] = m.mesh_face[m.mesh_faceadr[k]:m.mesh_faceadr[k] + m.mesh_facenum[k]]
                self.link_pts[g] = edge_points(self.verts[g], self.faces[g])
            elif m.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX:
                h = m.geom_size[g]
                c = np.array([[sx, sy, sz] for sx in (-1, 0, 1) for sy in (-1, 0, 1) for sz in (-1, 0, 1)], float)
                self.verts[g] = c * h

    def vertex_depth(self, pts):
        """Largest distance (m) of a point of `pts` (object frame) inside the part: inside one of its convex pieces,
        then its exact distance to the mesh's nearest triangle; 0 when none is inside."""
        inside = np.zeros(len(pts), bool)
        for A, b in self.halfspaces:
            inside |= (pts @ A.T + b <= 1e-12).all(axis=1)
        if not inside.any():
            return 0.0
        return float(point_triangle_distance(pts[inside], self.tris).min(axis=1).max())

    def mesh_depth(self, g, T_part_in_G):
        """Depth (m) of the real mesh of gripper geom g (not its hull) in the part, as docs/plan-format.md defines
        it (rule 2): the larger of the deepest point of the link's triangle edges (vertices and points every
        EDGE_STEP) inside the part and the deepest point of the part's triangle edges inside the link mesh
        (generalised winding number > 1/2); a point's depth is its distance to the other mesh's nearest triangle."""
        d = self.d
        R, t = d.geom_xmat[g].reshape(3, 3), d.geom_xpos[g]
        Tinv = inv(T_part_in_G)
        best = self.vertex_depth((self.link_pts[g] @ R.T + t) @ Tinv[:3, :3].T + Tinv[:3, 3])
        V = self.verts[g] @ R.T + t  # G
        tris = V[self.faces[g]]
        P = self.edge_pts @ T_part_in_G[:3, :3].T + T_part_in_G[:3, 3]
        lo, hi = V.min(axis=0), V.max(axis=0)
        P = P[((P >= lo) & (P <= hi)).all(axis=1)]
        if len(P):
            inside = np.concatenate([winding_number(P[i:i + 64], tris) > 0.5 for i in range(0, len(P), 64)])
            if inside.any():
                Q = P[inside]
                dist = np.concatenate([point_triangle_distance(Q[i:i + 64], tris).min(axis=1)
                                       for i in range(0, len(Q), 64)])
                best = max(best, float(dist.max()))
        return best

    def depths(self, T_part_in_G):
        """{geom name: (depth by mj_geomDistance, depth of its vertices inside the mesh, depth of the real mesh)}
        (m, > 0 = inside). The real-mesh depth is computed for mesh geoms deeper than THRESHOLD by MuJoCo (their
        hulls); otherwise it is the larger of the first two (a box is its own mesh)."""
        m, d = self.m, self.d
        d.mocap_pos[self.mocap] = T_part_in_G[:3, 3]
        d.mocap_quat[self.mocap] = quat(T_part_in_G[:3, :3])
        mujoco.mj_kinematics(m, d)
        out = {}
        Tinv = inv(T_part_in_G)
        for g, name, _ in self.grip:
            best = -DISTMAX
            for p in self.part_geoms:
                if np.linalg.norm(d.geom_xpos[g] - d.geom_xpos[p]) > m.geom_rbound[g] + m.geom_rbound[p] + DISTMAX:
                    continue
                best = max(best, -mujoco.mj_geomDistance(m, d, g, p, DISTMAX, None))
            vdepth = None
            if best > -VERTEX_CHECK_BELOW:
                pts = self.verts[g] @ d.geom_xmat[g].reshape(3, 3).T + d.geom_xpos[g]
                pts = pts @ Tinv[:3, :3].T + Tinv[:3, 3]
                vdepth = self.vertex_depth(pts)
            real = best if vdepth is None else max(best, vdepth)
            if g in self.faces and best > THRESHOLD:
                real = self.mesh_depth(g, T_part_in_G)
            out[name] = (best, vdepth, real)
        return out


def point_triangle_distance(P, T):
    """(n, m) distances from points P (n, 3) to triangles T (m, 3, 3): closest point on a triangle, Ericson's
    Real-Time Collision Detection 5.1.5, vectorised."""
    p = P[:, None, :]
    a, b, c = T[None, :, 0], T[None, :, 1], T[None, :, 2]
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = (ab * ap).sum(-1), (ac * ap).sum(-1)
    bp = p - b
    d3, d4 = (ab * bp).sum(-1), (ac * bp).sum(-1)
    cp = p - c
    d5, d6 = (ab * cp).sum(-1), (ac * cp).sum(-1)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    den = np.where(np.abs(va + vb + vc) > 1e-30, va + vb + vc, 1e-30)
    v, w = vb / den, vc / den
    q = a + ab * v[..., None] + ac * w[..., None]  # inside the face
    safe = lambda x: np.where(x > 1e-30, x, 1e-30)
    # edges and vertices: later conditions override earlier ones (the regions are disjoint up to ties)
    e_bc = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)
    q = np.where(e_bc[..., None], b + (c - b) * ((d4 - d3) / safe((d4 - d3) + (d5 - d6)))[..., None], q)
    e_ac = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
    q = np.where(e_ac[..., None], a + ac * (d2 / safe(d2 - d6))[..., None], q)
    e_ab = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
    q = np.where(e_ab[..., None], a + ab * (d1 / safe(d1 - d3))[..., None], q)
    q = np.where(((d6 >= 0) & (d5 <= d6))[..., None], c, q)
    q = np.where(((d3 >= 0) & (d4 <= d3))[..., None], b, q)
    q = np.where(((d1 <= 0) & (d2 <= 0))[..., None], a, q)
    return np.linalg.norm(p - q, axis=-1)


def edge_points(V, F):
    """The vertices V and points every EDGE_STEP along the unique edges of the triangles F."""
    E = np.unique(np.sort(np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)
    out = [V]
    L = np.linalg.norm(V[E[:, 1]] - V[E[:, 0]], axis=1)
    for (i, j), n in zip(E, np.ceil(L / EDGE_STEP).astype(int)):
        if n > 1:
            out.append(V[i] + (np.arange(1, n)[:, None] / n) * (V[j] - V[i]))
    return np.vstack(out)


def winding_number(P, T):
    """(n,) generalised winding numbers of points P (n, 3) w.r.t. the triangles T (m, 3, 3) (Jacobson et al. 2013,
    Van Oosterom-Strackee solid angles): ~1 inside a closed mesh, ~0 outside, whichever way it is wound overall."""
    a, b, c = (T[None, :, k] - P[:, None] for k in range(3))
    la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (a, b, c))
    num = (a * np.cross(b, c)).sum(-1)
    den = la * lb * lc + (a * b).sum(-1) * lc + (b * c).sum(-1) * la + (c * a).sum(-1) * lb
    return np.abs(np.arctan2(num, den).sum(-1) / (2 * np.pi))


def deepest(per_offset, real=False):
    """(depth, link, offset, mj depth, vertex depth) of the deepest geom over [(offset, depths)]: by MuJoCo's hulls
    and the vertices, or (`real`) by the real meshes."""
    best = (-np.inf, None, None, None, None)
    for off, dep in per_offset:
        for name, (a, v, r) in dep.items():
            x = r if real else a if v is None else max(a, v)
            if x > best[0] + 1e-12:
                best = (x, name, off, a, v)
    if best[0] <= -DISTMAX + 1e-12:  # nothing within DISTMAX
        best = (-DISTMAX, None, None, -DISTMAX, None)
    return best


def load_part(plan_path, doc, mesh_root):
    o = doc["object"]
    path = None
    for rel, base in ((o.get("mesh_from_plan"), Path(plan_path).resolve().parent), (o["mesh"], Path.cwd())):
        if rel and (base / rel).is_file():
            path = base / rel
            break
    if path is None:
        path = resolve_mesh(plan_path, o["mesh"], mesh_root)
    mesh = trimesh.load(str(path), force="mesh")
    mesh.apply_scale(o.get("scale", 1.0))
    try:
        pieces, info = decompose_extrusion(mesh)
    except ValueError:
        pieces, info = decompose_coacd(mesh)
    return mesh, pieces, info


def check_plan(pc, doc, plan):
    """Rows (one per state of STATES) of one plan."""
    robots = {r["name"]: r for r in doc["robots"]}
    segs = {s["name"]: s for s in plan["segments"]}
    poses = {"initial": pose_T(doc["object"]["initial_pose"]), "goal": pose_T(plan["object_goal_pose"])}
    offsets = np.arange(0, int(round(APPROACH / STEP)) + 1) * STEP
    rows = []
    for state, seg, k, role, grasp, part_at in STATES:
        arm = plan[role]
        r = robots[arm]
        row = {"state": state, "segment": seg, "arm": arm, "grasp": grasp, "part_pose": part_at}
        if r.get("model") not in DH or r.get("gripper", "robotiq_2f85") != "robotiq_2f85":
            rows.append({**row, "verdict": "skipped", "reason": f"model {r.get('model')} gripper {r.get('gripper')}"})
            continue
        F = pose_T(r["base"]) @ dh_fk(r["model"], segs[seg]["points"][k]["q"])
        Tp = poses[part_at]
        # the grasp as the format defines it: flange = object · grasp · point⁻¹
        if grasp == "support":
            Tg, pt = pose_T(doc["grasps"]["support"]), pose_T(r["precision_point"])
        else:
            Tg, pt = pose_T(doc["grasps"]["power"][[x["name"] for x in doc["robots"]].index(arm)]), pose_T(r["power_point"])
        Fdef = Tp @ Tg @ inv(pt)
        # the plan's own straight line next to this state (approach: approach_from .. last; retreat: 0 .. retreat_to):
        # how far its points' flange origins (FK) lie from the sampled line (the flange moved back along its z)
        pts = segs[seg]["points"]
        line = pts[segs[seg].get("approach_from", 0):] if k == -1 else pts[:segs[seg].get("retreat_to", 0) + 1]
        dev, length = 0.0, 0.0
        for pq in line:
            o = (pose_T(r["base"]) @ dh_fk(r["model"], pq["q"]))[:3, 3] - F[:3, 3]
            along = -float(o @ F[:3, 2])
            length = max(length, along)
            dev = max(dev, float(np.linalg.norm(o + along * F[:3, 2])), max(0.0, -along))
        row.update({"line_points": len(line), "line_length_mm": length * 1e3, "line_deviation_mm": dev * 1e3})
        per = [(float(s), pc.depths(Tz(s) @ inv(F) @ Tp)) for s in offsets]
        depth, link, off, a, v = deepest(per)
        at0 = deepest(per[:1])
        real = deepest(per, real=True)
        mm = lambda x: None if x is None else x * 1e3
        rows.append({**row, "depth_mm": depth * 1e3, "link": link, "offset_mm": mm(off),
                     "depth_mujoco_mm": a * 1e3, "depth_vertex_mm": None if v is None else v * 1e3,
                     "depth_at_grasp_mm": at0[0] * 1e3, "link_at_grasp": at0[1],
                     "links_inside": sorted({n for _, dep in per for n, (x, y, _) in dep.items()
                                             if (x if y is None else max(x, y)) > THRESHOLD}),
                     "links_touching": sorted({n for _, dep in per for n, (x, y, _) in dep.items()
                                               if (x if y is None else max(x, y)) > -TOUCH}),
                     "depth_mesh_mm": real[0] * 1e3, "link_mesh": real[1], "offset_mesh_mm": mm(real[2]),
                     "verdict_mesh": "inside" if real[0] > THRESHOLD else "ok",
                     "flange_fk_vs_grasp_mm": float(np.linalg.norm(F[:3, 3] - Fdef[:3, 3]) * 1e3),
                     "states": len(offsets), "verdict": "inside" if depth > THRESHOLD else "ok"})
    return rows


def check_file(plan_path, indices, hand, mesh_root, log):
    """Rows of every plan of plan_path (or `indices`), each with its part and plan index."""
    doc = json.load(open(plan_path))
    if doc.get("status") != "planned":
        return doc, []
    mesh, pieces, info = load_part(plan_path, doc, mesh_root)
    pc = PartCheck(hand, mesh, pieces)
    rows = []
    for k in (indices if indices is not None else range(len(doc["plans"]))):
        if k >= len(doc["plans"]):
            continue
        t0 = time.time()
        for r in check_plan(pc, doc, doc["plans"][k]):
            rows.append({"plan": k, "candidate": doc["plans"][k]["candidate"], "pieces": info["pieces"], **r})
        worst = max((r for r in rows if r["plan"] == k and "depth_mm" in r), key=lambda r: r["depth_mm"], default=None)
        if worst:
            log(f"  plan {k}: deepest {worst['depth_mm']:.2f} mm ({worst['state']} {worst['link']} at "
                f"{worst['offset_mm']} mm back), {time.time() - t0:.1f} s")
    return doc, rows


def header(a, prov, hand):
    return {
        "generator": SCRIPT,
        "args": [Path(x).name if Path(x).is_absolute() else x for x in sys.argv[1:]],
        "date": datetime.date.today().isoformat(),
        "source": {"repo": "https://github.com/google-deepmind/mujoco_menagerie", "path": f"{MODEL_DIR}/{MODEL_XML}",
                   **prov},
        "mujoco_version": mujoco.__version__, "numpy_version": np.__version__, "trimesh_version": trimesh.__version__,
        "scipy_version": scipy.__version__, "units": "depths and offsets in mm",
        "open_pose": {"joints": hand.open_joints, "settle": f"{SETTLE_T} s at ctrl 0, gravity off",
                      "qvel_max_end": hand.open_qvel_max},
        "test": {"threshold_mm": THRESHOLD * 1e3, "approach_mm": APPROACH * 1e3, "step_mm": STEP * 1e3,
                 "states": [s[0] for s in STATES],
                 "depth": "max over gripper geoms (Menagerie collision geoms + the pads' visual meshes) of "
                          "max(-mj_geomDistance to any convex piece of the part (meshes as their convex hulls), "
                          "depth of the geom's vertices inside the part mesh); clear by more than 20 mm: -20, "
                          "link null",
                 "depth_mesh": "the same with each mesh geom deeper than the threshold by its hull measured again "
                               "on its real mesh: deepest point of either mesh's triangle edges (sampled every "
                               f"{EDGE_STEP * 1e3} mm) inside the other",
                 "description": "tools/gripper_truth/README.md, section 'Open-hand test'"},
    }


def run_plans(a):
    log = lambda s: print(s, flush=True)
    t0 = time.time()
    rows = []
    with tempfile.TemporaryDirectory(prefix="open_hand_") as tmp:
        src, prov = load_source(a.menagerie, a.rev, tmp)
        hand = OpenHand(src)
        for p in a.plans:
            log(p)
            doc, rr = check_file(p, a.plan_index, hand, a.mesh_root, log)
            rows += [{"file": Path(p).name, **r} for r in rr]
    write_table(Path(a.out), a.name, header(a, prov, hand), rows, t0, log)


def write_table(out, name, head, rows, t0, log):
    write_atomic(out / f"{name}.json", dump_json(head, rows))
    write_atomic(out / f"{name}.csv", csv_text(rows))
    n_in = sum(1 for r in rows if r.get("verdict") == "inside")
    log(f"wrote {out / name}.{{json,csv}}: {len(rows)} rows, {n_in} inside, {time.time() - t0:.1f} s")


def auto_scene(text):
    """The scene text with its `[grasps]` table replaced by `mode = "auto"` (as crates/planner/tests/auto_vs_hand.rs)."""
    start = text.index("[grasps]")
    k = text.find("\n[", start + 1)
    end = len(text) if k < 0 else k
    return f'{text[:start]}[grasps]\nmode = "auto"\n{text[end:]}'


def run_sweep(a):
    log = lambda s: print(s, flush=True)
    t0 = time.time()
    rows, seeds = [], {}
    families = a.family or [None]
    with tempfile.TemporaryDirectory(prefix="open_hand_sweep_") as tmp:
        work = Path(a.workdir) if a.workdir else Path(tmp)
        parts = work / "parts"
        gen_cmds = []
        for fam in families:
            cmd = [str(a.pregrasp), "example", "generate", str(parts), "--per-family", str(a.per_family),
                   "--first-seed", str(a.first_seed)] + (["--family", fam] if fam else []) + (["--hard"] if a.hard else [])
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                sys.exit(f"{' '.join(cmd[1:])}: exit {r.returncode}: {r.stderr.strip()}")
            gen_cmds.append(" ".join(["pregrasp"] + cmd[1:3] + ["DIR"] + cmd[4:]))
        names = sorted(p.stem for p in parts.glob("*.toml") if not p.stem.endswith(".auto"))
        wanted = set(a.family) if a.family else None
        src, prov = load_source(a.menagerie, a.rev, tmp)
        hand = OpenHand(src)
        plans_dir = work / "plans"
        plans_dir.mkdir(parents=True, exist_ok=True)
        for stem in names:
            mm = re.fullmatch(r"(.+)_(\d+)", stem)
            family, seed = (mm.group(1), int(mm.group(2))) if mm else (stem, None)
            if wanted and family not in wanted:
                continue
            seeds.setdefault(family, []).append(seed)
            scene = parts / f"{stem}.toml"
            auto = parts / f"{stem}.auto.toml"
            auto.write_text(auto_scene(scene.read_text()))
            base = {"part": stem, "family": family, "seed": seed, "scene_sha256": sha256(scene),
                    "mesh_sha256": sha256(scene_mesh(scene))}
            for mode, sc in (("hand", scene), ("auto", auto)):
                out = plans_dir / f"{stem}.{mode}.plan.json"
                if a.reuse_plans and out.is_file():
                    doc = json.loads(out.read_text())
                    code, wall, err = (EXIT_PLANNED if doc.get("status") == "planned" else EXIT_NO_PLAN), 0.0, ""
                else:
                    out.unlink(missing_ok=True)
                    code, doc, wall, err = plan_scene(a.pregrasp, sc, out, a.max_plans)
                n = len(doc["plans"]) if doc and doc.get("status") == "planned" else 0
                log(f"{stem} {mode}: pregrasp plan exit {code}, {n} plan(s), {wall:.1f} s")
                part = {**base, "grasp_mode": mode, "planner_exit": code, "plans_emitted": n}
                if code != EXIT_PLANNED or n == 0:
                    reason = (doc or {}).get("reason") or (err.splitlines() or [None])[-1]
                    rows.append({**part, "plan": None, "state": None,
                                 "verdict": "no plan" if code == EXIT_NO_PLAN else "error", "reason": reason})
                    continue
                _, rr = check_file(out, None, hand, None, log)
                rows += [{**part, **r} for r in rr]
    rows.sort(key=lambda r: (r["family"], r["seed"] if r["seed"] is not None else -1, r["part"], r["grasp_mode"],
                             -1 if r["plan"] is None else r["plan"], [s[0] for s in STATES].index(r["state"])
                             if r["state"] else -1))
    head = header(a, prov, hand)
    plans = {(r["part"], r["grasp_mode"], r["plan"]) for r in rows if r["plan"] is not None}
    bad = {(r["part"], r["grasp_mode"], r["plan"]) for r in rows if r.get("verdict") == "inside"}
    head.update({"generator": SCRIPT,
                 "pregrasp": {**git_commit(), "binary_sha256": sha256(a.pregrasp), "binary_commit": a.pregrasp_commit,
                              "version": subprocess.run([str(a.pregrasp), "--version"], capture_output=True,
                                                        text=True).stdout.strip()},
                 "generate": gen_cmds, "seeds": {f: sorted(v) for f, v in seeds.items()},
                 "plan_command": f"pregrasp plan SCENE --quiet --max-plans {a.max_plans} --threads 1",
                 "auto_scene": "the scene's [grasps] table replaced by mode = \"auto\"",
                 "summary": {"parts": len({r['part'] for r in rows}), "plans_checked": len(plans),
                             "plans_with_open_hand_inside": len(bad),
                             "by_mode": {m: {"plans": sum(1 for p in plans if p[1] == m),
                                             "inside": sum(1 for p in bad if p[1] == m),
                                             "no_plan": sum(1 for r in rows if r["grasp_mode"] == m and r["plan"] is None)}
                                         for m in ("hand", "auto")}}})
    write_table(Path(a.out), a.name, head, rows, t0, log)
    log(json.dumps(head["summary"]))


def run_selftest(a):
    """Known cases: a bar pinched 3 mm too narrow for the open pads, and a slab 3 mm into the fingertips."""
    with tempfile.TemporaryDirectory(prefix="open_hand_") as tmp:
        src, _ = load_source(a.menagerie, a.rev, tmp)
        hand = OpenHand(src)
        probe = PartCheck(hand, trimesh.creation.box([0.01] * 3), [trimesh.creation.box([0.01] * 3).vertices])
        m, d = probe.m, probe.d
        mujoco.mj_kinematics(m, d)
        g = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, "right_pad1")
        # the pad box's inner face (towards -x of G) and the fingertip z
        R = d.geom_xmat[g].reshape(3, 3)
        corners = probe.verts[g] @ R.T + d.geom_xpos[g]
        face_x = corners[:, 0].min()
        tip_z = max(float((probe.verts[gg] @ d.geom_xmat[gg].reshape(3, 3).T + d.geom_xpos[gg])[:, 2].max())
                    for gg, _, _ in probe.grip)
        print(f"open pose: right pad box inner face x = {face_x * 1e3:.3f} mm, deepest gripper point z = "
              f"{tip_z * 1e3:.3f} mm; joints {hand.open_joints}")
        results = []
        for depth in (0.0, 0.0005, 0.003, 0.010):
            # bar along y, its +x face `depth` beyond the pad face, z over the pads only
            w = 2 * (face_x + depth)
            box = trimesh.creation.box([w, 0.3, 0.02])
            box.apply_translation([0, 0, 0.14])
            pieces, _ = decompose_extrusion(box)
            pc = PartCheck(hand, box, pieces)
            dep = pc.depths(np.eye(4))
            x = {n: tuple(None if y is None else round(y * 1e3, 3) for y in v) for n, v in dep.items()
                 if max(v[0], v[1] or 0) > 1e-5}
            print(f"bar {depth * 1e3:.1f} mm into each pad: {x}")
            results.append(("bar", depth, dep["right_pad1"][0], dep["left_pad1"][0]))
            # the same bar split in two pieces across the pad (y = 0.005): the union as two convex pieces
            half = [trimesh.creation.box([w, 0.15, 0.02]) for _ in range(2)]
            half[0].apply_translation([0, 0.005 - 0.075, 0.14])
            half[1].apply_translation([0, 0.005 + 0.075, 0.14])
            pc2 = PartCheck(hand, box, [h.vertices for h in half])
            dep2 = pc2.depths(np.eye(4))
            print(f"  same bar as 2 pieces split at y = 5 mm: right_pad1 {dep2['right_pad1'][0] * 1e3:.3f} mm")
        for depth in (0.003,):
            slab = trimesh.creation.box([0.2, 0.2, 0.02])
            slab.apply_translation([0, 0, tip_z - depth + 0.01])
            pieces, _ = decompose_extrusion(slab)
            pc = PartCheck(hand, slab, pieces)
            for s in (0.0, 0.001, 0.002, 0.003, 0.004):
                dep = pc.depths(Tz(s))
                name, v = max(dep.items(), key=lambda kv: kv[1][0] if kv[1][1] is None else max(kv[1][:2]))
                print(f"slab {depth * 1e3:.1f} mm into the fingertips, flange {s * 1e3:.1f} mm back: deepest {name} "
                      f"{v[0] * 1e3:.3f} mm (vertices {None if v[1] is None else round(v[1] * 1e3, 3)})")
        if a.plan:  # a real plan: mas1's grasp, the flange pushed towards the part along its z
            doc = json.load(open(a.plan))
            plan = doc["plans"][0]
            mesh, pieces, _ = load_part(a.plan, doc, None)
            pc = PartCheck(hand, mesh, pieces)
            r = {x["name"]: x for x in doc["robots"]}[plan["master"]]
            seg = [x for x in plan["segments"] if x["name"] == "mas1"][0]
            TG = inv(pose_T(r["base"]) @ dh_fk(r["model"], seg["points"][-1]["q"])) @ pose_T(plan["object_goal_pose"])
            for s in (0.0, 0.004, 0.005, 0.006, 0.008):
                name, v = max(pc.depths(Tz(-s) @ TG).items(), key=lambda kv: kv[1][0])
                print(f"{Path(a.plan).name} mas1, flange {s * 1e3:.0f} mm forward: {name} mujoco {v[0] * 1e3:.3f} "
                      f"vertices {None if v[1] is None else round(v[1] * 1e3, 3)} mesh {v[2] * 1e3:.3f} mm")
        for kind, want, r, l in results:
            if want > 0.0081:
                print(f"{kind} {want * 1e3:.1f} mm: right {r * 1e3:.3f} (the 8 mm pad box is then separated faster "
                      "along z: the least translation, not the bar's overlap)")
                continue
            ok = abs(r - want) < 5e-5 and abs(l - want) < 5e-5
            print(f"{kind} {want * 1e3:.1f} mm: right {r * 1e3:.3f} left {l * 1e3:.3f} {'OK' if ok else 'WRONG'}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    ps = sub.add_parser("plans", help="check plan files")
    pw = sub.add_parser("sweep", help="generate, plan (hand and auto grasps), check every plan")
    pt = sub.add_parser("selftest", help="known depths")
    for p in (ps, pw, pt):
        p.add_argument("--menagerie", required=True)
        p.add_argument("--rev", default="HEAD")
    for p in (ps, pw):
        p.add_argument("--out", default=str(OUT_DIR))
    pt.add_argument("--plan", default=None, help="also push this plan's mas1 flange 4-8 mm into the part")
    ps.add_argument("plans", nargs="+")
    ps.add_argument("--plan-index", type=int, nargs="*", default=None, help="default: every plan of the file")
    ps.add_argument("--mesh-root", default=None)
    ps.add_argument("--name", default="open_hand_2f85_plans")
    pw.add_argument("--pregrasp", default=str(DEFAULT_PREGRASP))
    pw.add_argument("--pregrasp-commit", default=None, help="the commit the binary was built from (recorded)")
    pw.add_argument("--family", nargs="*", default=None,
                    help=f"families to generate (default: all of `example generate`: {' '.join(SIX)}); any name is "
                         "passed to `pregrasp example generate --family`")
    pw.add_argument("--per-family", type=int, default=5)
    pw.add_argument("--first-seed", type=int, default=1)
    pw.add_argument("--hard", action="store_true", help="passed to `pregrasp example generate`")
    pw.add_argument("--max-plans", type=int, default=3, help="`pregrasp plan --max-plans` (its default 3)")
    pw.add_argument("--workdir", default=None, help="keep the parts and plans here (default: a temporary directory)")
    pw.add_argument("--reuse-plans", action="store_true", help="with --workdir: keep plan files already there")
    pw.add_argument("--name", default="open_hand_2f85")
    a = ap.parse_args()
    {"plans": run_plans, "sweep": run_sweep, "selftest": run_selftest}[a.cmd](a)


if __name__ == "__main__":
    main()
