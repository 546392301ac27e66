#!/usr/bin/env python3
"""Where the master's push comes from: the whole-plan replay (plan_replay.py's `run_plan`, unchanged) with the
part's motion during `mas1` measured in the master's flange frame G (x the closing axis, z the approach).

For plan 0 of each plan file it prints, along G's axes:
- `sag`: where the part lies when the master's fingers start to close, against the planned part (the point of
  the part planned at z = 0.16 m in G; + is away from the palm), after the rotation and the master's approach;
- `end`: the same once the closing has ended, and `pull` = sag.z − end.z (how far the closing pulled the bar in);
- `palm`: the least distance (m) from the master's palm geoms (`mas_base`, `mas_base_mount`) to the part then
  (MuJoCo's `mj_geomDistance`, negative inside);
- `at_G_s`: the planned support grasp point of the part against the supportive flange at the end of `rot`
  (G_s's own frame), with the supportive flange's weld error and how far its pads moved along z in `rot`;
- the replay's own `mas1_close.part_moved` (the centre of mass, as the tables have it) and kind.

    python3 tools/gripper_truth/push_probe.py --menagerie <menagerie> --mesh-root <scenes> plan1.json ...

Nothing is written; docs/physics.md ("What is left of the push") quotes its output.
"""
import argparse
import json
import sys
import tempfile
from pathlib import Path

import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import plan_replay as pr  # noqa: E402
from source import load_source  # noqa: E402
from pregrasp_sim import part as sim_part  # noqa: E402
from pregrasp_sim.geometry import T_of, dh_fk, inv, pose_T  # noqa: E402
from pregrasp_sim.run import F_MAX, run_plan, segment_forces  # noqa: E402
from pregrasp_sim.scene import PAD_POINT, PlanScene  # noqa: E402

PROBE_Z = 0.16  # m: the point of G where the part is followed (between palm and fingertips)


def probe(plan_path, src, mesh_root):
    doc = json.load(open(plan_path))
    tri, meshes, _ = pr.part_pieces(plan_path, doc, mesh_root)
    plan = doc["plans"][0]
    ph = plan.get("physics") or {}
    mp = sim_part.mass_properties(tri, doc["object"].get("mass") or ph.get("mass"))
    sc = PlanScene(src / pr.MODEL_XML, doc, meshes, mp, ph.get("mu_pad", 0.8),
                   ph.get("mu_support", 0.4), 0.001, 10)
    m = sc.m
    body = lambda n: mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, n)
    palm = [g for g in range(m.ngeom) if m.geom_bodyid[g] in (body("mas_base"), body("mas_base_mount"))
            and (m.geom_contype[g] or m.geom_conaffinity[g])]
    seen = {"mas": [], "sup": []}
    contacts = sc.contacts

    def watched(arm):
        # The replay asks for the contacts at every kind() and force sample: keep what the probe needs then.
        d = sc.d
        if arm == "mas":
            ft = np.zeros(6)
            dist = min(mujoco.mj_geomDistance(m, d, g, p, 0.05, ft) for g in palm for p in sc.part_geoms)
            seen["mas"].append((d.time, dist))
        else:
            target = T_of(d.mocap_pos[sc.g["sup"]["mocap"]], d.mocap_quat[sc.g["sup"]["mocap"]])
            pads = [(inv(target) @ T_of(d.xpos[b], d.xquat[b]) @ np.r_[PAD_POINT, 1])[2]
                    for b in sc.g["sup"]["pad_body"].values()]
            seen["sup"].append((d.time, inv(target) @ sc.flange_actual("sup"), float(np.mean(pads)), sc.part_T()))
        return contacts(arm)
    sc.contacts = watched
    force, _ = segment_forces(plan, ph.get("grip_force_recommended", 20.0), F_MAX)
    rec, trace = run_plan(sc, doc, plan, force)
    robots = {r["name"]: r for r in doc["robots"]}
    segs = {s["name"]: s for s in plan["segments"]}
    flange = lambda n, seg: pose_T(robots[n]["base"]) @ dh_fk(robots[n]["model"], np.array(seg["points"][-1]["q"]))
    F = flange(plan["master"], segs["mas1"])
    T_plan = pose_T(segs["rot"]["points"][-1]["object_pose"])
    p = np.array([0.0, 0.0, PROBE_Z, 1.0])
    T_before, T_after = trace["mas1"]
    sag = (inv(F) @ T_before @ inv(T_plan) @ F @ p)[:3] - p[:3]
    end = (inv(F) @ T_after @ inv(T_plan) @ F @ p)[:3] - p[:3]
    # The supportive side at the end of `rot`: the first contacts call after the rotation's long gap.
    ts = [s[0] for s in seen["sup"]]
    i = next(k for k in range(1, len(ts)) if ts[k] - ts[k - 1] > 0.5)
    _, weld, pad_z, T_rot = seen["sup"][i]
    Fs = flange(plan["supportive"], segs["rot"])
    gs = np.r_[pose_T(doc["grasps"]["support"])[:3, 3], 1.0]
    at_gs = (inv(Fs) @ T_rot @ gs)[:3] - (inv(Fs) @ T_plan @ gs)[:3]
    names = [r["name"] for r in doc["robots"]]
    seated = (doc["grasps"].get("seated") or [0.0, 0.0])[names.index(plan["master"])]
    mm = lambda v: "[" + " ".join(f"{1e3 * x:+.2f}" for x in v) + "]"
    print(f"{Path(plan_path).stem}: seated {1e3 * seated:.2f} mm; sag {mm(sag)} end {mm(end)} pull "
          f"{1e3 * (sag[2] - end[2]):.2f} mm; palm {1e3 * seen['mas'][-2][1]:+.2f} mm; at_G_s {mm(at_gs)} (weld "
          f"{mm(weld[:3, 3])}, pads z {1e3 * (pad_z - seen['sup'][i - 1][2]):+.2f}); part_moved "
          f"{1e3 * rec['mas1_close']['part_moved']:.2f} mm, {rec['mas1_close']['kind']}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("plans", nargs="+")
    ap.add_argument("--menagerie", required=True)
    ap.add_argument("--rev", default="HEAD")
    ap.add_argument("--mesh-root", default=None)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="push_probe_") as tmp:
        src, _ = load_source(a.menagerie, a.rev, tmp)
        for plan_path in a.plans:
            probe(plan_path, src, a.mesh_root)


if __name__ == "__main__":
    main()
