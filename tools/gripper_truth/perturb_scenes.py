#!/usr/bin/env python3
"""Scenes a user might write, drawn from the generated ones: each case takes a generated scene and moves what a
cell or a hand-written scene moves — the part shifted (±12 cm) or turned about the vertical, its mass (×0.05–20)
or scale (0.6–1.4), the support's height, the power grasps moved (±2 cm across, ±1 cm along the approach), the
power points' depth (±3 cm), the bases (±10 cm) or the arm model — a few at a time, drawn from `--seed`. The
planner must answer each with a plan, `no plan` and a reason, or one error naming the key (exit 0, 2 or 1), and
every plan it emits is held to the whole-plan replay like the generated parts' (plan_sweep.py).

    target/release/pregrasp example generate six --per-family 100
    target/release/pregrasp example generate hard --hard --per-family 100
    python3 tools/gripper_truth/perturb_scenes.py six hard --out perturbed --count 700 --seed 1
    python3 tools/gripper_truth/plan_sweep.py perturbed --menagerie <menagerie> --name plan_replay_perturbed_2f85

Each case is written as `<source stem>__p<k>.toml` (the mutations in its first comment line) with its mesh under
`meshes/`. Same sources, count and seed: the same files, byte for byte. README: tools/gripper_truth/README.md,
"Scenes a user might write".
"""
import argparse
import random
import re
import shutil
from pathlib import Path

MODELS = ["ur3e", "ur10e", "ur16e", "ur5"]


def num(x):
    return f"{x:.4f}"


def mutate(text, r):
    """`text` with a few of the mutations applied, and their names."""
    edits = []
    if r.random() < 0.5:
        dx, dy = r.uniform(-0.12, 0.12), r.uniform(-0.12, 0.12)

        def shift(m):
            x, y, z = [float(v) for v in m.group(1).split(",")]
            return f"pose = {{ xyz = [{num(x + dx)}, {num(y + dy)}, {num(z)}]"
        text = re.sub(r"pose = \{ xyz = \[([^\]]+)\]", shift, text, count=1)
        edits.append(f"shift {dx * 100:+.1f} {dy * 100:+.1f} cm")
    if r.random() < 0.5:
        yaw = r.uniform(-180, 180)
        text = re.sub(r"rpy_deg = \[0\.00, 0\.00, ([-0-9.]+)\] \}\nmass",
                      lambda m: f"rpy_deg = [0.00, 0.00, {yaw:.2f}] }}\nmass", text, count=1)
        edits.append(f"yaw {yaw:.0f}°")
    if r.random() < 0.4:
        k = r.choice([0.05, 0.3, 3, 8, 20])
        text = re.sub(r"mass = ([0-9.]+)", lambda m: f"mass = {float(m.group(1)) * k:.3f}", text, count=1)
        edits.append(f"mass ×{k}")
    if r.random() < 0.3:
        s = r.choice([0.6, 0.8, 1.2, 1.4])
        text = re.sub(r"scale = 1\.0", f"scale = {s}", text, count=1)
        edits.append(f"scale {s}")
    if r.random() < 0.3:
        h = r.uniform(-0.05, 0.2)
        text = re.sub(r"height = 0\.0", f"height = {h:.3f}", text, count=1)
        edits.append(f"support {h * 100:+.1f} cm")
    if r.random() < 0.3:
        def grasp(m):
            x, y, z = [float(v) for v in m.group(1).split(",")]
            return (f"{{ xyz = [{num(x + r.uniform(-.02, .02))}, {num(y + r.uniform(-.02, .02))}, "
                    f"{num(z + r.uniform(-.01, .01))}], rpy_deg = [180")
        text = re.sub(r"\{ xyz = \[([^\]]+)\], rpy_deg = \[180", grasp, text)
        edits.append("grasps moved")
    if r.random() < 0.3:
        text = re.sub(r"power_point_z = ([0-9.]+)",
                      lambda m: f"power_point_z = {float(m.group(1)) + r.uniform(-0.03, 0.03):.3f}", text)
        edits.append("power points moved")
    if r.random() < 0.3:
        def base(m):
            xyz = m.group(1).split(",")
            return "base = { xyz = [" + ", ".join(
                num(float(v) + r.uniform(-0.1, 0.1)) if i < 2 else v.strip() for i, v in enumerate(xyz)) + "] }"
        text = re.sub(r"base = \{ xyz = \[([^\]]+)\] \}", base, text)
        edits.append("bases moved")
    if r.random() < 0.2:
        model = r.choice(MODELS)
        text = text.replace('model = "ur5e"', f'model = "{model}"')
        edits.append(f"arms {model}")
    return text, edits


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sources", nargs="+", help="folders of generated scenes (`pregrasp example generate`)")
    ap.add_argument("--out", required=True)
    ap.add_argument("--count", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    r = random.Random(a.seed)
    sources = sorted(p for d in a.sources for p in Path(d).glob("*.toml"))
    if not sources:
        raise SystemExit(f"no scene files in {', '.join(a.sources)}")
    out = Path(a.out)
    (out / "meshes").mkdir(parents=True, exist_ok=True)
    written = 0
    for k in range(a.count):
        src = r.choice(sources)
        text, edits = mutate(src.read_text(), r)
        if not edits:
            continue
        mesh = re.search(r'^mesh = "([^"]+)"', text, re.M).group(1)
        shutil.copyfile(src.parent / mesh, out / mesh)
        head = f"# {src.stem} perturbed (tools/gripper_truth/perturb_scenes.py, seed {a.seed}, case {k}): " \
               f"{'; '.join(edits)}\n"
        (out / f"{src.stem}__p{k}.toml").write_text(head + text)
        written += 1
    print(f"wrote {written} scenes to {out}")


if __name__ == "__main__":
    main()
