"""The time line of the whole-plan replay (`run_plan`): all four segments of one plan (sup1, close the pinch; rot;
mas1, close the master's power grasp; the supportive gripper opens; sup2, close its power grasp), then both
grippers rise together and hold. Phases and columns: tools/gripper_truth/README.md, "Replay of the whole plan"."""
import math

import mujoco
import numpy as np

from .arms import placed_arms
from .geometry import DH, inv, pose_T, rot_angle
from .scene import TAU_OPEN, TIP_POINT
from .verdict import LIFT, verdict

F_MAX = 235.0  # N, the 2F-85's largest grip force
# measured pad force ~ CAL_A * tau + CAL_B (the pinch calibration of replay.py, README "Replay of the rotation")
CAL_A, CAL_B = 9.2, 1.8
# phases (simulated seconds)
T_SETTLE = 0.3  # the part settles on the table, both grippers open
T_SPRING = 0.6  # a closing: tau 0, the spring links close the fingers gently
T_RAMP = 0.3  # tau ramps to its target
T_WINDOW = 0.3  # one force window (the pinch's tau is corrected after each, at most N_CORRECT)
N_CORRECT = 3
T_OPEN = 0.5  # the supportive gripper opens at the start of sup2 (arm held)
T_LIFT = 1.0
T_HOLD = 1.0
SAMPLE_EVERY = 10
CAGED_MARGIN = 0.002  # m: pads closed this much past the bar width (plan grip_width) with no pad contact
CLOSINGS = ("sup1", "mas1", "sup2")


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


def moved(Ta, Tb, com):
    """CoM displacement (m) and rotation angle (deg) of the part from pose Ta to pose Tb."""
    return (float(np.linalg.norm((Tb[:3, :3] @ com + Tb[:3, 3]) - (Ta[:3, :3] @ com + Ta[:3, 3]))),
            math.degrees(rot_angle(Tb[:3, :3], Ta[:3, :3])))


def run_plan(scene, doc, plan, force, lift=LIFT, slow=1.0, fk_check=None, log=None, plan_path=None, arms=None):
    """Replays `plan` (a dict of doc["plans"]) in `scene` with the closing forces `force` (N, keys sup1, mas1, sup2).
    `fk_check(model, q)` -> (m, rad) compares dh_fk with another FK at three points of every segment of a UR arm
    (None: not checked). The arms' flange poses come from `arms` (name -> fk(q), `arms.placed_arms`), else are placed
    here (a described arm's file found from the scene's folder, or `plan_path`'s). Returns (record, trace): the
    record as the truth tables' rows have it, and per segment the part's pose at its start and end (the supportive
    gripper's opening counts to sup2). Raises arms.ArmError for an arm the replay cannot place or a gripper it does
    not model."""
    m, d = scene.m, scene.d
    dt = m.opt.timestep
    robots = {r["name"]: r for r in doc["robots"]}
    role = {plan["supportive"]: "sup", plan["master"]: "mas"}
    q = {n: np.array(r["start"], float) for n, r in robots.items()}
    base = {n: pose_T(r["base"]) for n, r in robots.items()}
    fk = arms if arms is not None else placed_arms(doc, plan_path)
    flange = lambda n, qq: base[n] @ fk[n](qq)
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
        if fk_check and robots[n_arm]["model"] in DH:
            for p in (pts[0], pts[len(pts) // 2], pts[-1]):
                e = fk_check(robots[n_arm]["model"], p["q"])
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
    T_start = scene.part_T()
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
    rec["mas1_close"]["part_moved"], rec["mas1_close"]["part_turned_deg"] = moved(Tm0, Tm1, com)
    tau["sup"] = TAU_OPEN
    To0 = scene.part_T()
    step(steps(T_OPEN))
    To1 = scene.part_T()
    rec["sup_open"] = {"kind_after": kind("sup", None)}
    rec["sup_open"]["part_moved"], rec["sup_open"]["part_turned_deg"] = moved(To0, To1, com)
    move(segs["sup2"])
    Ts0 = scene.part_T()
    rec["sup2_close"] = close("sup", force["sup2"], False, segs["sup2"].get("grip_width"))
    Ts1 = scene.part_T()
    rec["sup2_close"]["part_moved"], rec["sup2_close"]["part_turned_deg"] = moved(Ts0, Ts1, com)
    trace = {"sup1": (T_start, T_before_rot), "rot": (T_before_rot, Tp), "mas1": (Tp, Tm1), "sup2": (Tm1, Ts1),
             "com": np.array(com)}
    # --- the lift: both flanges up `lift` together, then hold
    F0 = {n: flange(n, q[n]) for n in robots}
    Tl0 = scene.part_T()
    in_grip0 = {arm: inv(scene.flange_actual(arm)) @ Tl0 for arm in ("sup", "mas")}
    lowest0 = float((scene.part_verts @ Tl0[:3, :3].T + Tl0[:3, 3])[:, 2].min()) - doc.get("support_height", 0.0)
    table0 = scene.table_contact()
    n = steps(T_LIFT)

    def up(i):
        for nm in robots:
            T = F0[nm].copy()
            T[2, 3] += lift * (i + 1) / n
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
    # Only UR arms are checked (`pregrasp kin fk` knows them alone): none, no record.
    if fk_check and any(r["model"] in DH for r in robots.values()):
        rec["fk_check_max"] = {"pos": fk_err[0], "rad": fk_err[1]}
    rec.update(verdict(rec, lift))
    if log:
        log(f"  pinch {rec['pinch']['kind']} N {rec['pinch']['N_pos']:.1f}/{rec['pinch']['N_neg']:.1f}; rot edge slide "
            f"{rec['rot']['edge_slide_max']*1e3:.1f} mm lift {rec['rot']['edge_lift_max']*1e3:.1f} mm, err "
            f"{rec['rot']['pos_err_at_G_s']*1e3:.1f} mm {rec['rot']['ang_err_deg']:.1f} deg; mas1 {rec['mas1_close']['kind']} "
            f"moved {rec['mas1_close']['part_moved']*1e3:.1f} mm {rec['mas1_close']['part_turned_deg']:.1f} deg; sup2 "
            f"{rec['sup2_close']['kind']}; lift rise {rec['lift']['rise']*1e3:.1f} mm tilt {rec['lift']['tilt_deg']:.1f} deg; "
            f"{rec['verdict']} {'+'.join(rec['failures'])}")
    return rec, trace
