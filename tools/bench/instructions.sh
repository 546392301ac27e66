#!/usr/bin/env bash
# Instructions per plan and per `bench reach` run, counted by callgrind: the measure
# docs/performance.md quotes next to wall-clock medians (it does not depend on the machine's
# load). Usage: tools/bench/instructions.sh [BINARY] (default target/release/pregrasp).
#
# Per plan: `bench plan SCENE --threads 1 --runs 6` minus `--runs 1`, over 5 (loading, the
# warm-up and start-up cancel out), warm runs only (`--cold-runs 0`: callgrind does not follow
# the cold runs' processes). Reach: one whole `bench reach` on the shipped problem set.
set -euo pipefail
bin=${1:-target/release/pregrasp}
count() {
    local out
    out=$(mktemp)
    valgrind --tool=callgrind --callgrind-out-file="$out" "$@" >/dev/null 2>"$out.log"
    grep -m1 -o 'Collected : [0-9]*' "$out.log" | grep -o '[0-9]*'
    rm -f "$out" "$out.log"
}
for scene in examples/chair_side.toml examples/shelf_side.toml examples/stool_side.toml; do
    one=$(count "$bin" bench plan "$scene" --threads 1 --runs 1 --cold-runs 0)
    six=$(count "$bin" bench plan "$scene" --threads 1 --runs 6 --cold-runs 0)
    awk -v s="$scene" -v a="$one" -v b="$six" \
        'BEGIN { printf "%-28s %8.1f M instructions per plan\n", s, (b - a) / 5 / 1e6 }'
done
reach=$(count "$bin" bench reach data/reach-ur5-table-boxes.json)
awk -v r="$reach" 'BEGIN { printf "%-28s %8.1f M instructions\n", "bench reach", r / 1e6 }'
