#!/usr/bin/env python3
"""Derive planner geometry from the UR and Robotiq ROS 2 descriptions.

usage: derive.py <Universal_Robots_ROS2_Description repo> <ros2_robotiq_gripper repo>
       derive.py <Universal_Robots_ROS2_Description repo> --ur-only
       derive.py <ros2_robotiq_gripper repo> --gripper-only
Repos may be bare git mirrors; files are read from HEAD with `git show`.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DATA = os.path.join(ROOT, "crates", "robot", "data")


def dump(path, obj):
    """Atomic write: the file is always either the old or the complete new version."""
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(obj, f, separators=(",", ":"))
        f.write("\n")
    os.replace(tmp, path)


def split_vertices(out):
    """The shapes (what the library loads at run time) apart from the mesh vertices they must
    contain (test data): `ur_links.json` without `hull`, and `ur_link_vertices.json` with only
    each link's `name`, `frame` and `hull`."""
    shapes = json.loads(json.dumps(out))
    vertices = {"generator": out.get("generator"), "source": out.get("source"), "models": {}}
    for model, m in shapes["models"].items():
        vertices["models"][model] = {"links": [
            {"name": l["name"], "frame": l["frame"], "hull": l.pop("hull")} for l in m["links"]]}
    return shapes, vertices


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    flags = [a for a in sys.argv[1:] if a.startswith("--")]
    # --ur-only needs only the UR repo, --gripper-only only the gripper repo
    if len(args) == 1 and "--ur-only" in flags:
        args = [args[0], None]
    elif len(args) == 1 and "--gripper-only" in flags:
        args = [None, args[0]]
    if len(args) != 2:
        sys.exit(__doc__)
    ur_repo, rq_repo = args
    os.makedirs(DATA, exist_ok=True)
    if "--gripper-only" not in flags:
        import derive_ur
        out, rep = derive_ur.run(ur_repo)
        shapes, vertices = split_vertices(out)
        dump(os.path.join(DATA, "ur_links.json"), shapes)
        dump(os.path.join(DATA, "ur_link_vertices.json"), vertices)
        txt = derive_ur.format_report(rep)
        print(txt)
        with open(os.path.join(os.path.dirname(__file__), "ur_report.md"), "w") as f:
            f.write(txt + "\n")
    if "--ur-only" not in flags:
        import derive_gripper
        out, txt = derive_gripper.run(rq_repo)
        dump(os.path.join(DATA, "robotiq_2f85.json"), out)
        print(txt)
        with open(os.path.join(os.path.dirname(__file__), "gripper_report.md"), "w") as f:
            f.write(txt + "\n")


if __name__ == "__main__":
    main()
