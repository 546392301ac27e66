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
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import mujoco
import numpy as np
import trimesh

# The work is in source.py (the Menagerie files), replay_part.py (the part's convex pieces and mass),
# replay_scene.py (the scene, one run, its verdict) and tables.py (JSON / CSV); this file gets N_min from
# `pregrasp physics`, bisects F* and writes the output.
sys.path.insert(0, str(Path(__file__).resolve().parent))
from replay_part import decompose_coacd, decompose_extrusion, mass_properties  # noqa: E402
from replay_scene import (  # noqa: E402
    ANG_TOL_DEG,
    GAP_TOL,
    N_CORRECT,
    POS_TOL,
    T_CORRECT,
    T_HOLD,
    T_MEASURE,
    T_RAMP,
    T_SETTLE_OPEN,
    T_SPRING_CLOSE,
    TAU_OPEN,
    Replay,
)
from source import MODEL_DIR, MODEL_XML, load_source  # noqa: E402
from tables import csv_text, dump_json, write_atomic  # noqa: E402

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
    text = dump_json(header, rows)
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
