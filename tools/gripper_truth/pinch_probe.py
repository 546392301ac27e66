#!/usr/bin/env python3
"""Scenes that probe the twist rule (pregrasp_physics::twist): generated parts with the pinch G_s moved to a chosen
fraction of the centre of mass' distance from the intended axis, on the bar there nearest the centre of mass, its pads
facing along the axis.

The generated scenes pinch the far rail, about twice as far from the axis as the centre of mass, with the pads facing
across the axis: no twist to hold. These scenes make the part hang from the pinch by 10-40 % of that distance, so the
replay (plan_sweep.py) can say what a pinch that must hold the part on its pads' twist does:

    target/release/pregrasp example generate parts --per-family 5 --first-seed 1
    python3 tools/gripper_truth/pinch_probe.py parts probes --parts ladder_1 ladder_2 ladder_3 \\
        ladder_4 ladder_5 --fractions 0.6 0.7 0.8 0.9
    python3 tools/gripper_truth/plan_sweep.py --menagerie <menagerie> --name plan_replay_pinch_probe_2f85 \\
        --mesh-root probes probes

Each probe `pinch<NN>_<part>.toml` is the part's scene with `support` at `y = fraction * y_com` (object frame: the
intended axis is the object's x axis) on the bar crossing that line nearest the centre of mass (a ladder's middle
rung), the fingers closing across it (along x), at the height the scene pinches, and `[physics] max_twist_arm = 1` so
that the planner does not refuse it. A pinch on an end bar would hold the part's twist about the line to the axis'
far end as well: only parts with a bar near the centre of mass probe the hang alone. The probes are kept in
crates/planner/tests/fixtures/pinch_probe/ for the test that reads the replay's table
(crates/planner/tests/twist_truth.rs).
"""
import argparse
import re
import sys
import tomllib
from pathlib import Path

import trimesh

sys.path.insert(0, str(Path(__file__).resolve().parent))
from tables import write_atomic  # noqa: E402

SUPPORT_LINE = re.compile(r"^support = \{.*\}$", re.MULTILINE)


def bar_across(mesh, y, z):
    """The centre x of the bar the line `(x, y, z)`, x running, crosses nearest the centre of mass: the material
    intervals along it 10-80 mm wide (a pinch's reach), `None` if there is none."""
    # The mesh cut by the plane y = const: segments in it; where they cross the height z.
    segments = trimesh.intersections.mesh_plane(mesh, plane_normal=[0.0, 1.0, 0.0], plane_origin=[0.0, y, 0.0])
    xs = []
    for (x0, _, z0), (x1, _, z1) in segments:
        if (z0 - z) * (z1 - z) < 0.0:
            xs.append(x0 + (x1 - x0) * (z - z0) / (z1 - z0))
    xs.sort()
    bars = [(a + b) / 2 for a, b in zip(xs[::2], xs[1::2]) if 0.010 <= b - a <= 0.080]
    x_com = float(mesh.center_mass[0])
    return min(bars, key=lambda x: abs(x - x_com), default=None)


def probe_text(text, mesh_path, fraction):
    """The scene `text` with its pinch moved to `fraction` of the centre of mass' distance from the axis, on the bar
    there nearest the centre of mass; `None` if no bar crosses that line."""
    scene = tomllib.loads(text)
    mesh = trimesh.load(mesh_path, force="mesh")
    if not mesh.is_watertight:
        raise SystemExit(f"{mesh_path}: not a closed surface, no centre of mass")
    _, y_com, z_com = (float(c) for c in mesh.center_mass)
    x_bar = bar_across(mesh, fraction * y_com, z_com)
    if x_bar is None:
        return None
    z_pinch = scene["grasps"]["support"]["xyz"][2]
    support = (f"support = {{ xyz = [{x_bar:.4f}, {fraction * y_com:.4f}, {z_pinch:.4f}], "
               f"rpy_deg = [180.00, 0.00, 0.00] }}")
    if len(SUPPORT_LINE.findall(text)) != 1:
        raise SystemExit("the scene has no single `support = { ... }` line")
    text = SUPPORT_LINE.sub(support, text)
    note = f"# Pinch probe (tools/gripper_truth/pinch_probe.py): G_s at {fraction:.2f} of y_com = {y_com:.4f} m.\n"
    return note + text.rstrip("\n") + "\n\n[physics]\nmax_twist_arm = 1\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", type=Path, help="directory of generated scenes (pregrasp example generate)")
    ap.add_argument("out", type=Path, help="directory for the probe scenes (its meshes/ links to the scenes')")
    ap.add_argument("--parts", nargs="+", required=True, help="scene stems, e.g. frame_1")
    ap.add_argument("--fractions", nargs="+", type=float, required=True)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    meshes = args.out / "meshes"
    if not meshes.exists():
        meshes.symlink_to((args.scenes / "meshes").resolve())
    for part in args.parts:
        text = (args.scenes / f"{part}.toml").read_text()
        mesh = args.scenes / tomllib.loads(text)["object"]["mesh"]
        for fraction in args.fractions:
            probe = probe_text(text, mesh, fraction)
            if probe is None:
                print(f"{part}: no bar crosses y = {fraction:.2f} y_com", file=sys.stderr)
                continue
            out = args.out / f"pinch{round(fraction * 100):02d}_{part}.toml"
            write_atomic(out, probe)
            print(out)


if __name__ == "__main__":
    sys.exit(main())
