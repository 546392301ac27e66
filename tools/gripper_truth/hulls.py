#!/usr/bin/env python3
"""The collision geometry MuJoCo closes the Menagerie 2F-85 with, as our closing model's test needs it.

    pip install numpy scipy trimesh
    python3 tools/gripper_truth/hulls.py <menagerie git dir or checkout>

MuJoCo collides a mesh geom as its convex hull, and the 2F-85's pads as two boxes. This writes, for
the +x finger (Menagerie `right_*`), the hull vertices of the collision meshes of the driver, coupler,
spring link and follower and the corners of the two pad boxes, in our link frames L (the body's
origin, G's axes at the zero pose: a body-frame vertex (x, y, z) is (y, -x, z) in L, the base being
turned -90 deg about z), to crates/robot/data/gripper_truth/menagerie_2f85_collision.json. Only
derived numbers (hull vertices) are written, no mesh. Deterministic; written atomically.
"""
import hashlib
import io
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import trimesh
from scipy.spatial import ConvexHull

REPO_ROOT = Path(__file__).resolve().parents[2]
OUT = REPO_ROOT / "crates/robot/data/gripper_truth/menagerie_2f85_collision.json"
LINKS = ["driver", "coupler", "spring_link", "follower"]
# 2f85.xml: class pad_box1 / pad_box2 (pos, half sizes) in the pad body frame
PAD_BOXES = [((0.0, -0.0026, 0.028125), (0.011, 0.004, 0.009375)),
             ((0.0, -0.0026, 0.009375), (0.011, 0.004, 0.009375))]


def read(source, path):
    src = Path(source)
    if (src / path).is_file():
        return (src / path).read_bytes()
    return subprocess.run(["git", "--git-dir", str(src), "show", f"HEAD:{path}"],
                          check=True, capture_output=True).stdout


def commit(source):
    try:
        return subprocess.run(["git", "--git-dir", str(source), "rev-parse", "HEAD"], check=True,
                              capture_output=True, text=True).stdout.strip()
    except subprocess.CalledProcessError:
        return None


def to_link(v):
    v = np.asarray(v, dtype=float)
    return np.stack([v[:, 1], -v[:, 0], v[:, 2]], axis=1)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    source = sys.argv[1]
    out = {"generator": "tools/gripper_truth/hulls.py",
           "source": {"repo": "https://github.com/google-deepmind/mujoco_menagerie",
                      "commit": commit(source), "sha256": {}},
           "frame": "link frame L: the Menagerie body's origin with G's axes at the zero pose (all "
                    "joint angles 0); the +x finger (right_*); mirror x -> -x for the other",
           "links": {}}
    for name in LINKS:
        raw = read(source, f"robotiq_2f85/assets/{name}.stl")
        out["source"]["sha256"][f"{name}.stl"] = hashlib.sha256(raw).hexdigest()
        mesh = trimesh.load(io.BytesIO(raw), file_type="stl")
        v = np.asarray(mesh.vertices) * 0.001
        hull = v[ConvexHull(v).vertices]
        pts = to_link(hull)
        out["links"][name] = [sorted([round(float(x), 7) for x in p] for p in pts)]
    pads = []
    for pos, half in PAD_BOXES:
        corners = [[pos[0] + sx * half[0], pos[1] + sy * half[1], pos[2] + sz * half[2]]
                   for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
        pads.append(sorted([round(float(x), 7) for x in p] for p in to_link(corners)))
    out["links"]["pad"] = pads
    text = json.dumps(out, indent=1, sort_keys=True) + "\n"
    fd, tmp = tempfile.mkstemp(dir=OUT.parent, prefix=".hulls-")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.chmod(tmp, 0o644)
    os.replace(tmp, OUT)
    for name, pieces in out["links"].items():
        print(name, [len(p) for p in pieces])


if __name__ == "__main__":
    main()
