#!/usr/bin/env bash
# Real-browser test of the plan viewer (`pregrasp view`): headless Chromium opens the
# generated pages with every network request refused (the page must need none), checks the
# canvas is drawn, the candidate table is filled, the timeline moves the arms (as the
# exporter's timeline does: its CSV is compared row by row), the page
# explains itself in words when WebGL is missing, and there is no console error.
# A screenshot goes to target/viewer-screenshot.png (plus target/viewer-screenshot-<segment>.png,
# the 3D view at the end of each segment, and -no-plan.png). Last line: `browser: N passed, M failed`.
#
# PLAN_JSON=path/to/plan.json  view that plan (e.g. `pregrasp demo` output) instead of the
#                              viewer's own fixture plan; the no-plan page always uses the fixture.
set -euo pipefail
if [ -n "${PLAN_JSON:-}" ]; then PLAN_JSON=$(realpath "$PLAN_JSON"); fi
cd "$(dirname "$0")/.."
root=$(pwd)

if ! command -v chromium >/dev/null; then
  apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y chromium
fi
CHROMIUM=$(command -v chromium)
export CHROMIUM
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y nodejs npm
fi
(cd ci/browser && npm ci --no-audit --no-fund --loglevel=error)

target="${CARGO_TARGET_DIR:-$root/target}"
# The workspace's binaries and examples: the features `cargo test --workspace` resolves, so after
# the tests nothing is compiled again (`-p pregrasp` alone built every dependency a second time).
cargo build --quiet --workspace --bins --examples
pregrasp="$target/debug/pregrasp"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$target/debug/examples/fixture_plan" "$work"
plan_json="${PLAN_JSON:-$work/plan.json}"
"$pregrasp" view "$plan_json" -o "$work/view-plan.html"
"$pregrasp" view "$work/no-plan.json" -o "$work/view-no-plan.html"
"$pregrasp" export "$plan_json" --format csv -o "$work/csv" > /dev/null

mkdir -p "$root/target"
node ci/browser/test.mjs "$work/view-plan.html" "$work/view-no-plan.html" "$root/target/viewer-screenshot.png" "$work/csv"
