"""The scene of replay.py (`Replay`): table, part, the Menagerie 2F-85 on a free base welded to a mocap
flange that follows the plan's `rot`; one squeeze-and-turn run (`Replay.run`) and its verdict, and the
force calibration (`Replay.calibrate`)."""
import math

import mujoco
import numpy as np
import trimesh

from transforms import T_of, inv, pose_T, rot_angle, slerp
from transforms import mat_of_quat as mat
from transforms import quat_of_mat as quat

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
