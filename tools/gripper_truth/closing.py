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
import json
import sys
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np

# The work is in source.py (the Menagerie files), closing_gripper.py (the model's index, the frame G),
# closing_scene.py (the bar grid, the scene, one simulated row), tables.py (JSON / CSV); this file runs the
# free-air sweep, compares it with our table and writes the output.
sys.path.insert(0, str(Path(__file__).resolve().parent))
from closing_gripper import DISTAL, LINKS, SIDES  # noqa: E402
from closing_scene import (  # noqa: E402
    BAR_LEN,
    CTRL_CLOSED,
    CURL_RAD,
    DEPTHS_MM,
    GRAVITY_G,
    OPEN_TOL,
    POWER_Z,
    SAMPLE_EVERY,
    SETTLE_TOL,
    SETTLE_WIN,
    T_CAP,
    T_MIN,
    T_RAMP,
    THICKS_MM,
    TILTED_DEPTHS_MM,
    TILTED_WIDTHS_MM,
    TILTS_DEG,
    WIDTHS_MM,
    Scene,
    grid,
    simulate_row,
)
from source import MODEL_DIR, MODEL_XML, load_source, menagerie_args  # noqa: E402
from tables import write_tables  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[2]
OUT_DIR = REPO_ROOT / "crates/robot/data/gripper_truth"
OUR_TABLE = REPO_ROOT / "crates/robot/data/robotiq_2f85.json"
SCRIPT = "tools/gripper_truth/closing.py"

# Free-air sweep
SWEEP_N = 20
SWEEP_T_CAP = 2.0
SWEEP_VTOL = 1e-5  # rad/s


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


def main():
    a = menagerie_args(__doc__, OUT_DIR)
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
    write_tables(a.out, "closing_2f85", header, rows, t_start)


if __name__ == "__main__":
    main()
