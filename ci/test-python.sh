#!/usr/bin/env bash
# The Python package's tests: a fresh virtual environment under target/, the package installed
# the way the README tells users (`pip install "./python[sim]"`: maturin builds the abi3 wheel, the
# `sim` extra adds MuJoCo for pregrasp.simulate), its test dependencies (pytest, Ray for the cluster
# backend), then pytest against the CLI binary
# that `cargo test --workspace` built (the byte-for-byte comparison).
set -euo pipefail
cd "$(dirname "$0")/.."
target="${CARGO_TARGET_DIR:-$(pwd)/target}"
venv="$target/pyenv"
python="${PYTHON:-python3}"
rm -rf "$venv"
"$python" -m venv "$venv"
"$venv/bin/pip" install --quiet --upgrade pip
"$venv/bin/pip" install --quiet pytest "ray>=2.9"
"$venv/bin/pip" install --quiet "./python[sim]"
# The binary `cargo test --workspace` built (a plain `cargo build -p pregrasp` would resolve other
# features and rebuild the dependencies).
[ -x "$target/debug/pregrasp" ] || cargo build --workspace --quiet
export PREGRASP_BIN="$target/debug/pregrasp"
# Ray: no usage-stats prompt or upload from CI, no dashboard.
export RAY_USAGE_STATS_ENABLED=0
"$venv/bin/python" -m pytest -q python/tests
