#!/usr/bin/env python3
"""Regenerate the plain URDF files of data/robots/ from the vendors' xacro descriptions.

usage: derive.py --ur REPO --franka REPO --xarm REPO [--out DIR] [--allow-other-commit]

  --ur      a clone of UniversalRobots/Universal_Robots_ROS2_Description
  --franka  a clone of frankaemika/franka_description
  --xarm    a clone of xArm-Developer/xarm_ros2
  --out     output folder (default: data/robots/ at the repository root)

Each REPO may be a work tree or a bare clone. The files are read from the commit pinned in
SOURCES below (`git show`), never from the work tree, so the output depends on the commit
alone; a repository that lacks that commit is an error unless --allow-other-commit is given,
which reads its HEAD instead (and records that commit in the file header).

Only the xacro and YAML files are read: mesh files are not needed, and the generated URDFs keep
their mesh references as `package://<package>/...` strings. Needs Python >= 3.11 and the
`xacro` package from PyPI (`pip install xacro`, which brings PyYAML); `$(find pkg)` is resolved
to the extracted package folders by replacing xacro's ament lookup, so no ROS is needed.
The output is byte-identical for identical inputs.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

# name -> (repository, pinned commit, license, {ROS package: folder inside the repository})
SOURCES = {
    "ur": (
        "UniversalRobots/Universal_Robots_ROS2_Description",
        "2221ec0f720fb1af99339eb891639b499b62f1da",
        "BSD-3-Clause",
        {"ur_description": ""},
    ),
    "franka": (
        "frankaemika/franka_description",
        "b299b39d9692bfae795184df32a98ce7778d56af",
        "Apache-2.0",
        {"franka_description": ""},
    ),
    "xarm": (
        "xArm-Developer/xarm_ros2",
        "3654ba7bb2a0e502088251728d07263ea399d4a4",
        "BSD-3-Clause",
        {"xarm_description": "xarm_description", "xarm_controller": "xarm_controller"},
    ),
}

# output file -> (source, xacro file inside the repository, xacro arguments, what it is)
ROBOTS = {
    **{
        f"{ur}.urdf": (
            "ur",
            "urdf/ur.urdf.xacro",
            {"name": ur, "ur_type": ur},
            f"{ur[:2].upper() + ur[2:]} arm, nominal kinematics"
            f" (config/{ur}/default_kinematics.yaml), no gripper",
        )
        for ur in ("ur3e", "ur5e", "ur10e", "ur16e", "ur5")
    },
    "fr3.urdf": (
        "franka",
        "robots/fr3/fr3.urdf.xacro",
        {"hand": "true", "ee_id": "franka_hand"},
        "Franka Research 3 arm with the Franka Hand (two fingers, the second one a mimic joint)",
    ),
    "xarm6.urdf": (
        "xarm",
        "xarm_description/urdf/xarm_device.urdf.xacro",
        {"dof": "6", "robot_type": "xarm", "limited": "false"},
        "UFACTORY xArm6 arm, no gripper, the description's default (unlimited) joint ranges",
    ),
}

MESH_SUFFIXES = (".stl", ".dae", ".obj", ".glb", ".STL", ".DAE")


def git(repo, *args):
    return subprocess.run(["git", "-C", repo, *args], check=True, capture_output=True).stdout


def extract(repo, commit, folders, dest):
    """Writes the non-mesh files of `commit` of `repo` under `folders` ("" = all) to `dest`."""
    entries = git(repo, "ls-tree", "-r", "-z", commit, "--", *folders).split(b"\0")
    for raw in entries:
        if not raw:
            continue
        meta, name = raw.decode().split("\t", 1)
        if meta.split()[1] != "blob" or name.endswith(MESH_SUFFIXES) or "/meshes/" in "/" + name:
            continue
        path = os.path.join(dest, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "wb") as f:
            f.write(git(repo, "show", f"{commit}:{name}"))


def resolve_commit(repo, pinned, allow_other):
    try:
        return git(repo, "rev-parse", "--verify", "--quiet", pinned + "^{commit}").decode().strip()
    except subprocess.CalledProcessError:
        if not allow_other:
            sys.exit(f"{repo}: commit {pinned} not found (fetch it, or pass --allow-other-commit)")
        return git(repo, "rev-parse", "HEAD").decode().strip()


def run_xacro(path, args, packages):
    import xacro
    import xacro.substitution_args as subst

    def find(pkg):
        if pkg not in packages:
            raise RuntimeError(f"$(find {pkg}): package not among {sorted(packages)}")
        return packages[pkg]

    subst._eval_find = find
    # xacro keeps global state between runs (file stacks, all_includes): reset what it keeps.
    xacro.all_includes = []
    doc = xacro.process_file(path, mappings=dict(args))
    return doc.toprettyxml(indent="  ")


def clean(xml, packages, header):
    """Mesh paths back to package:// form; every comment (xacro's banner names a temp folder,
    the others describe the xacro, not this file) replaced by `header`."""
    for pkg, folder in sorted(packages.items(), key=lambda kv: -len(kv[1])):
        xml = re.sub(r"(file:/*)?" + re.escape(folder) + "/", f"package://{pkg}/", xml)
    xml = re.sub(r"\s*<!--.*?-->", "", xml, flags=re.S)
    first, rest = xml.split("\n", 1)
    return first + "\n" + header + rest


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    for key in SOURCES:
        ap.add_argument("--" + key, required=True, metavar="REPO")
    ap.add_argument("--out", default=os.path.join(ROOT, "data", "robots"))
    ap.add_argument("--allow-other-commit", action="store_true")
    opts = ap.parse_args()
    os.makedirs(opts.out, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="urdf-derive-") as tmp:
        trees = {}
        for key, (name, pinned, lic, pkgs) in SOURCES.items():
            repo = getattr(opts, key)
            commit = resolve_commit(repo, pinned, opts.allow_other_commit)
            dest = os.path.join(tmp, key)
            extract(repo, commit, [f or "." for f in pkgs.values()] + ["LICENSE", "NOTICE"], dest)
            trees[key] = (dest, commit, name, lic,
                          {p: os.path.normpath(os.path.join(dest, f)) for p, f in pkgs.items()})
        # The sources' license texts (and Apache NOTICE) go along with the derived files.
        lic_dir = os.path.join(opts.out, "licenses")
        os.makedirs(lic_dir, exist_ok=True)
        for key, (dest, commit, name, lic, packages) in trees.items():
            texts = []
            for f in ("LICENSE", "NOTICE"):
                path = os.path.join(dest, f)
                if os.path.exists(path):
                    with open(path) as fh:
                        texts.append(f"==> {name} {f} (commit {commit}) <==\n\n" + fh.read())
            with open(os.path.join(lic_dir, name.split("/")[1] + ".txt"), "w") as fh:
                fh.write("\n".join(texts))
        for out_name, (key, xacro_file, args, what) in ROBOTS.items():
            dest, commit, name, lic, packages = trees[key]
            xml = run_xacro(os.path.join(dest, xacro_file), args, packages)
            arg_text = " ".join(f"{k}:={v}" for k, v in args.items())
            header = (
                "<!-- Generated by tools/urdf/derive.py: do not edit by hand.\n"
                f"     {what}.\n"
                f"     Source: {name} at commit {commit},\n"
                f"     {xacro_file} expanded with xacro ({arg_text}).\n"
                f"     License of the source description: {lic}; its text: data/robots/licenses/. -->\n"
            )
            xml = clean(xml, packages, header)
            path = os.path.join(opts.out, out_name)
            with open(path + ".tmp", "w") as f:
                f.write(xml)
            os.replace(path + ".tmp", path)
            print(f"{path}: {len(xml)} bytes")


if __name__ == "__main__":
    main()
