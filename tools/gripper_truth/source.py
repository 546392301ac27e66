"""The Menagerie `robotiq_2f85/` files the simulations load (`load_source`: from a checkout, or from a
git directory into a temporary directory) and their provenance. Used by closing.py and replay.py."""
import argparse
import hashlib
import subprocess
import sys
from pathlib import Path

MODEL_DIR = "robotiq_2f85"
MODEL_XML = "2f85.xml"


def git(args, cwd_git_dir, text=True):
    return subprocess.run(["git", "--git-dir", str(cwd_git_dir), *args], capture_output=True, check=True,
                          text=text).stdout


def sha256(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def load_source(path, rev, tmp):
    """Returns (directory holding 2f85.xml, provenance dict)."""
    p = Path(path).resolve()
    prov = {"argument_kind": None, "commit": None, "robotiq_2f85_last_change": None, "robotiq_2f85_tree": None}
    if (p / MODEL_DIR / MODEL_XML).is_file():
        prov["argument_kind"] = "checkout"
        src = p / MODEL_DIR
        gd = subprocess.run(["git", "-C", str(p), "rev-parse", "--absolute-git-dir", "--show-toplevel"],
                            capture_output=True, text=True)
        lines = gd.stdout.split("\n")
        # only the checkout's own repository counts, not one that merely encloses the directory
        if gd.returncode == 0 and len(lines) > 1 and Path(lines[1]).resolve() == p:
            gdir = lines[0].strip()
            prov["commit"] = git(["rev-parse", "HEAD"], gdir).strip()
            dirty = subprocess.run(["git", "-C", str(p), "status", "--porcelain", "--", MODEL_DIR],
                                   capture_output=True, text=True).stdout.strip()
            prov["worktree_modified"] = bool(dirty)
            rev = "HEAD"
    else:
        gdir = p
        try:
            git(["rev-parse", "--git-dir"], gdir)
        except subprocess.CalledProcessError:
            sys.exit(f"{p}: neither a checkout holding {MODEL_DIR}/{MODEL_XML} nor a git directory")
        prov["argument_kind"] = "git directory (files read with git cat-file)"
        prov["commit"] = git(["rev-parse", f"{rev}^{{commit}}"], gdir).strip()
        src = Path(tmp) / MODEL_DIR
        listing = git(["ls-tree", "-r", "-z", prov["commit"], MODEL_DIR + "/"], gdir)
        for entry in filter(None, listing.split("\0")):
            meta, fpath = entry.split("\t", 1)
            _, kind, obj = meta.split()
            if kind != "blob" or fpath.endswith(".png"):
                continue
            out = Path(tmp) / fpath
            out.parent.mkdir(parents=True, exist_ok=True)
            out.write_bytes(git(["cat-file", "blob", obj], gdir, text=False))
    if prov["commit"]:
        prov["robotiq_2f85_last_change"] = git(["log", "-1", "--format=%H %cs", prov["commit"], "--", MODEL_DIR],
                                               gdir).strip()
        prov["robotiq_2f85_tree"] = git(["rev-parse", f"{prov['commit']}:{MODEL_DIR}"], gdir).strip()
    if not prov["commit"]:
        print("WARNING: no git commit for the Menagerie files; only their SHA-256 are recorded", file=sys.stderr)
    files = sorted(str(f.relative_to(src)) for f in src.rglob("*") if f.is_file() and f.suffix in (".xml", ".stl", ".obj"))
    prov["sha256"] = {f: sha256(src / f) for f in files if f == MODEL_XML or f.startswith("assets/")}
    return src, prov


def menagerie_args(description, out_dir):
    """The command line of the closing grids (closing.py, power_closing.py): the Menagerie checkout or git
    directory, `--rev`, `--out` (default `out_dir`) and `--limit`."""
    ap = argparse.ArgumentParser(description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("menagerie", help="mujoco_menagerie checkout or (bare) git directory")
    ap.add_argument("--rev", default="HEAD", help="revision to read from a git directory (default HEAD)")
    ap.add_argument("--out", default=str(out_dir), help="output directory")
    ap.add_argument("--limit", type=int, default=0, help="simulate only the first N grid rows (testing)")
    return ap.parse_args()
