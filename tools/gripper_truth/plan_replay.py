#!/usr/bin/env python3
"""Dynamic ground truth of a whole pregrasp plan: both arms' Robotiq 2F-85 grippers (MuJoCo Menagerie), each a
free body welded to a mocap body that follows the planned flange pose (FK of the arm's joints, linear in joint
space between the plan points), the part a free body on the table. All four segments on one time line
(sup1, close the pinch; rot; mas1, close the master's power grasp; the supportive gripper opens; sup2, close its
power grasp), then both grippers rise 50 mm together and hold 1 s.

    pip install mujoco numpy trimesh
    python3 tools/gripper_truth/plan_replay.py --menagerie <menagerie> plan1.json [plan2.json ...]

Every plan (plan 0 of each file unless --plan-index) is run once per power force (--power-force, default the
plan's physics.grip_force_recommended, and the 2F-85's maximum 235 N). Writes
crates/physics/data/replay_truth/plan_replay_2f85.{json,csv} (atomically, keys sorted, floats rounded).
Model and columns: tools/gripper_truth/README.md, section "Replay of the whole plan".
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
from replay import resolve_mesh  # noqa: E402
from replay_part import decompose_coacd, decompose_extrusion, mass_properties  # noqa: E402
from replay_scene import GRIPPER_BODIES, PAD_GEOMS, TAU_OPEN  # noqa: E402
from source import MODEL_DIR, MODEL_XML, load_source  # noqa: E402
from plan_verdict import THRESHOLDS, verdict  # noqa: E402
from tables import csv_text, dump_json, write_atomic  # noqa: E402
from transforms import T_of, inv, pose_T, rot_angle  # noqa: E402
from transforms import quat_of_mat as quat  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[2]
OUT_DIR = REPO_ROOT / "crates/physics/data/replay_truth"
SCRIPT = "tools/gripper_truth/plan_replay.py"
DEFAULT_PREGRASP = REPO_ROOT / "target/release/pregrasp"

# UR standard DH lengths (m), as crates/robot/src/model.rs (UrModel::dh); checked against `pregrasp kin fk`
DH = {"ur3e": (0.15185, -0.24355, -0.2132, 0.13105, 0.08535, 0.0921),
      "ur5e": (0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996),
      "ur10e": (0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655),
      "ur16e": (0.1807, -0.4784, -0.36, 0.17415, 0.11985, 0.11655),
      "ur5": (0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823)}
F_MAX = 235.0  # N, the 2F-85's largest grip force
# measured pad force ~ CAL_A * tau + CAL_B (the pinch calibration of replay.py, README "Replay of the rotation")
CAL_A, CAL_B = 9.2, 1.8
PAD_POINT = np.array([0.0, -0.0066, 0.01875])  # pad contact-face centre in the pad body (README "Points")
TIP_POINT = np.array([0.0, -0.0066, 0.0375])  # the far end of that face (the fingertip)
# phases (simulated seconds)
T_SETTLE = 0.3  # the part settles on the table, both grippers open
T_SPRING = 0.6  # a closing: tau 0, the spring links close the fingers gently
T_RAMP = 0.3  # tau ramps to its target
T_WINDOW = 0.3  # one force window (the pinch's tau is corrected after each, at most N_CORRECT)
N_CORRECT = 3
T_OPEN = 0.5  # the supportive gripper opens at the start of sup2 (arm held)
LIFT = 0.05  # m, both grippers raised together
T_LIFT = 1.0
T_HOLD = 1.0
SAMPLE_EVERY = 10
CAGED_MARGIN = 0.002  # m: pads closed this much past the bar width (plan grip_width) with no pad contact


def dh_fk(model, q):
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


def fk_check(pregrasp, model, q):
    """Largest difference (m, rad) between dh_fk and `pregrasp kin fk` at q."""
    out = subprocess.run([str(pregrasp), "kin", "fk", *[repr(float(v)) for v in q], "--model", model, "--json"],
                         capture_output=True, text=True, check=True)
    T = pose_T(json.loads(out.stdout))
    M = dh_fk(model, q)
    return float(np.linalg.norm(T[:3, 3] - M[:3, 3])), rot_angle(T[:3, :3], M[:3, :3])


class PlanScene:
    """Table, part (free body), two 2F-85 (prefixes `sup_`, `mas_`) on free bases welded to mocap flanges."""

    def __init__(self, gripper_xml, doc, plan, pieces, mp, mu_pad, mu_sup, dt, noslip):
        self.doc, self.plan = doc, plan
        sp = mujoco.MjSpec()
        sp.option.timestep = dt
        sp.option.noslip_iterations = noslip
        sp.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
        sp.option.impratio = 10.0
        sp.option.gravity = [0.0, 0.0, -9.81]
        for arm in ("sup", "mas"):
            tgt = sp.worldbody.add_body(name=f"{arm}_target", mocap=True)
            del tgt
        for arm in ("sup", "mas"):
            c = mujoco.MjSpec.from_file(str(gripper_xml))
            for b in GRIPPER_BODIES:
                c.body(b).gravcomp = 1.0
            c.body("base_mount").add_freejoint(name="free")
            for g in c.geoms:
                if g.name in PAD_GEOMS["pos"] + PAD_GEOMS["neg"]:
                    g.friction = [mu_pad, 0.0, 0.0001]
                    g.condim = 3
                elif g.contype or g.conaffinity:
                    g.friction = [mu_pad, 0.005, 0.0001]
            act = c.actuator("fingers_actuator")
            act.gaintype = mujoco.mjtGain.mjGAIN_FIXED
            act.gainprm = [1.0] + [0.0] * 9
            act.biastype = mujoco.mjtBias.mjBIAS_NONE
            act.biasprm = [0.0] * 10
            act.ctrlrange = [-1000.0, 1000.0]
            act.forcerange = [-1000.0, 1000.0]
            fr = sp.worldbody.add_frame()
            sp.attach(c, prefix=f"{arm}_", frame=fr)
            eq = sp.add_equality(name=f"{arm}_weld", type=mujoco.mjtEq.mjEQ_WELD, objtype=mujoco.mjtObj.mjOBJ_BODY,
                                 name1=f"{arm}_target", name2=f"{arm}_base_mount")
            eq.solref = [0.002, 1.0]
            eq.solimp = [0.99, 0.999, 0.001, 0.5, 2]
        sp.worldbody.add_geom(name="table", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[3, 3, 0.1],
                              pos=[0, 0, doc.get("support_height", 0.0)], friction=[mu_sup, 0.005, 0.0001],
                              priority=2, condim=3)
        T0 = pose_T(doc["object"]["initial_pose"])
        part = sp.worldbody.add_body(name="part", pos=list(T0[:3, 3]), quat=list(quat(T0[:3, :3])))
        part.add_freejoint(name="part_free")
        part.explicitinertial = True
        part.mass = mp["mass"]
        part.ipos = list(mp["com"])
        part.fullinertia = list(mp["fullinertia"])
        for i, P in enumerate(pieces):
            hull = trimesh.Trimesh(P).convex_hull
            sp.add_mesh(name=f"piece{i}", uservert=list(np.asarray(hull.vertices).ravel()),
                        userface=list(np.asarray(hull.faces).ravel()))
            part.add_geom(name=f"part{i}", type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"piece{i}",
                          friction=[mu_sup, 0.005, 0.0001], condim=3, mass=0)
        self.part_verts = np.vstack(pieces)  # object frame (scaled)
        self.m = m = sp.compile()
        nid = lambda t, n: mujoco.mj_name2id(m, t, n)
        B, G, J = mujoco.mjtObj.mjOBJ_BODY, mujoco.mjtObj.mjOBJ_GEOM, mujoco.mjtObj.mjOBJ_JOINT
        self.part_body = nid(B, "part")
        self.part_geoms = set(g for g in range(m.ngeom) if m.geom_bodyid[g] == self.part_body)
        self.jpart = m.jnt_qposadr[nid(J, "part_free")]
        self.g = {}
        for arm in ("sup", "mas"):
            bodies = {nid(B, f"{arm}_{b}") for b in GRIPPER_BODIES}
            self.g[arm] = {
                "mocap": m.body_mocapid[nid(B, f"{arm}_target")],
                "bm": nid(B, f"{arm}_base_mount"),
                "jfree": m.jnt_qposadr[nid(J, f"{arm}_free")],
                "act": nid(mujoco.mjtObj.mjOBJ_ACTUATOR, f"{arm}_fingers_actuator"),
                "pad": {s: set(nid(G, f"{arm}_{n}") for n in ns) for s, ns in PAD_GEOMS.items()},
                "pad_body": {"pos": nid(B, f"{arm}_right_pad"), "neg": nid(B, f"{arm}_left_pad")},
                "side_geoms": {s: set(g for g in range(m.ngeom) if m.geom_bodyid[g] in
                                      {nid(B, f"{arm}_{pre}_{ln}") for ln in ("driver", "coupler", "spring_link",
                                                                               "follower", "pad", "silicone_pad")})
                               for s, pre in (("pos", "right"), ("neg", "left"))},
                "geoms": set(g for g in range(m.ngeom) if m.geom_bodyid[g] in bodies),
            }
        self.bm_off = T_of(m.body_pos[self.g["sup"]["bm"]], [1, 0, 0, 0])  # base_mount in G (0, 0, 0.007)
        self.d = mujoco.MjData(m)

    def set_flange(self, arm, T, init=False):
        g, d = self.g[arm], self.d
        d.mocap_pos[g["mocap"]] = T[:3, 3]
        d.mocap_quat[g["mocap"]] = quat(T[:3, :3])
        if init:
            Tb = T @ self.bm_off
            d.qpos[g["jfree"]:g["jfree"] + 3] = Tb[:3, 3]
            d.qpos[g["jfree"] + 3:g["jfree"] + 7] = quat(Tb[:3, :3])

    def flange_actual(self, arm):
        bm = self.g[arm]["bm"]
        return T_of(self.d.xpos[bm], self.d.xquat[bm]) @ inv(self.bm_off)

    def part_T(self):
        return T_of(self.d.xpos[self.part_body], self.d.xquat[self.part_body])

    def contacts(self, arm):
        """Normal force of this gripper on the part: per pad side and for its other links."""
        d, g = self.d, self.g[arm]
        out = {"pos": 0.0, "neg": 0.0, "other": 0.0}
        f6 = np.zeros(6)
        for i in range(d.ncon):
            a, b = d.contact.geom[i]
            if b in self.part_geoms:
                a, b = b, a
            if a not in self.part_geoms or b not in g["geoms"]:
                continue
            side = "pos" if b in g["pad"]["pos"] else "neg" if b in g["pad"]["neg"] else "other"
            mujoco.mj_contactForce(self.m, d, i, f6)
            out[side] += f6[0]
        return out

    def pad_gap(self, arm, point=PAD_POINT):
        """x distance (m) between the two fingers' `point` (pad face centre or tip) in the actual flange frame."""
        Tf_inv = inv(self.flange_actual(arm))
        xs = {}
        for s, b in self.g[arm]["pad_body"].items():
            p = T_of(self.d.xpos[b], self.d.xquat[b]) @ np.r_[point, 1]
            xs[s] = (Tf_inv @ p)[0]
        return float(xs["pos"] - xs["neg"])

    def table_contact(self):
        """Summed normal force of the table on the part (N)."""
        f6, tot = np.zeros(6), 0.0
        tid = mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_GEOM, "table")
        for i in range(self.d.ncon):
            a, b = self.d.contact.geom[i]
            if (a == tid and b in self.part_geoms) or (b == tid and a in self.part_geoms):
                mujoco.mj_contactForce(self.m, self.d, i, f6)
                tot += f6[0]
        return tot

    def fingers_touch(self, arm):
        """The +x and -x fingers of this gripper touch each other."""
        sg = self.g[arm]["side_geoms"]
        for i in range(self.d.ncon):
            a, b = self.d.contact.geom[i]
            if (a in sg["pos"] and b in sg["neg"]) or (a in sg["neg"] and b in sg["pos"]):
                return True
        return False


def tau_of_force(F):
    return max(0.0, (F - CAL_B) / CAL_A)


def segment_forces(plan, pinch_force, power_force):
    """The force (N) each closing uses: the closing segment's `grip_force` when the plan has one, else `pinch_force`
    for the pinch (sup1) and `power_force` for the power grasps (mas1, sup2); and which segments had the key."""
    segs = {s["name"]: s for s in plan["segments"]}
    default = {"sup1": pinch_force, "mas1": power_force, "sup2": power_force}
    forces = {n: float(segs[n]["grip_force"]) if segs[n].get("grip_force") is not None else f
              for n, f in default.items()}
    return forces, [n for n in default if segs[n].get("grip_force") is not None]


def run_plan(scene, doc, plan, pregrasp, pinch_force, power_force, slow, log):
    m, d = scene.m, scene.d
    force, from_plan = segment_forces(plan, pinch_force, power_force)
    dt = m.opt.timestep
    robots = {r["name"]: r for r in doc["robots"]}
    role = {plan["supportive"]: "sup", plan["master"]: "mas"}
    q = {n: np.array(r["start"], float) for n, r in robots.items()}
    base = {n: pose_T(r["base"]) for n, r in robots.items()}
    flange = lambda n, qq: base[n] @ dh_fk(robots[n]["model"], qq)
    tau = {"sup": TAU_OPEN, "mas": TAU_OPEN}
    lift_plan = doc.get("planner", {}).get("lift", 0.0) or 0.0
    for n in robots:
        scene.set_flange(role[n], flange(n, q[n]), init=True)
    d.qpos[scene.jpart + 2] -= lift_plan
    mujoco.mj_forward(m, d)
    segs = {s["name"]: s for s in plan["segments"]}
    # axis endpoints in the object frame (the candidate's edge at P_init)
    cand = [c for c in doc["candidates"] if c["id"] == plan["candidate"]][0]
    T_init = pose_T(doc["object"]["initial_pose"])
    axis_obj = [inv(T_init) @ np.r_[p, 1] for p in cand["axis"]]
    rec = {"t_sim": 0.0}
    track = {"on": False, "start": None, "slide": 0.0, "rise": 0.0}
    fk_err = [0.0, 0.0]

    def step(n, per_step=None):
        for i in range(n):
            if per_step:
                per_step(i)
            for arm in ("sup", "mas"):
                d.ctrl[scene.g[arm]["act"]] = tau[arm]
            mujoco.mj_step(m, d)
            if track["on"] and i % SAMPLE_EVERY == 0:
                Tp = scene.part_T()
                pts = [(Tp @ e)[:3] for e in axis_obj]
                if track["start"] is None:
                    track["start"] = pts
                for p, p0 in zip(pts, track["start"]):
                    track["slide"] = max(track["slide"], float(np.linalg.norm((p - p0)[:2])))
                    track["rise"] = max(track["rise"], float(p[2] - p0[2]))
        rec["t_sim"] += n * dt

    steps = lambda T: int(round(T / dt))

    def move(seg):
        n_arm = seg["robot"]
        pts = seg["points"]
        ts = np.array([p["t"] for p in pts]) * slow
        qs = np.array([p["q"] for p in pts])
        for p in (pts[0], pts[len(pts) // 2], pts[-1]):
            e = fk_check(pregrasp, robots[n_arm]["model"], p["q"])
            fk_err[0], fk_err[1] = max(fk_err[0], e[0]), max(fk_err[1], e[1])
        n = steps(ts[-1] - ts[0])

        def ps(i):
            t = ts[0] + (i + 1) * dt
            k = min(int(np.searchsorted(ts, t, side="right")) - 1, len(ts) - 2)
            u = min(max((t - ts[k]) / (ts[k + 1] - ts[k]), 0.0), 1.0)
            q[n_arm] = (1 - u) * qs[k] + u * qs[k + 1]
            scene.set_flange(role[n_arm], flange(n_arm, q[n_arm]))
        step(n, ps)
        q[n_arm] = qs[-1]
        scene.set_flange(role[n_arm], flange(n_arm, q[n_arm]))

    def close(arm, F, correct, width):
        """Spring-close, ramp tau to the force, hold (correcting tau on the measured pad force if `correct`)."""
        tau[arm] = 0.0
        step(steps(T_SPRING))
        target = tau_of_force(F)
        t0 = tau[arm]
        n = steps(T_RAMP)

        def ramp(i):
            tau[arm] = t0 + (target - t0) * (i + 1) / n
        step(n, ramp)
        tau[arm] = target
        meas = None
        for k in range(N_CORRECT if correct else 1):
            acc = {"pos": 0.0, "neg": 0.0, "other": 0.0}
            cnt = [0]

            def sample(i):
                if i >= steps(T_WINDOW) - steps(0.1) and i % 5 == 0:
                    c = scene.contacts(arm)
                    for s in acc:
                        acc[s] += c[s]
                    cnt[0] += 1
            step(steps(T_WINDOW), sample)
            meas = {s: v / max(cnt[0], 1) for s, v in acc.items()}
            mean = 0.5 * (meas["pos"] + meas["neg"])
            if not correct or abs(mean - F) <= 0.01 * F:
                break
            tau[arm] = max(0.0, tau[arm] + (F - mean) / CAL_A)
        return {"F_cmd": F, "tau": tau[arm], "N_pos": meas["pos"], "N_neg": meas["neg"], "N_other": meas["other"],
                "pad_gap": scene.pad_gap(arm), "tip_gap": scene.pad_gap(arm, TIP_POINT),
                "fingers_touch": scene.fingers_touch(arm), "grip_width_plan": width, "kind": kind(arm, width)}

    def kind(arm, width):
        c = scene.contacts(arm)
        on = [c[s] > 0.5 for s in ("pos", "neg")]
        if all(on):
            return "both_sides"
        if any(on):
            return "one_side"
        closed_past = width is not None and min(scene.pad_gap(arm), scene.pad_gap(arm, TIP_POINT)) < width - CAGED_MARGIN
        if closed_past or scene.fingers_touch(arm):
            return "caged" if c["other"] > 0.5 else "caged_no_contact"
        return "no_contact"

    # --- the time line
    step(steps(T_SETTLE))
    move(segs["sup1"])
    rec["pinch"] = close("sup", force["sup1"], True, segs["sup1"].get("grip_width"))
    T_before_rot = scene.part_T()
    track["on"] = True
    move(segs["rot"])
    track["on"] = False
    Tp = scene.part_T()
    Tplan = pose_T(segs["rot"]["points"][-1]["object_pose"])
    gs = np.r_[pose_T(doc["grasps"]["support"])[:3, 3], 1]
    rec["rot"] = {"edge_slide_max": track["slide"], "edge_lift_max": track["rise"],
                  "pos_err_at_G_s": float(np.linalg.norm((Tp @ gs)[:3] - (Tplan @ gs)[:3])),
                  "ang_err_deg": math.degrees(rot_angle(Tp[:3, :3], Tplan[:3, :3])),
                  "turned_deg": math.degrees(rot_angle(Tp[:3, :3], T_before_rot[:3, :3])),
                  "turn_plan_deg": math.degrees(rot_angle(Tplan[:3, :3], T_init[:3, :3])),
                  "pinch_kind_end": kind("sup", segs["rot"].get("grip_width"))}
    move(segs["mas1"])
    Tm0 = scene.part_T()
    rec["mas1_close"] = close("mas", force["mas1"], False, segs["mas1"].get("grip_width"))
    Tm1 = scene.part_T()
    com = m.body_ipos[scene.part_body]
    rec["mas1_close"]["part_moved"] = float(np.linalg.norm((Tm1[:3, :3] @ com + Tm1[:3, 3]) - (Tm0[:3, :3] @ com + Tm0[:3, 3])))
    rec["mas1_close"]["part_turned_deg"] = math.degrees(rot_angle(Tm1[:3, :3], Tm0[:3, :3]))
    tau["sup"] = TAU_OPEN
    To0 = scene.part_T()
    step(steps(T_OPEN))
    To1 = scene.part_T()
    rec["sup_open"] = {"kind_after": kind("sup", None),
                       "part_moved": float(np.linalg.norm((To1[:3, :3] @ com + To1[:3, 3]) - (To0[:3, :3] @ com + To0[:3, 3]))),
                       "part_turned_deg": math.degrees(rot_angle(To1[:3, :3], To0[:3, :3]))}
    move(segs["sup2"])
    Ts0 = scene.part_T()
    rec["sup2_close"] = close("sup", force["sup2"], False, segs["sup2"].get("grip_width"))
    Ts1 = scene.part_T()
    rec["sup2_close"]["part_moved"] = float(np.linalg.norm((Ts1[:3, :3] @ com + Ts1[:3, 3]) - (Ts0[:3, :3] @ com + Ts0[:3, 3])))
    rec["sup2_close"]["part_turned_deg"] = math.degrees(rot_angle(Ts1[:3, :3], Ts0[:3, :3]))
    # --- the lift: both flanges up LIFT together, then hold
    F0 = {n: flange(n, q[n]) for n in robots}
    Tl0 = scene.part_T()
    in_grip0 = {arm: inv(scene.flange_actual(arm)) @ Tl0 for arm in ("sup", "mas")}
    lowest0 = float((scene.part_verts @ Tl0[:3, :3].T + Tl0[:3, 3])[:, 2].min()) - doc.get("support_height", 0.0)
    table0 = scene.table_contact()
    n = steps(T_LIFT)

    def up(i):
        for nm in robots:
            T = F0[nm].copy()
            T[2, 3] += LIFT * (i + 1) / n
            scene.set_flange(role[nm], T)
    step(n, up)
    step(steps(T_HOLD))
    Tl1 = scene.part_T()
    lowest = float((scene.part_verts @ Tl1[:3, :3].T + Tl1[:3, 3])[:, 2].min()) - doc.get("support_height", 0.0)
    Tgoal = pose_T(plan["object_goal_pose"])
    rec["lift"] = {"rise": float((Tl1[:3, :3] @ com + Tl1[:3, 3])[2] - (Tl0[:3, :3] @ com + Tl0[:3, 3])[2]),
                   "tilt_deg": math.degrees(rot_angle(Tl1[:3, :3], Tl0[:3, :3])),
                   "table_force_end": scene.table_contact(),
                   "part_lowest_above_table_end": lowest,
                   "part_lowest_above_table_start": lowest0, "table_force_start": table0,
                   "slip_in_grip": {arm: float(np.linalg.norm((inv(scene.flange_actual(arm)) @ Tl1 @ np.r_[com, 1])[:3]
                                                            - (in_grip0[arm] @ np.r_[com, 1])[:3])) for arm in ("sup", "mas")},
                   "slip_in_grip_deg": {arm: math.degrees(rot_angle((inv(scene.flange_actual(arm)) @ Tl1)[:3, :3],
                                                                    in_grip0[arm][:3, :3])) for arm in ("sup", "mas")},
                   "goal_ang_err_deg_before_lift": math.degrees(rot_angle(Tl0[:3, :3], Tgoal[:3, :3])),
                   "kind_end": {"mas": kind("mas", segs["mas1"].get("grip_width")),
                                "sup": kind("sup", segs["sup2"].get("grip_width"))},
                   "N_end": {"mas": scene.contacts("mas"), "sup": scene.contacts("sup")}}
    rec["fk_check_max"] = {"pos": fk_err[0], "rad": fk_err[1]}
    rec["grip_force_from_plan"] = from_plan
    rec.update(verdict(rec))
    log(f"  pinch {rec['pinch']['kind']} N {rec['pinch']['N_pos']:.1f}/{rec['pinch']['N_neg']:.1f}; rot edge slide "
        f"{rec['rot']['edge_slide_max']*1e3:.1f} mm lift {rec['rot']['edge_lift_max']*1e3:.1f} mm, err "
        f"{rec['rot']['pos_err_at_G_s']*1e3:.1f} mm {rec['rot']['ang_err_deg']:.1f} deg; mas1 {rec['mas1_close']['kind']} "
        f"moved {rec['mas1_close']['part_moved']*1e3:.1f} mm {rec['mas1_close']['part_turned_deg']:.1f} deg; sup2 "
        f"{rec['sup2_close']['kind']}; lift rise {rec['lift']['rise']*1e3:.1f} mm tilt {rec['lift']['tilt_deg']:.1f} deg; "
        f"{rec['verdict']} {'+'.join(rec['failures'])}")
    return rec


def replay_file(plan_path, plan_indices, power_forces, src, a, log):
    """Rows of plan_path's plans `plan_indices` (those present), each once per power force: `power_forces(pinch)`
    gives the forces for a plan whose pinch force is `pinch` (N). `a`: pregrasp, mesh_root, slow, dt, noslip."""
    rows = []
    doc = json.load(open(plan_path))
    if doc.get("status") != "planned":
        log(f"{plan_path}: status {doc.get('status')}, skipped")
        return rows
    example = Path(doc["scene"]["file"]).stem
    mesh = trimesh.load(str(resolve_mesh(plan_path, doc["object"]["mesh"], a.mesh_root)), force="mesh")
    scale = doc["object"].get("scale", 1.0)
    mesh_s = mesh.copy()
    mesh_s.apply_scale(scale)
    try:
        pieces, dinfo = decompose_extrusion(mesh_s)
    except ValueError:
        pieces, dinfo = decompose_coacd(mesh_s)
    for k in plan_indices:
        if k >= len(doc["plans"]):
            continue
        plan = doc["plans"][k]
        ph = plan.get("physics") or {}
        mass = doc["object"].get("mass") or ph.get("mass")
        mp = mass_properties(mesh, mass, scale)
        pinch = ph.get("grip_force_recommended", 20.0)
        for pf in power_forces(pinch):
            t0 = time.time()
            log(f"{example} plan {k}: mass {mass} kg, {dinfo['pieces']} pieces, pinch {pinch} N, power {pf} N")
            sc = PlanScene(src / MODEL_XML, doc, plan, pieces, mp, ph.get("mu_pad", 0.8),
                           ph.get("mu_support", 0.4), a.dt, a.noslip)
            rec = run_plan(sc, doc, plan, a.pregrasp, pinch, pf, a.slow, log)
            log(f"  {time.time() - t0:.1f} s wall, {rec['t_sim']:.1f} s simulated")
            rows.append({"example": example, "plan": k, "candidate": plan["candidate"], "mass": mass,
                         "master": plan["master"], "supportive": plan["supportive"], "pieces": dinfo["pieces"],
                         "pinch_force": pinch, "power_force": pf, **rec})
    return rows


def header(a, prov):
    """The provenance header of a replay table (script, args, date, Menagerie source, versions, model settings)."""
    return {
        "generator": SCRIPT,
        "args": [os.path.basename(x) if os.path.isabs(x) else x for x in sys.argv[1:]],
        "date": datetime.date.today().isoformat(),
        "source": {"repo": "https://github.com/google-deepmind/mujoco_menagerie", "path": f"{MODEL_DIR}/{MODEL_XML}", **prov},
        "mujoco_version": mujoco.__version__, "numpy_version": np.__version__, "trimesh_version": trimesh.__version__,
        "units": "metres, kilograms, newtons, seconds; *_deg in degrees",
        "model": {"timestep": a.dt, "noslip_iterations": a.noslip, "cone": "elliptic", "impratio": 10.0,
                  "pads_condim": 3, "time_scaling": a.slow, "force_calibration": [CAL_A, CAL_B],
                  "phases": {"settle": T_SETTLE, "spring_close": T_SPRING, "ramp": T_RAMP, "window": T_WINDOW,
                             "pinch_corrections": N_CORRECT, "open": T_OPEN, "lift": LIFT, "t_lift": T_LIFT,
                             "hold": T_HOLD},
                  "caged_margin": CAGED_MARGIN,
                  "description": "README section 'Replay of the whole plan'"},
        "verdict": THRESHOLDS,
    }


def model_args(ap):
    """The arguments the replay itself takes (shared with plan_sweep.py)."""
    ap.add_argument("--menagerie", required=True)
    ap.add_argument("--rev", default="HEAD")
    ap.add_argument("--pregrasp", default=str(DEFAULT_PREGRASP), help="binary for `kin fk` (the FK check)")
    ap.add_argument("--mesh-root", default=None)
    ap.add_argument("--slow", type=float, default=1.0, help="time scaling of every segment (1 = the plan's time line)")
    ap.add_argument("--dt", type=float, default=0.001)
    ap.add_argument("--noslip", type=int, default=10)
    ap.add_argument("--out", default=str(OUT_DIR))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("plans", nargs="+")
    model_args(ap)
    ap.add_argument("--plan-index", type=int, nargs="*", default=[0])
    ap.add_argument("--power-force", type=float, default=None,
                    help="N, the power grasps' force (default: the plan's physics.grip_force_recommended)")
    ap.add_argument("--no-max-pass", action="store_true", help="skip the second pass at 235 N")
    ap.add_argument("--name", default="plan_replay_2f85")
    a = ap.parse_args()
    t_start = time.time()
    log = lambda s: print(s, flush=True)

    def power_forces(pinch):
        forces = [a.power_force if a.power_force is not None else pinch]
        if not a.no_max_pass and forces[0] != F_MAX:
            forces.append(F_MAX)
        return forces
    rows = []
    with tempfile.TemporaryDirectory(prefix="plan_replay_") as tmp:
        src, prov = load_source(a.menagerie, a.rev, tmp)
        for plan_path in a.plans:
            rows += replay_file(plan_path, a.plan_index, power_forces, src, a, log)
    rows.sort(key=lambda r: (r["example"], r["plan"], r["power_force"]))
    out = Path(a.out)
    write_atomic(out / f"{a.name}.json", dump_json(header(a, prov), rows))
    write_atomic(out / f"{a.name}.csv", csv_text(rows))
    log(f"wrote {out / a.name}.{{json,csv}}: {len(rows)} rows, {time.time() - t_start:.1f} s")


if __name__ == "__main__":
    main()
