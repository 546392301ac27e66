#!/usr/bin/env python3
"""List the source files longer than 600 lines (Rust, Python, JavaScript) in the repository.

Usage: tools/lint/long_files.py [LIMIT]; exits 1 and lists each such file if any. Generated
data (JSON, CSV, meshes) is not source and is not counted.
"""
import os
import sys

ROOTS = ["crates", "python", "fuzz", "tools", "ci", "examples"]
SUFFIXES = (".rs", ".py", ".js")
SKIP = {"target", "__pycache__", "node_modules", ".venv"}


def main():
    limit = int(sys.argv[1]) if len(sys.argv) > 1 else 600
    long = []
    for root in ROOTS:
        for folder, dirs, files in os.walk(root):
            dirs[:] = sorted(d for d in dirs if d not in SKIP)
            for name in sorted(files):
                if name.endswith(SUFFIXES):
                    path = os.path.join(folder, name)
                    with open(path, encoding="utf-8", errors="replace") as f:
                        n = sum(1 for _ in f)
                    if n > limit:
                        long.append((path, n))
    for path, n in long:
        print(f"{path}: {n} lines (limit {limit})")
    sys.exit(1 if long else 0)


if __name__ == "__main__":
    main()
