#!/usr/bin/env python3
"""Ground truth of how the Robotiq 2F-85 closes on a bar held as a power grasp: the bar's top a few
millimetres below the palm, simulated with the MuJoCo Menagerie model.

    pip install mujoco numpy
    python3 tools/gripper_truth/power_closing.py <menagerie> [--rev REV]

closing.py's grid puts the bar's top at or past the power point (z 0.115 in G), 14 mm or more below the
palm (the base ends at z 0.1008). A planned power grasp holds the bar much nearer the palm: the scenes'
power point is the palm + half the bar's thickness + 4 mm, so the bar's top is about 4 mm below the palm,
and a seated grasp (crates/planner/src/seat/mod.rs) 0.5 mm. Whether the fingers then squeeze the bar or
close under it (caged) is what the carry check needs to know; this grid is that regime.

Grid: tilt 0, no table (a power grasp closes on the part off the table or beside it), the bar's top
`palm gap` below the palm's lowest point: gap x width x thickness below. Same scene, command and
settle rule as closing.py (closing_scene.py), plus per finger the bar's normal force on its distal
(follower + pad) and proximal links at the end (`bar_force_end`), and on the palm (`palm_force_end`).

Writes crates/robot/data/gripper_truth/closing_2f85_power.{json,csv} (atomically; deterministic for
the same inputs, MuJoCo version and machine).
"""
import sys
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from closing_gripper import geom_points  # noqa: E402
from closing_scene import BAR_LEN, CTRL_CLOSED, POWER_Z, T_CAP, T_MIN, T_RAMP, Scene, simulate_row  # noqa: E402
from source import MODEL_DIR, MODEL_XML, load_source, menagerie_args  # noqa: E402
from tables import write_tables  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[2]
OUT_DIR = REPO_ROOT / "crates/robot/data/gripper_truth"
SCRIPT = "tools/gripper_truth/power_closing.py"

GAPS_MM = [0.5, 2, 4, 6, 9, 12, 16]  # bar top below the palm (16: 1.8 mm past the power point)
WIDTHS_MM = [15, 20, 25, 30, 35, 40]  # along x (closing axis)
THICKS_MM = [18, 22, 26, 30, 34, 38, 42]  # along z (approach)


def palm_z(m, d, gr):
    """The palm's lowest point: max G z over the hull vertices of the base and base_mount geoms (open pose)."""
    zrow = gr.R_w_G[:, 2]
    best = -1e9
    for g in sorted(gr.palm_geoms):
        V = geom_points(m, g)
        if V is None:
            continue
        b = m.geom_bodyid[g]
        W = V @ d.xmat[b].reshape(3, 3).T + d.xpos[b]
        best = max(best, float(((W - gr.o_w_G) @ zrow).max()))
    return best


def main():
    a = menagerie_args(__doc__, OUT_DIR)
    t_start = time.time()
    with tempfile.TemporaryDirectory(prefix="gripper_truth_") as tmp:
        src, prov = load_source(a.menagerie, a.rev, tmp)
        scene = Scene(src / MODEL_XML)
        m0, gr = scene.compile(gravity=False)
        d0 = mujoco.MjData(m0)
        mujoco.mj_forward(m0, d0)
        palm = round(palm_z(m0, d0, gr), 6)
        print(f"menagerie commit {prov['commit']}, mujoco {mujoco.__version__}; palm's lowest point z {palm:.5f}",
              flush=True)
        specs = [(g, w, t) for g in GAPS_MM for w in WIDTHS_MM for t in THICKS_MM]
        if a.limit:
            specs = specs[:a.limit]
        rows = []
        for i, (g, w, t) in enumerate(specs):
            t0 = time.time()
            dep_mm = round((palm + g / 1000 - POWER_Z) * 1000, 6)
            rid = f"w{w:02d}_t{t:02d}_g{int(round(g * 10)):02d}_power"
            r = simulate_row(scene, (w, t, dep_mm, 0, False), rid)
            r["palm_gap"] = g / 1000
            rows.append(r)
            extra = ""
            if r["status"] == "simulated":
                f = {s: r["fingers"][s]["bar_force_end"] for s in ("pos", "neg")}
                extra = (f"{r['mode']:12s}{' caged' if r['caged'] else '      '} "
                         f"distal {f['pos']['distal']:6.1f}/{f['neg']['distal']:6.1f} N "
                         f"proximal {f['pos']['proximal']:6.1f}/{f['neg']['proximal']:6.1f} N "
                         f"pad gap {r['pad_gap'] * 1e3:5.1f} mm {'settled' if r['settled'] else 'creeping'}")
            print(f"[{i + 1}/{len(specs)}] {rid} {r['status']} {extra} ({time.time() - t0:.2f} s)", flush=True)
    rows.sort(key=lambda r: r["id"])
    header = {
        "generator": SCRIPT,
        "source": {"repo": "https://github.com/google-deepmind/mujoco_menagerie", "path": f"{MODEL_DIR}/{MODEL_XML}",
                   **prov},
        "mujoco_version": mujoco.__version__,
        "numpy_version": np.__version__,
        "units": "metres, radians (angles named *_deg in degrees), seconds, newtons; positions in G",
        "frame": "G, points and columns as closing_2f85.json (tools/gripper_truth/README.md)",
        "grid": {"palm_z": palm, "power_point_z": POWER_Z, "bar_length_y": BAR_LEN, "palm_gaps_mm": GAPS_MM,
                 "widths_mm": WIDTHS_MM, "thicknesses_mm": THICKS_MM,
                 "rule": ("tilt 0, no table; the bar's top at z_top = palm_z + palm_gap (palm_z: the palm's "
                          "lowest point, max G z of the base and base_mount geoms at the open pose); "
                          "depth_past_power_point = z_top - power_point_z (negative: nearer the palm)"),
                 "rows": len(rows)},
        "simulation": {"as": "closing_2f85.json", "ctrl": f"ramp 0 -> {CTRL_CLOSED} over {T_RAMP} s, then held",
                       "t_min": T_MIN, "t_cap": T_CAP,
                       "forces": ("bar_force_end: per finger, the summed normal contact force of the bar on its "
                                  "distal (follower, pad, silicone pad) and proximal (driver, coupler, spring link) "
                                  "geoms at the end (mj_contactForce); palm_force_end: on the base and base_mount")},
    }
    write_tables(a.out, "closing_2f85_power", header, rows, t_start)


if __name__ == "__main__":
    main()
