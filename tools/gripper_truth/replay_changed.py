#!/usr/bin/env python3
"""After a change of the planner: the scenes whose plans it changed, replayed whole again into the tables that
hold them (plan_sweep.py --into), every other row kept as it was replayed.

    python3 tools/gripper_truth/replay_changed.py --old OLD_BIN --new NEW_BIN --menagerie <menagerie> \\
        six hard [--dry-run] [--jobs 2]

Each directory holds scene files (*.toml; `pregrasp example generate DIR --per-family 90 --first-seed 1`, with
and without --hard, makes the parts of the tables). Every scene is planned by both binaries as plan_sweep.py plans
(`--max-plans 2 --threads 1`); a scene plans differently where the exit code or the plan file (without
`timing_ms` and `scene`, which hold times and paths) differs. A table of crates/physics/data/replay_truth made
by plan_sweep.py holds a scene where one of its rows has the scene file's SHA-256: tables of edited scenes
(other arms, other planner settings) hold none and are left alone, and so are the experiments' tables, the same
scenes planned by a planner built otherwise (`EXPERIMENTS`). Each table holding changed scenes is
replayed again for those scenes with the new binary and the table's own replay settings (pads, time step,
no-slip iterations, time scaling, force, plan indices). Prints the changed scenes and, per table, the parts.
A run stopped part-way resumes: a table whose `replayed_again` already holds those parts replayed by the new binary
(the same SHA-256) is not replayed again.

With --all (no --old), every scene of the directories that a table holds is replayed with the new binary: tables
last replayed by older planners (the other arms' scenes, `pregrasp example generate --arm ARM` run from the
repository's root) brought up to it.

    pregrasp example generate ur10e_hard --hard --per-family 90 --first-seed 1 --arm ur10e
    python3 tools/gripper_truth/replay_changed.py --all --new NEW_BIN --menagerie <menagerie> ur10e_hard
"""
import argparse
import hashlib
import json
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from plan_replay import OUT_DIR  # noqa: E402

SWEEP = "tools/gripper_truth/plan_sweep.py"
# Tables of experiments: the same scenes planned by a planner built otherwise (docs/physics.md says which), kept as
# they were; replaying them with today's planner would make them ordinary rows.
EXPERIMENTS = ("_seat_all_", "_seat_thick_", "_wraps_", "_set_", "_twist_off_", "_pinch_seated_full_", "_pinch_probe_")


def sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def planned(binary, scene, out):
    """(exit code, the plan file without `timing_ms` and `scene`, or None)."""
    r = subprocess.run([str(binary), "plan", str(scene), "-o", str(out), "--quiet", "--max-plans", "2",
                        "--threads", "1"], capture_output=True, text=True)
    if not out.is_file():
        return r.returncode, None
    doc = json.loads(out.read_text())
    doc.pop("timing_ms", None)
    doc.pop("scene", None)
    return r.returncode, doc


def changed_scenes(old, new, scenes, jobs):
    """The scenes of `scenes` the two binaries plan differently."""
    with tempfile.TemporaryDirectory(prefix="replay_changed_") as tmp:
        def differs(k_scene):
            k, scene = k_scene
            a = planned(old, scene, Path(tmp) / f"{k}.old.json")
            b = planned(new, scene, Path(tmp) / f"{k}.new.json")
            return a != b
        with ThreadPoolExecutor(jobs) as pool:
            flags = list(pool.map(differs, enumerate(scenes)))
    return [s for s, f in zip(scenes, flags) if f]


def replay_args(table):
    """plan_sweep.py's arguments that reproduce `table`'s replay settings."""
    model = table["model"]
    return ["--pads-condim", str(model.get("pads_condim", 3)), "--dt", str(model["timestep"]),
            "--noslip", str(model["noslip_iterations"]), "--slow", str(model["time_scaling"]),
            "--power-force", str(table["power_force"]), "--plan-index", *map(str, table["plan_index"])]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dirs", nargs="+", help="directories of scene files (*.toml)")
    ap.add_argument("--old", help="the pregrasp binary before the change (not with --all)")
    ap.add_argument("--all", action="store_true",
                    help="replay every scene a table holds, whether or not the new binary plans it otherwise")
    ap.add_argument("--new", required=True, help="the pregrasp binary after it (it replays)")
    ap.add_argument("--menagerie", required=True)
    ap.add_argument("--tables", default="plan_replay_*.json", help="which tables to look in (a glob in their directory)")
    ap.add_argument("--jobs", type=int, default=2, help="scenes planned at once, tables replayed at once")
    ap.add_argument("--dry-run", action="store_true", help="list what would be replayed, replay nothing")
    a = ap.parse_args()
    if a.all == bool(a.old):
        ap.error("give exactly one of --old (replay the scenes NEW plans otherwise) and --all (replay every scene)")
    scenes = [s for d in a.dirs for s in sorted(Path(d).glob("*.toml"))]
    if not scenes:
        sys.exit(f"{', '.join(a.dirs)}: no scene files")
    if a.all:
        changed = scenes
    else:
        changed = changed_scenes(a.old, a.new, scenes, a.jobs)
        print(f"{len(changed)} of {len(scenes)} scenes plan differently", flush=True)
    by_sha = {sha256(s): s for s in changed}
    new_sha = sha256(a.new)
    runs = []
    for path in sorted(p for p in Path(OUT_DIR).glob(a.tables) if p.suffix == ".json"):
        table = json.loads(path.read_text())
        if table.get("generator") != SWEEP or any(e in path.name for e in EXPERIMENTS):
            continue
        hits = {}
        for row in table["rows"]:
            scene = by_sha.get(row.get("scene_sha256"))
            if scene is not None and scene.stem == row["part"]:
                hits.setdefault(scene.parent, set()).add(scene.stem)
        done = set()
        for again in table.get("replayed_again", []):
            if again.get("pregrasp", {}).get("binary_sha256") == new_sha:
                done.update(again.get("parts", []))
        for directory, parts in sorted(hits.items()):
            if parts <= done:
                print(f"{path.stem}: {' '.join(sorted(parts))} (replayed by this binary already)", flush=True)
                continue
            print(f"{path.stem}: {' '.join(sorted(parts))}", flush=True)
            runs.append([sys.executable, str(HERE / "plan_sweep.py"), str(directory), "--menagerie", a.menagerie,
                         "--pregrasp", str(a.new), "--name", path.stem, "--into", *replay_args(table),
                         "--only", *sorted(parts)])
    if a.dry_run or not runs:
        return
    # One table's replays run one after the other (each rewrites the table); different tables side by side.
    by_table = {}
    for cmd in runs:
        by_table.setdefault(cmd[cmd.index("--name") + 1], []).append(cmd)

    def replay(cmds):
        for cmd in cmds:
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                return f"{' '.join(cmd)}: exit {r.returncode}\n{r.stderr[-2000:]}"
            print(r.stdout.strip().splitlines()[-1], flush=True)
        return None

    with ThreadPoolExecutor(a.jobs) as pool:
        errors = [e for e in pool.map(replay, by_table.values()) if e]
    if errors:
        sys.exit("\n".join(errors))


if __name__ == "__main__":
    main()
