#!/usr/bin/env python3
"""Copy the collision meshes of data/robots/{fr3,xarm6}.urdf from the pinned source commits.

usage: meshes.py --franka REPO --xarm REPO [--robots DIR] [--check]

  --franka  a clone of frankaemika/franka_description (work tree or bare)
  --xarm    a clone of xArm-Developer/xarm_ros2 (work tree or bare)
  --robots  the folder holding the URDFs (default: data/robots/ at the repository root)
  --check   copy nothing: exit 1 if a copied mesh is missing or differs from its commit

Reads every `<collision><geometry><mesh filename="package://PKG/PATH"/>` of the URDFs named in
MESH_ROBOTS and writes the blob `PATH` of package `PKG` at the commit pinned in derive.py's
SOURCES table to `<robots>/meshes/PKG/PATH`, so `package://` resolves against
`<robots>/meshes` (a folder holding the package folders). Only collision meshes are copied:
visual meshes are not needed for collision geometry (the xArm6 description uses its visual
meshes as collision meshes; those are the ones copied). Primitive collision geometry (box,
cylinder, sphere) needs no file. The licence texts of the sources are in <robots>/licenses/
(written by derive.py). Output is byte-identical to the blobs; files are written atomically.
"""
import argparse
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from derive import ROOT, SOURCES, git, resolve_commit  # noqa: E402

# URDF file -> key of SOURCES that provides its meshes
MESH_ROBOTS = {"fr3.urdf": "franka", "xarm6.urdf": "xarm"}

# A collision mesh larger than this is reported (a collision mesh is normally a few kB).
LARGE = 200_000


def collision_meshes(urdf_path):
    """`(link, package, path)` of every collision mesh of the URDF, file order, no repeats."""
    seen, out = set(), []
    for link in ET.parse(urdf_path).getroot().iter("link"):
        for mesh in link.findall("./collision/geometry/mesh"):
            name = mesh.get("filename", "")
            if not name.startswith("package://"):
                sys.exit(f"{urdf_path}: link {link.get('name')}: {name!r} is not package://")
            pkg, path = name[len("package://"):].split("/", 1)
            if (pkg, path) not in seen:
                seen.add((pkg, path))
                out.append((link.get("name"), pkg, path))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    for key in sorted(set(MESH_ROBOTS.values())):
        ap.add_argument("--" + key, required=True, metavar="REPO")
    ap.add_argument("--robots", default=os.path.join(ROOT, "data", "robots"))
    ap.add_argument("--check", action="store_true")
    opts = ap.parse_args()
    out_root = os.path.join(opts.robots, "meshes")
    bad, total = 0, 0
    for urdf, key in MESH_ROBOTS.items():
        name, pinned, _lic, packages = SOURCES[key]
        repo = getattr(opts, key)
        commit = resolve_commit(repo, pinned, False)
        for link, pkg, path in collision_meshes(os.path.join(opts.robots, urdf)):
            if pkg not in packages:
                sys.exit(f"{urdf}: link {link}: package {pkg} is not one of {name}'s")
            inside = os.path.join(packages[pkg], path) if packages[pkg] else path
            blob = git(repo, "show", f"{commit}:{inside}")
            dest = os.path.join(out_root, pkg, path)
            total += len(blob)
            note = "  (large for a collision mesh)" if len(blob) > LARGE else ""
            if opts.check:
                ok = os.path.exists(dest) and open(dest, "rb").read() == blob
                bad += not ok
                print(f"{'ok ' if ok else 'BAD'} {dest}")
                continue
            os.makedirs(os.path.dirname(dest), exist_ok=True)
            with open(dest + ".tmp", "wb") as f:
                f.write(blob)
            os.replace(dest + ".tmp", dest)
            print(f"{os.path.relpath(dest, opts.robots)}: {len(blob)} bytes ({link}){note}")
    print(f"total: {total} bytes")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    try:
        main()
    except subprocess.CalledProcessError as e:
        sys.exit(f"git failed: {' '.join(e.cmd)}: {e.stderr.decode().strip()}")
