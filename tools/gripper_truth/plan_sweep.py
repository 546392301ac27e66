#!/usr/bin/env python3
"""The whole-plan replay (plan_replay.py) as a sweep over a directory of scenes: each scene is planned with the
pregrasp binary (`pregrasp plan`), plans 0 and 1 (when present) are replayed with the power grasps at one force
(default 235 N), and every row gets its verdict (python/pregrasp/sim/verdict.py). A scene that plans nothing is a
row too, verdict "no plan".

    cargo build --release -p pregrasp
    target/release/pregrasp example generate parts --per-family 5 --first-seed 1
    target/release/pregrasp example write parts
    python3 tools/gripper_truth/plan_sweep.py --menagerie <menagerie> parts

Writes crates/physics/data/replay_truth/plan_replay_generated_2f85.{json,csv} (atomically, keys sorted, floats
rounded) with provenance (Menagerie commit, mujoco version, pregrasp commit, the parts' families and seeds).
README: tools/gripper_truth/README.md, section "Replay of the whole plan", "Sweep over generated parts".
"""
import argparse
import hashlib
import json
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from plan_replay import REPO_ROOT, header, model_args, replay_file  # noqa: E402
from source import load_source  # noqa: E402
from tables import csv_text, dump_json, write_atomic  # noqa: E402

SCRIPT = "tools/gripper_truth/plan_sweep.py"
EXIT_PLANNED, EXIT_NO_PLAN = 0, 2
# crates/examples/src/parts/kit.rs, Family::name: the six families and the six hard ones (`--hard`)
FAMILIES = ("frame", "ladder", "u_frame", "panel", "stool", "h_frame",
            "t_junction", "l_corner", "hand_hole", "parallel_bars", "chamfered", "thin_rungs")


def family_seed(stem):
    """(family, seed) of a generated part's stem `<family>_<seed>`; ("example", None) for any other scene."""
    m = re.fullmatch(r"(.+)_(\d+)", stem)
    if m and m.group(1) in FAMILIES:
        return m.group(1), int(m.group(2))
    return "example", None


def sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def scene_mesh(scene):
    """The mesh path a scene file names (`[object] mesh`), relative to the scene."""
    text = scene.read_text()
    m = re.search(r'^\s*mesh\s*=\s*"([^"]+)"', text[text.index("[object]"):], re.M)
    return scene.parent / m.group(1)


def git_commit():
    head = subprocess.run(["git", "-C", str(REPO_ROOT), "rev-parse", "HEAD"], capture_output=True, text=True)
    dirty = subprocess.run(["git", "-C", str(REPO_ROOT), "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True)
    return {"commit": head.stdout.strip() or None, "worktree_modified": bool(dirty.stdout.strip())}


def plan_scene(pregrasp, scene, out, max_plans):
    """`pregrasp plan scene -o out`: (exit code, the plan file or None, planner wall seconds)."""
    t0 = time.time()
    r = subprocess.run([str(pregrasp), "plan", str(scene), "-o", str(out), "--quiet", "--max-plans", str(max_plans),
                        "--threads", "1"], capture_output=True, text=True)
    doc = json.loads(out.read_text()) if out.is_file() else None
    return r.returncode, doc, time.time() - t0, r.stderr.strip()


def row_order(r):
    """A table's row order: by family, seed, part, then plan (a part without a plan first)."""
    return r["family"], r["seed"] if r["seed"] is not None else -1, r["part"], -1 if r["plan"] is None else r["plan"]


def spliced(table, head, rows, parts):
    """The table `table` with the rows of `parts` replaced by `rows` (this replay's, header `head`): its other
    rows and header kept, this replay recorded in the header's `replayed_again` (date, pregrasp commit and binary,
    the parts, the arguments), in `row_order`."""
    old = json.loads(table.read_text())
    missing = parts - {r["part"] for r in old["rows"]}
    if missing:
        sys.exit(f"{table}: no rows of {sorted(missing)} to replace (--into replays scenes the table has)")
    for k in ("source", "mujoco_version", "model", "verdict", "power_force", "plan_index"):
        if old.get(k) != head.get(k):
            sys.exit(f"{table}: its {k!r} differs from this replay's; replay the whole table instead")
    kept = [r for r in old.pop("rows") if r["part"] not in parts]
    again = old.get("replayed_again", []) + [{"date": head["date"], "pregrasp": head["pregrasp"],
                                               "parts": sorted(parts), "args": head["args"]}]
    old["replayed_again"] = again
    merged = kept + rows
    merged.sort(key=row_order)
    return old, merged


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", help="a directory of scene files (*.toml)")
    model_args(ap)
    ap.add_argument("--plan-index", type=int, nargs="*", default=[0, 1])
    ap.add_argument("--power-force", type=float, default=235.0, help="N, both power grasps' force (one pass)")
    ap.add_argument("--name", default="plan_replay_generated_2f85")
    ap.add_argument("--only", nargs="*", default=None, help="only these scene stems")
    ap.add_argument("--into", action="store_true",
                    help="replace the rows of the scenes replayed in the existing table --name, keeping its other "
                         "rows as they were replayed, and record this replay in its header's 'replayed_again'")
    a = ap.parse_args()
    t_start = time.time()
    log = lambda s: print(s, flush=True)
    scenes = sorted(Path(a.scenes).glob("*.toml"))
    if a.only is not None:
        scenes = [s for s in scenes if s.stem in a.only]
    if not scenes:
        sys.exit(f"{a.scenes}: no scene files")
    rows, seeds = [], {}
    with tempfile.TemporaryDirectory(prefix="plan_sweep_") as tmp:
        src, prov = load_source(a.menagerie, a.rev, tmp)
        for scene in scenes:
            family, seed = family_seed(scene.stem)
            seeds.setdefault(family, []).append(seed if seed is not None else scene.stem)
            part = {"part": scene.stem, "family": family, "seed": seed, "scene_sha256": sha256(scene),
                    "mesh_sha256": sha256(scene_mesh(scene))}
            plan_path = Path(tmp) / f"{scene.stem}.plan.json"
            code, doc, wall, err = plan_scene(a.pregrasp, scene, plan_path, max(a.plan_index) + 1)
            n_plans = len(doc["plans"]) if doc and doc.get("status") == "planned" else 0
            part.update({"planner_exit": code, "plans_emitted": n_plans})
            log(f"{scene.stem}: pregrasp plan exit {code}, {n_plans} plan(s), {wall:.1f} s")
            if code != EXIT_PLANNED or n_plans == 0:
                # The planner's error names the scene by the path it was given: keep its file name only,
                # as the header keeps the arguments' (the table holds no path of this machine).
                reason = (doc or {}).get("reason") or (err.replace(str(scene), scene.name).splitlines() or [None])[-1]
                bad = "no plan" if code == EXIT_NO_PLAN else "error"
                rows.append({**part, "example": scene.stem, "plan": None, "verdict": bad, "carried": False,
                             "failures": [bad.replace(" ", "_")], "reason": reason})
                continue
            for r in replay_file(plan_path, a.plan_index, lambda pinch: [a.power_force], src, a, log):
                rows.append({**part, **r})
    rows.sort(key=row_order)
    head = header(a, prov)
    head.update({"generator": SCRIPT, "pregrasp": {**git_commit(), "binary_sha256": sha256(a.pregrasp)},
                 "seeds": {f: sorted(v, key=str) for f, v in seeds.items()}, "scenes": len(scenes),
                 "power_force": a.power_force, "plan_index": a.plan_index})
    out = Path(a.out)
    if a.into:
        head, rows = spliced(out / f"{a.name}.json", head, rows, {s.stem for s in scenes})
    write_atomic(out / f"{a.name}.json", dump_json(head, rows))
    write_atomic(out / f"{a.name}.csv", csv_text(rows))
    log(f"wrote {out / a.name}.{{json,csv}}: {len(rows)} rows, {time.time() - t_start:.1f} s")


if __name__ == "__main__":
    main()
