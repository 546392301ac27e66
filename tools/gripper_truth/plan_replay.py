#!/usr/bin/env python3
"""Dynamic ground truth of a whole pregrasp plan: both arms' Robotiq 2F-85 grippers (MuJoCo Menagerie), each a
free body welded to a mocap body that follows the planned flange pose (FK of the arm's joints, linear in joint
space between the plan points), the part a free body on the table. All four segments on one time line
(sup1, close the pinch; rot; mas1, close the master's power grasp; the supportive gripper opens; sup2, close its
power grasp), then both grippers rise 50 mm together and hold 1 s.

    pip install mujoco numpy trimesh scipy
    python3 tools/gripper_truth/plan_replay.py --menagerie <menagerie> plan1.json [plan2.json ...]

Every plan (plan 0 of each file unless --plan-index) is run once per power force (--power-force, default the
plan's physics.grip_force_recommended, and the 2F-85's maximum 235 N). Writes
crates/physics/data/replay_truth/plan_replay_2f85.{json,csv} (atomically, keys sorted, floats rounded).
The replay itself is the Python package's (python/pregrasp/sim: `pregrasp.simulate`), loaded from the source
tree without the native extension; this script adds the Menagerie source, the FK check against `pregrasp kin fk`,
trimesh's convex hulls of the pieces (as the tables were made) and the tables.
Model and columns: tools/gripper_truth/README.md, section "Replay of the whole plan".
"""
import argparse
import datetime
import importlib.util
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

sys.path.insert(0, str(Path(__file__).resolve().parent))
from source import MODEL_DIR, MODEL_XML, load_source  # noqa: E402
from tables import csv_text, dump_json, write_atomic  # noqa: E402

REPO_ROOT = Path(__file__).resolve().parents[2]
OUT_DIR = REPO_ROOT / "crates/physics/data/replay_truth"
SCRIPT = "tools/gripper_truth/plan_replay.py"
DEFAULT_PREGRASP = REPO_ROOT / "target/release/pregrasp"
SIM_DIR = REPO_ROOT / "python/pregrasp/sim"


def load_sim():
    """python/pregrasp/sim as the package `pregrasp_sim` (numpy and mujoco only; no native extension needed)."""
    if "pregrasp_sim" not in sys.modules:
        spec = importlib.util.spec_from_file_location("pregrasp_sim", SIM_DIR / "__init__.py",
                                                      submodule_search_locations=[str(SIM_DIR)])
        mod = importlib.util.module_from_spec(spec)
        sys.modules["pregrasp_sim"] = mod
        spec.loader.exec_module(mod)
    return sys.modules["pregrasp_sim"]


load_sim()
from pregrasp_sim import part as sim_part  # noqa: E402
from pregrasp_sim.geometry import dh_fk, pose_T, rot_angle  # noqa: E402
from pregrasp_sim.run import (CAGED_MARGIN, CAL_A, CAL_B, F_MAX, N_CORRECT, T_HOLD, T_LIFT, T_OPEN,  # noqa: E402
                              T_RAMP, T_SETTLE, T_SPRING, T_WINDOW, run_plan, segment_forces)
from pregrasp_sim.scene import PAD_TORSION_RADIUS, PlanScene  # noqa: E402
from pregrasp_sim.verdict import LIFT, THRESHOLDS  # noqa: E402


def resolve_mesh(plan_path, mesh_rel, mesh_root):
    for base in ([Path(mesh_root)] if mesh_root else []) + [Path.cwd(), REPO_ROOT, Path(plan_path).resolve().parent]:
        p = base / mesh_rel
        if p.is_file():
            return p
    sys.exit(f"{plan_path}: mesh {mesh_rel} not found (use --mesh-root)")


def fk_check(pregrasp, model, q):
    """Largest difference (m, rad) between dh_fk and `pregrasp kin fk` at q."""
    out = subprocess.run([str(pregrasp), "kin", "fk", *[repr(float(v)) for v in q], "--model", model, "--json"],
                         capture_output=True, text=True, check=True)
    T = pose_T(json.loads(out.stdout))
    M = dh_fk(model, q)
    return float(np.linalg.norm(T[:3, 3] - M[:3, 3])), rot_angle(T[:3, :3], M[:3, :3])


def hull_meshes(pieces):
    """Each piece (vertices) as trimesh's convex hull (scipy's qhull): the triangulation the tables were made with.
    pregrasp.simulate triangulates the prisms itself (numpy only); MuJoCo's mesh frames then differ by ~1e-16 m."""
    out = []
    for P in pieces:
        h = trimesh.Trimesh(P).convex_hull
        out.append((np.asarray(h.vertices), np.asarray(h.faces)))
    return out


def part_pieces(plan_path, doc, mesh_root):
    """The part of plan file `doc` (read from `plan_path`): its triangles (scaled), its convex pieces as trimesh's
    hulls (the exact decomposition of an extrusion, else CoACD's) and the decomposition's info."""
    tri = sim_part.read_stl(resolve_mesh(plan_path, doc["object"]["mesh"], mesh_root))
    tri = tri * doc["object"].get("scale", 1.0)
    try:
        pieces, dinfo = sim_part.decompose_extrusion(tri)
    except ValueError:
        meshes, dinfo = sim_part.decompose_coacd(tri)
        pieces = [V for V, _ in meshes]
    return tri, hull_meshes(pieces), dinfo


def replay_file(plan_path, plan_indices, power_forces, src, a, log):
    """Rows of plan_path's plans `plan_indices` (those present), each once per power force: `power_forces(pinch)`
    gives the forces for a plan whose pinch force is `pinch` (N). `a`: pregrasp, mesh_root, slow, dt, noslip."""
    rows = []
    doc = json.load(open(plan_path))
    if doc.get("status") != "planned":
        log(f"{plan_path}: status {doc.get('status')}, skipped")
        return rows
    example = Path(doc["scene"]["file"]).stem
    tri, meshes, dinfo = part_pieces(plan_path, doc, a.mesh_root)
    for k in plan_indices:
        if k >= len(doc["plans"]):
            continue
        plan = doc["plans"][k]
        ph = plan.get("physics") or {}
        mass = doc["object"].get("mass") or ph.get("mass")
        mp = sim_part.mass_properties(tri, mass)
        pinch = ph.get("grip_force_recommended", 20.0)
        for pf in power_forces(pinch):
            t0 = time.time()
            log(f"{example} plan {k}: mass {mass} kg, {dinfo['pieces']} pieces, pinch {pinch} N, power {pf} N")
            sc = PlanScene(src / MODEL_XML, doc, meshes, mp, ph.get("mu_pad", 0.8), ph.get("mu_support", 0.4),
                           a.dt, a.noslip, pad_condim=a.pads_condim)
            force, from_plan = segment_forces(plan, pinch, pf)
            rec, _ = run_plan(sc, doc, plan, force, lift=LIFT, slow=a.slow,
                              fk_check=lambda model, q: fk_check(a.pregrasp, model, q), log=log,
                              plan_path=plan_path)
            rec["grip_force_from_plan"] = from_plan
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
                  "pads_condim": a.pads_condim,
                  **({"pad_torsion_radius": PAD_TORSION_RADIUS} if a.pads_condim == 4 else {}),
                  "time_scaling": a.slow, "force_calibration": [CAL_A, CAL_B],
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
    ap.add_argument("--pads-condim", type=int, choices=[3, 4], default=3,
                    help="pad contacts: 3 (no torsional friction at a point; the truth tables) or 4 (torsional "
                         "friction mu_pad x 11.6 mm, as the rotation replay's condim 4)")
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
