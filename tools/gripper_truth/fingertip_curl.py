#!/usr/bin/env python3
"""How far the Robotiq 2F-85's fingers curl when they pinch a bar near their tips at a set force: the
MuJoCo Menagerie model closing on a fixed bar, with the whole-plan replay's force actuator.

    pip install mujoco numpy
    python3 tools/gripper_truth/fingertip_curl.py <menagerie> [--rev REV]

A power grasp held at the fingertips (crates/planner/src/seat/mod.rs) puts its bar between the pads at the
precision point (150 mm from the flange) or a few millimetres nearer the palm. The nearer the palm the
pads meet the bar, the more the closing force turns the fingers' distal links in (the tips closer than the
pad centres): at 235 N a bar that is not held fast is then pried towards the palm (frame_80's master in the
whole-plan replay, docs/physics.md "Fingertip holds no deeper than 4 mm"). This grid measures that curl.

Grid: the gripper pointing down, a bar fixed in space (no table), `width` along the closing axis,
`thickness` along the approach, its centre `short` millimetres nearer the palm than the precision point.
Closing as the whole-plan replay's (python/pregrasp/sim/run.py): open, the spring links close (tendon force
0), the force ramps to the setting's, held 0.6 s; pad friction 0.8, contact dimension 3. Per row: the pad
centres' and the tips' distance across (`pad_gap`, `tip_gap`; curl = pad_gap - tip_gap), each side's
normal force, and the force-weighted depth of the pads' contacts from the flange (`z_force`).

Writes crates/robot/data/gripper_truth/fingertip_curl_2f85.{json,csv} (atomically; deterministic for the
same inputs, MuJoCo version and machine).
"""
import sys
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from source import MODEL_DIR, MODEL_XML, load_source, menagerie_args  # noqa: E402
from tables import write_tables  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[2]
OUT_DIR = REPO_ROOT / "crates/robot/data/gripper_truth"
SCRIPT = "tools/gripper_truth/fingertip_curl.py"
sys.path.insert(0, str(REPO_ROOT / "python/pregrasp"))
from sim.geometry import T_of  # noqa: E402
from sim.run import T_RAMP, T_SPRING, T_WINDOW, tau_of_force  # noqa: E402
from sim.scene import GRIPPER_BODIES, PAD_GEOMS, PAD_POINT, TAU_OPEN, TIP_POINT  # noqa: E402

PRECISION_Z = 0.150  # m from the flange (the scenes' precision_point_z)
WIDTHS_MM = [35, 45, 54]
THICKS_MM = [19, 25]
SHORT_MM = [-1.5, 0.5, 2.5, 4.5, 6.5, 8.5, 10.5]  # the bar's centre nearer the palm than the precision point
FORCES_N = [20.0, 235.0]
MU_PAD = 0.8
BAR_LEN = 0.3
DT = 0.001
T_OPEN = 0.2
T_HELD = 2 * T_WINDOW
H = 0.5  # the flange's height; its z points down


def scene(xml, w, t, zc):
    """The gripper at the flange (0, 0, H) pointing down and a bar fixed with its centre zc below the flange."""
    sp = mujoco.MjSpec()
    sp.option.timestep = DT
    sp.option.noslip_iterations = 10
    sp.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
    sp.option.impratio = 10.0
    c = mujoco.MjSpec.from_file(str(xml))
    for b in GRIPPER_BODIES:
        c.body(b).gravcomp = 1.0
    for g in c.geoms:
        if g.name in PAD_GEOMS["pos"] + PAD_GEOMS["neg"]:
            g.friction = [MU_PAD, 0.0, 0.0001]
            g.condim = 3
        elif g.contype or g.conaffinity:
            g.friction = [MU_PAD, 0.005, 0.0001]
    act = c.actuator("fingers_actuator")
    act.gaintype = mujoco.mjtGain.mjGAIN_FIXED
    act.gainprm = [1.0] + [0.0] * 9
    act.biastype = mujoco.mjtBias.mjBIAS_NONE
    act.biasprm = [0.0] * 10
    act.ctrlrange = [-1000.0, 1000.0]
    act.forcerange = [-1000.0, 1000.0]
    fr = sp.worldbody.add_frame(pos=[0, 0, H - 0.007], quat=[0, 1, 0, 0])  # base_mount 7 mm along flange z
    sp.attach(c, prefix="g_", frame=fr)
    bar = sp.worldbody.add_body(name="bar", pos=[0, 0, H - zc])
    bar.add_geom(name="bar", type=mujoco.mjtGeom.mjGEOM_BOX, size=[w / 2, BAR_LEN / 2, t / 2],
                 friction=[MU_PAD, 0.005, 0.0001])
    return sp.compile()


def close(xml, w, t, short, force):
    zc = PRECISION_Z - short
    m = scene(xml, w, t, zc)
    d = mujoco.MjData(m)
    nid = lambda ty, n: mujoco.mj_name2id(m, ty, n)
    B, G = mujoco.mjtObj.mjOBJ_BODY, mujoco.mjtObj.mjOBJ_GEOM
    bar = nid(G, "bar")
    pads = {s: {nid(G, "g_" + n) for n in ns} for s, ns in PAD_GEOMS.items()}
    pad_body = {"pos": nid(B, "g_right_pad"), "neg": nid(B, "g_left_pad")}
    steps = lambda T: int(round(T / DT))

    def hold(n, tau):
        for _ in range(n):
            d.ctrl[0] = tau
            mujoco.mj_step(m, d)
    mujoco.mj_forward(m, d)
    hold(steps(T_OPEN), TAU_OPEN)
    hold(steps(T_SPRING), 0.0)
    target, n = tau_of_force(force), steps(T_RAMP)
    for i in range(n):
        d.ctrl[0] = target * (i + 1) / n
        mujoco.mj_step(m, d)
    hold(steps(T_HELD), target)

    def across(point):
        x = {s: (T_of(d.xpos[b], d.xquat[b]) @ np.r_[point, 1])[0] for s, b in pad_body.items()}
        return abs(x["pos"] - x["neg"])
    f6, N, zN = np.zeros(6), {"pos": 0.0, "neg": 0.0, "other": 0.0}, {"pos": 0.0, "neg": 0.0}
    for i in range(d.ncon):
        a, b = d.contact.geom[i]
        if b == bar:
            a, b = b, a
        if a != bar:
            continue
        mujoco.mj_contactForce(m, d, i, f6)
        side = "pos" if b in pads["pos"] else "neg" if b in pads["neg"] else "other"
        N[side] += f6[0]
        if side != "other":
            zN[side] += f6[0] * (H - d.contact.pos[i][2])
    pad_gap, tip_gap = across(PAD_POINT), across(TIP_POINT)
    return {"id": f"w{w * 1e3:.0f}_t{t * 1e3:.0f}_s{short * 1e3:+.1f}_f{force:.0f}",
            "bar": {"width": w, "thickness": t, "z_center": zc, "short_of_precision_point": short},
            "force_set": force, "pad_gap": pad_gap, "tip_gap": tip_gap, "curl": pad_gap - tip_gap,
            "N": N, "z_force": {s: (zN[s] / N[s] if N[s] > 0 else None) for s in zN}}


def main():
    a = menagerie_args(__doc__, OUT_DIR)
    t_start = time.time()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        src, prov = load_source(a.menagerie, a.rev, tmp)
        specs = [(w / 1e3, t / 1e3, s / 1e3, f) for w in WIDTHS_MM for t in THICKS_MM for s in SHORT_MM
                 for f in FORCES_N]
        if a.limit:
            specs = specs[:a.limit]
        for w, t, s, f in specs:
            r = close(src / MODEL_XML, w, t, s, f)
            rows.append(r)
            print(f"{r['id']}: pad gap {r['pad_gap'] * 1e3:5.1f} tip gap {r['tip_gap'] * 1e3:5.1f} curl "
                  f"{r['curl'] * 1e3:4.1f} mm, N {r['N']['pos']:.0f}/{r['N']['neg']:.0f} N", flush=True)
    rows.sort(key=lambda r: r["id"])
    header = {
        "generator": SCRIPT,
        "source": {"repo": "https://github.com/google-deepmind/mujoco_menagerie", "path": f"{MODEL_DIR}/{MODEL_XML}",
                   **prov},
        "mujoco_version": mujoco.__version__,
        "numpy_version": np.__version__,
        "units": "metres, seconds, newtons",
        "frame": "the flange's: z along the approach; x the closing axis",
        "grid": {"precision_point_z": PRECISION_Z, "widths_mm": WIDTHS_MM, "thicknesses_mm": THICKS_MM,
                 "short_mm": SHORT_MM, "forces_n": FORCES_N, "bar_length_y": BAR_LEN, "rows": len(rows)},
        "simulation": {"timestep": DT, "mu_pad": MU_PAD, "pads_condim": 3, "bar": "fixed, no table",
                       "phases": {"open": T_OPEN, "spring_close": T_SPRING, "ramp": T_RAMP, "held": T_HELD},
                       "actuator": "tendon force, tau = tau_of_force(force) (python/pregrasp/sim/run.py)"},
    }
    write_tables(a.out, "fingertip_curl_2f85", header, rows, t_start)


if __name__ == "__main__":
    main()
