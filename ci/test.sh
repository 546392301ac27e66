#!/usr/bin/env bash
# The README's test command: the Rust workspace's tests, then the Python package's (built from
# python/ with maturin into a fresh virtual environment, pytest, a local Ray instance).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --workspace
bash ci/test-python.sh
