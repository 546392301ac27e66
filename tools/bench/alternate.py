#!/usr/bin/env python3
"""One-shot `pregrasp plan -q` processes of several binaries, interleaved process by process.

Wall-clock medians of different binaries measured minutes apart on a shared VM differ by more
than most changes; run side by side, each scene planned by each binary in turn (the order
reversed every other round), they see the same load. docs/performance.md quotes its medians.

Usage: tools/bench/alternate.py BIN[,BIN...] SCENE[,SCENE...] [ROUNDS]   (default 41 rounds)
"""
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def main() -> int:
    if len(sys.argv) not in (3, 4):
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    bins = sys.argv[1].split(",")
    scenes = sys.argv[2].split(",")
    rounds = int(sys.argv[3]) if len(sys.argv) == 4 else 41
    times = {(b, s): [] for b in bins for s in scenes}
    with tempfile.TemporaryDirectory() as out:
        plan = str(Path(out) / "plan.json")
        for r in range(rounds):
            for s in scenes:
                for b in bins if r % 2 == 0 else bins[::-1]:
                    t = time.perf_counter()
                    subprocess.run([b, "plan", s, "-o", plan, "-q"], check=True)
                    times[(b, s)].append((time.perf_counter() - t) * 1e3)
    for s in scenes:
        medians = "  ".join(f"{b}: {statistics.median(times[(b, s)]):.2f} ms" for b in bins)
        print(f"{s}  {medians}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
