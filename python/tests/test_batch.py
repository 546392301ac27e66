"""The batch from Python: locally and on a local Ray instance, the same summary."""

import csv
import json

import pytest

import pregrasp


def comparable(records):
    """Records without what differs between runs (timing, reuse)."""
    return [{k: v for k, v in r.items() if k not in ("time_ms", "reused")} for r in records]


@pytest.fixture()
def batch_dir(examples):
    folder = examples[0].parent
    (folder / "broken.toml").write_text("[object]\nmesh = 'nowhere.stl'\n")
    return folder


def test_local_batch_writes_the_summary_and_an_error_row(batch_dir, tmp_path):
    out = tmp_path / "out"
    records = pregrasp.batch.run(batch_dir, out)
    by_scene = {r["scene"]: r for r in records}
    assert set(by_scene) == {"broken.toml", "chair_side.toml", "shelf_side.toml", "stool_side.toml"}
    assert by_scene["broken.toml"]["status"] == "error"
    assert "broken.toml" in by_scene["broken.toml"]["reason"]
    for name in ("chair_side.toml", "shelf_side.toml", "stool_side.toml"):
        assert by_scene[name]["status"] == "planned"
        assert by_scene[name]["check"] == "valid"
        assert (out / by_scene[name]["plan_file"]).exists()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["scenes"] == records
    assert summary["counts"]["planned"] == 3 and summary["counts"]["error"] == 1
    with open(out / "summary.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["scene"] for r in rows] == [r["scene"] for r in records]
    assert "broken.toml" in (out / "report.html").read_text()
    # A rerun reuses every plan that is up to date.
    again = pregrasp.batch.run(batch_dir, out)
    assert all(r["reused"] for r in again if r["status"] != "error")
    assert comparable(again) == comparable(records)


def test_ray_batch_gives_the_same_summary(batch_dir, tmp_path):
    import ray  # installed by the README's test command (ci/test-python.sh)

    local = pregrasp.batch.run(batch_dir, tmp_path / "local")
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        remote = pregrasp.batch.run(batch_dir, tmp_path / "ray", backend="ray")
    finally:
        ray.shutdown()
    assert comparable(remote) == comparable(local)
    with open(tmp_path / "ray" / "summary.csv", newline="") as f:
        assert len(list(csv.DictReader(f))) == 4
    assert (tmp_path / "ray" / "report.html").exists()
