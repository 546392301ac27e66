"""Plans from Python are the CLI's plans; the arrays API plans parts with no file."""

import json
import pathlib
import re
import threading

import numpy as np
import pytest

import pregrasp
from pregrasp import _pregrasp
from conftest import REPO, run_cli

TIMING = re.compile(r'\n  "timing_ms": \{[^}]*\}')


def without_timing(text: str) -> str:
    """A plan file's text without its `timing_ms` object (the one part runs may differ in)."""
    stripped, n = TIMING.subn("", text)
    assert n == 1, "exactly one timing_ms object"
    return stripped


@pytest.mark.parametrize("index", [0, 1, 2])
def test_examples_plan_byte_for_byte_as_the_cli(cli, examples, index):
    scene = str(examples[index])
    out = run_cli(cli, "plan", scene, "-o", "cli.json", "--quiet")
    assert out.returncode == 0, out.stderr
    with open("cli.json", encoding="utf-8") as f:
        cli_text = f.read()
    plan = pregrasp.plan(scene)
    assert plan.status == "planned"
    # Written beside the CLI's: the same file (both record where scene and mesh are from it).
    plan.write("py.json")
    with open("py.json", encoding="utf-8") as f:
        py_text = f.read()
    assert without_timing(py_text) == without_timing(cli_text)
    # Same keys in timing_ms too (stages and "process").
    assert json.loads(py_text)["timing_ms"].keys() == json.loads(cli_text)["timing_ms"].keys()
    # to_json() is that file without the two locations.
    located = json.loads(py_text)
    del located["scene"]["file_from_plan"], located["object"]["mesh_from_plan"]
    assert json.loads(plan.to_json()) == located
    # And the same with one thread and through a loaded Scene object.
    again = pregrasp.plan(pregrasp.Scene.load(scene), threads=1)
    again.write("again.json")
    with open("again.json", encoding="utf-8") as f:
        assert without_timing(f.read()) == without_timing(cli_text)


def test_plan_segments_are_numpy_arrays(examples):
    plan = pregrasp.plan(examples[0])
    best = plan.plans[0]
    assert best.segment_names == ["sup1", "rot", "mas1", "sup2"]
    rot = best.segment("rot")
    assert rot.t.shape == (len(rot),)
    assert rot.q.shape == (len(rot), 6)
    assert np.all(np.diff(rot.t) > 0)
    assert rot.object_poses.shape == (len(rot), 4, 4)
    assert best.segment("sup1").object_poses is None
    # Each closing's grip force: sup1 the pinch's recommended one, the power grasps the
    # 2F-85's largest (the planner's carry check), rot none.
    assert best.segment("sup1").grip_force == best.physics["grip_force_recommended"]
    assert [best.segment(n).grip_force for n in ("rot", "mas1", "sup2")] == [None, 235.0, 235.0]
    file = json.loads(plan.to_json())
    assert rot.q.tolist() == [p["q"] for p in file["plans"][0]["segments"][1]["points"]]
    assert [c["id"] for c in plan.candidates] == [c["id"] for c in file["candidates"]]
    assert best.theta_goal == pytest.approx(
        next(c["theta_goal"] for c in file["candidates"] if c["id"] == best.candidate)
    )
    with pytest.raises(KeyError, match="no segment"):
        best.segment("lift")


def test_a_part_given_as_numpy_arrays_plans_and_passes_check(examples):
    # A part from "perception": vertices in millimetres, faces, pose and grasps as arrays.
    ref = pregrasp.Scene.load(examples[0])
    vertices_mm = np.asarray(ref.vertices) * 1000.0
    faces = np.asarray(ref.faces, dtype=np.int32)
    grasps = ref.grasps
    scene = pregrasp.Scene.from_arrays(
        vertices_mm,
        faces,
        ref.pose,
        {"power": grasps["power"], "support": grasps["support"]},
        ref.robots,
        scale=0.001,
        name="chair side from arrays",
    )
    plan = pregrasp.plan(scene)
    assert plan.status == "planned", plan.reason
    report = pregrasp.check(plan)
    assert report.valid, [r for r in report.rules if r["ok"] is False]
    assert bool(report)
    # The same motions as the file's plan (the mesh went through mm and back).
    ref_plan = pregrasp.plan(ref)
    assert [p.candidate for p in plan.plans] == [p.candidate for p in ref_plan.plans]
    np.testing.assert_allclose(
        plan.plans[0].segment("rot").q, ref_plan.plans[0].segment("rot").q, atol=1e-6
    )


def test_from_arrays_defaults_and_auto_grasps(examples):
    ref = pregrasp.Scene.load(examples[0])
    scene = pregrasp.Scene.from_arrays(ref.vertices, ref.faces, ref.pose, "auto")
    assert [r["name"] for r in scene.robots] == [r["name"] for r in pregrasp.default_robots()]
    assert scene.grasps["mode"] == "auto"
    plan = pregrasp.plan(scene)
    assert plan.status == "planned", plan.reason
    assert plan.grasps["auto"]["planned"] >= 1
    assert pregrasp.check(plan).valid


def test_a_bad_scene_raises_scene_error_naming_the_key(cli, examples):
    ref = pregrasp.Scene.load(examples[0])
    with pytest.raises(pregrasp.SceneError, match=r"planner\.step_deg"):
        pregrasp.Scene.from_arrays(
            ref.vertices, ref.faces, ref.pose, "auto", planner={"step_deg": -1.0}
        )
    with pytest.raises(pregrasp.SceneError, match=r"faces must have shape"):
        pregrasp.Scene.from_arrays(ref.vertices, [[0, 1]], ref.pose, "auto")
    with pytest.raises(pregrasp.SceneError, match=r"face 0 uses vertex 99999"):
        pregrasp.Scene.from_arrays(ref.vertices, [[0, 1, 99999]], ref.pose, "auto")
    with pytest.raises(pregrasp.SceneError, match=r"^<arrays>: object.pose: .* must be a rotation"):
        pregrasp.Scene.from_arrays(ref.vertices, ref.faces, np.diag([2.0, 1, 1, 1]), "auto")
    # A scene file: the exception says what the CLI says after "error: ".
    text = examples[0].read_text().replace("step_deg", "step_dog", 1)
    if "step_dog" not in text:
        text = text.replace("[planner]", "[planner]\nmax_angle_deg = -5.0", 1)
    bad = examples[0].with_name("bad.toml")
    bad.write_text(text)
    out = run_cli(cli, "plan", str(bad), "-o", "never.json", "--quiet")
    assert out.returncode == 1
    cli_error = [l for l in out.stderr.splitlines() if l.startswith("error: ")]
    assert len(cli_error) == 1
    with pytest.raises(pregrasp.SceneError) as caught:
        pregrasp.plan(str(bad))
    assert "error: " + str(caught.value) == cli_error[0]
    assert "planner.max_angle" in str(caught.value)
    assert issubclass(pregrasp.SceneError, pregrasp.PregraspError)


def test_plan_files_read_write_and_errors(examples, tmp_path):
    plan = pregrasp.plan(examples[1])
    path = tmp_path / "shelf.plan.json"
    plan.write(path)
    again = pregrasp.Plan.load(path)
    assert again.to_json() == path.read_text()
    # The file says where its scene and mesh are from its own folder.
    written = json.loads(path.read_text())
    assert (tmp_path / written["object"]["mesh_from_plan"]).resolve() == (
        pathlib.Path(json.loads(plan.to_json())["object"]["mesh"]).resolve()
    )
    assert pregrasp.check(path).valid
    with pytest.raises(pregrasp.PlanFileError, match="x.json: not a pregrasp plan file"):
        pregrasp.Plan.from_json('{"format": "other/1"}', "x.json")
    with pytest.raises(pregrasp.PlanFileError, match="missing.json"):
        pregrasp.check(tmp_path / "missing.json")


def test_axes_are_algorithm_1(examples):
    axes = pregrasp.axes(examples[0])
    scores = [a["score"] for a in axes]
    assert scores == sorted(scores, reverse=True)
    plan = pregrasp.plan(examples[0])
    assert [a["id"] for a in axes] == [c["id"] for c in plan.candidates]


def test_kinematics_round_trip():
    q = [0.3, -1.2, 1.4, -0.5, 1.1, 0.7]
    pose = pregrasp.kin.fk(q, "ur10e")
    assert pose.shape == (4, 4)
    solutions = pregrasp.kin.ik(pose, "ur10e", seed=q)
    np.testing.assert_allclose(solutions[0], q, atol=1e-9)
    for s in solutions[:8]:
        np.testing.assert_allclose(pregrasp.kin.fk(s, "ur10e"), pose, atol=1e-9)
    far = np.eye(4)
    far[0, 3] = 5.0
    assert pregrasp.kin.ik(far).shape == (0, 6)
    with pytest.raises(ValueError, match="unknown robot model"):
        pregrasp.kin.fk(q, "ur99")


def test_planning_releases_the_gil(examples):
    """While a plan runs in another thread, this thread runs Python: it sees the plan inside
    its GIL-free section (impossible if the GIL were held there), and two plans run in it at
    once."""
    scenes = [pregrasp.Scene.load(p) for p in examples]
    seen = set()
    results = []

    def work(s):
        # A plan takes some 15 ms: a few in a row give the two threads time to overlap.
        for _ in range(4):
            results.append(pregrasp.plan(s, threads=1).status)

    threads = [threading.Thread(target=work, args=(s,)) for s in (scenes[2], scenes[1])]
    for t in threads:
        t.start()
    while any(t.is_alive() for t in threads):
        seen.add(_pregrasp._planning_now())
    for t in threads:
        t.join()
    assert results == ["planned"] * 8
    assert seen - {0}, f"never saw a plan in its GIL-free section: {seen}"
    assert 2 in seen, f"two plans never ran at once: {seen}"


def test_replanner_follows_the_measured_part(examples):
    scene = pregrasp.Scene.load(examples[0])
    plan = pregrasp.plan(scene)
    cell = pregrasp.Replanner(scene, plan)
    # Shifted on the table, measured 2 mm high: settled, replanned with the plan's own axis.
    pose = scene.pose.copy()
    pose[0, 3] += 0.004
    pose[1, 3] -= 0.002
    pose[2, 3] += 0.002
    again = cell.replan(pose, threads=1)
    assert again.status == "planned", again.reason
    assert again.plans[0].candidate == plan.plans[0].candidate
    assert "replan" in again.timing_ms
    assert pregrasp.check(again).valid
    # Replanning again and again gives the same plan (the part's knowledge is reused, not changed).
    assert without_timing(cell.replan(pose, threads=2).to_json()) == without_timing(again.to_json())
    # 5 cm in the air is no measurement error.
    high = scene.pose.copy()
    high[2, 3] += 0.05
    with pytest.raises(pregrasp.SceneError, match="check the measurement"):
        cell.replan(high)
    with pytest.raises(IndexError):
        cell.replan(pose, plan_index=7)


def test_replanner_resumes_after_the_rotation(examples):
    scene = pregrasp.Scene.load(examples[0])
    plan = pregrasp.plan(scene)
    cell = pregrasp.Replanner(scene, plan)
    goal = plan.plans[0].object_goal_pose
    # The part measured 2 mm off where the rotation left it, held in the pinch: what is left
    # is planned there, the segments that ran are kept, and the whole plan checks.
    held = goal.copy()
    held[0, 3] += 0.002
    for start in ("mas1", "sup2"):
        again = cell.replan(held, start=start, threads=1)
        assert again.status == "planned", again.reason
        assert np.allclose(again.plans[0].object_goal_pose, held, atol=1e-12)
        assert np.array_equal(again.plans[0].segment("sup1").q, plan.plans[0].segment("sup1").q)
        assert pregrasp.check(again).valid
    floating = goal.copy()
    floating[2, 3] += 0.03
    with pytest.raises(pregrasp.SceneError, match="above the support"):
        cell.replan(floating, start="mas1")
    with pytest.raises(ValueError, match="start"):
        cell.replan(held, start="mas2")


def test_two_fr3_with_the_franka_hand_plan_and_pass_check(examples):
    """Arms and gripper from a robot description (`urdf`, `gripper = "urdf"`), from Python."""
    fr3 = (REPO / "data" / "robots" / "fr3.urdf").as_posix()
    text = examples[0].read_text(encoding="utf-8")
    out = []
    lines = iter(text.splitlines())
    for line in lines:
        key = line.strip()
        if key == 'model = "ur5e"':
            side = "-0.45" if "-0.450" in next(lines) else "0.45"
            next(lines)  # the start line
            out += [
                f'urdf = "{fr3}"',
                'tool_link = "fr3_link8"',
                "hold = { fr3_joint3 = 0.0 }",
                'gripper = "urdf"',
                f"base = {{ xyz = [0.0, {side}, 0.0] }}",
                "start = [0.0, -0.7854, -2.3562, 0.0, 1.5708, 0.7854]",
            ]
        elif not key.startswith(("gripper =", "precision_point_z", "power_point_z")):
            out.append(line)
    scene = examples[0].with_name("fr3_hand.toml")
    scene.write_text("\n".join(out) + "\n", encoding="utf-8")
    robots = pregrasp.Scene.load(scene).robots
    assert [r["gripper"] for r in robots] == ["urdf", "urdf"]
    plan = pregrasp.plan(str(scene))
    assert plan.status == "planned", plan.reason
    assert [r["gripper"] for r in plan.to_dict()["robots"]] == ["urdf", "urdf"]
    entry = plan.plans[0]
    assert 0.0 < entry.segment("rot").grip_width < 0.08  # within the hand's 80 mm
    assert entry.physics["grip_force_recommended"] <= 100.0  # the hand's 100 N
    assert pregrasp.check(plan).valid
