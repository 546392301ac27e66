"""Shared fixtures: the built-in examples written to a temporary folder, and the `pregrasp`
binary of this repository (the CLI the Python plans are compared with)."""

import os
import pathlib
import shutil
import subprocess

import pytest

import pregrasp

REPO = pathlib.Path(__file__).resolve().parents[2]


def _cli() -> str:
    """The `pregrasp` binary: $PREGRASP_BIN, else the repository's debug or release build
    (the README's test command builds it before pytest runs)."""
    given = os.environ.get("PREGRASP_BIN")
    if given:
        return given
    for profile in ("debug", "release"):
        candidate = REPO / "target" / profile / "pregrasp"
        if candidate.exists():
            return str(candidate)
    on_path = shutil.which("pregrasp")
    if on_path:
        return on_path
    pytest.fail("no pregrasp binary: build it (cargo build) or set PREGRASP_BIN")


@pytest.fixture(scope="session")
def cli():
    return _cli()


@pytest.fixture()
def examples(tmp_path, monkeypatch):
    """The three example scenes in a fresh folder, which is also the working directory."""
    monkeypatch.chdir(tmp_path)
    paths = pregrasp.write_examples("examples")
    return [pathlib.Path(p) for p in paths]


def run_cli(cli, *args, cwd=None):
    return subprocess.run([cli, *args], cwd=cwd, capture_output=True, text=True)
