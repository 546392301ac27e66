"""pregrasp.simulate: the chair example planned, written and replayed in MuJoCo (the `sim` extra); bad input."""

import json
import pathlib
import re
import time

import pytest

import pregrasp

SEGMENTS = ["sup1", "rot", "mas1", "sup2"]


@pytest.fixture(scope="module")
def chair(tmp_path_factory):
    """The chair example's plan file (planned here, as a user would) and its replay at the plan's own forces."""
    pytest.importorskip("mujoco", reason='the sim extra: pip install "./python[sim]"')
    folder = tmp_path_factory.mktemp("sim")
    scene = pregrasp.write_examples(folder / "examples", only="chair_side")[0]
    path = folder / "chair_side.json"
    pregrasp.plan(scene).write(str(path))
    t0 = time.time()
    result = pregrasp.simulate(path, lift=0.05)
    print(f"simulate chair_side plan 0: {time.time() - t0:.1f} s wall, {result.sim_seconds:.1f} s simulated")
    return path, json.loads(path.read_text()), result


def test_every_segment_in_order(chair):
    _, doc, r = chair
    plan = doc["plans"][0]
    assert [s.name for s in r.segments] == SEGMENTS
    assert [s.robot for s in r.segments] == [s["robot"] for s in plan["segments"]]
    assert (r.master, r.supportive, r.candidate) == (plan["master"], plan["supportive"], plan["candidate"])
    assert r.segment("rot").closing is None
    for name in ("sup1", "mas1", "sup2"):
        c = r.segment(name).closing
        # each closing at its segment's own grip_force (20 N pinch, 235 N power grasps)
        assert c.force == next(s["grip_force"] for s in plan["segments"] if s["name"] == name)
        assert c.force_from == "segment grip_force"
        assert c.arm == ("master" if name == "mas1" else "supportive")
    pinch = r.segment("sup1").closing
    assert pinch.kind == "both_sides"
    assert all(abs(f - 20.0) < 1.0 for f in pinch.pad_force)  # the pinch squeezes at its force
    # rot turns the part as planned, on the table
    rot = r.segment("rot")
    assert abs(rot.turned_deg - rot.details["turn_plan_deg"]) < 1.0
    assert rot.details["edge_lift_max"] < 0.003
    assert r.sim_seconds > 15.0


def test_the_part_is_lifted(chair):
    _, _, r = chair
    assert r.lift.lift_mm == pytest.approx(50.0)
    assert r.lift.rise_mm >= 45.0, r.summary()
    assert r.lift.tilt_deg < 5.0, r.summary()
    assert not r.lift.on_table
    # the verdict names what failed, with numbers
    assert r.verdict.passed == (not r.verdict.failures) == r.record["carried"]
    assert [f.criterion for f in r.verdict.failures] == r.record["failures"]
    assert all("mm" in f.message or "deg" in f.message or "grasp" in f.message for f in r.verdict.failures)
    assert "part rose" in r.summary()


def test_carried_at_the_pinch_force(chair):
    """At 20 N for the power grasps the truth table (plan_replay_2f85.csv) has chair plan 0 carried."""
    path, _, _ = chair
    r = pregrasp.simulate(path, power_force=20.0)
    assert [s.closing.force_from for s in r.segments if s.closing] == ["segment grip_force", "argument", "argument"]
    assert r.verdict.passed, r.summary()
    assert r.lift.rise_mm >= 45.0 and r.lift.tilt_deg < 5.0


def test_pads_with_torsion(chair):
    """The pads' contacts with torsional friction (condim 4): chair plan 0 is carried there too; 3 and 4 only."""
    path, _, _ = chair
    r = pregrasp.simulate(path, pad_condim=4)
    assert r.verdict.passed, r.summary()
    with pytest.raises(ValueError, match="pad_condim must be 3 or 4, found 6"):
        pregrasp.simulate(path, pad_condim=6)


def test_bad_input_names_the_file(tmp_path):
    missing = tmp_path / "nowhere.json"
    with pytest.raises(pregrasp.SimulationError, match="nowhere.json"):
        pregrasp.simulate(missing)
    empty = tmp_path / "no_plan.json"
    empty.write_text(json.dumps({"format": "pregrasp.plan/1", "status": "no_plan", "reason": "no axis",
                                 "plans": []}))
    with pytest.raises(pregrasp.SimulationError, match=r"no_plan\.json: no plan to simulate"):
        pregrasp.simulate(empty)
    not_json = tmp_path / "broken.json"
    not_json.write_text("{")
    with pytest.raises(pregrasp.SimulationError, match="broken.json"):
        pregrasp.simulate(not_json)
    with pytest.raises(pregrasp.SimulationError, match="no plan 5"):
        pregrasp.simulate({"plans": [{"segments": []}]}, plan_index=5)


REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def xarm(tmp_path_factory):
    """The stool example planned with two UFACTORY xArm6 (data/robots/xarm6.urdf) where the UR5e stand, 10 cm
    nearer the part, as crates/planner/tests/non_ur_arms.rs plans it; the scene names the description by a path
    relative to itself, and the plan file is written elsewhere."""
    pytest.importorskip("mujoco", reason='the sim extra: pip install "./python[sim]"')
    folder = tmp_path_factory.mktemp("xarm")
    scene = pathlib.Path(pregrasp.write_examples(folder / "cell", only="stool_side")[0])
    (scene.parent / "robots").symlink_to(REPO / "data" / "robots", target_is_directory=True)
    text = scene.read_text().replace('model = "ur5e"', 'urdf = "robots/xarm6.urdf"')
    text = text.replace("[0.000, 0.450, 0.000]", "[0.1, 0.35, 0.0]").replace("[0.000, -0.450, 0.000]",
                                                                          "[0.1, -0.35, 0.0]")
    text = re.sub(r"start = \[[^\]]*\]", "start = [0.0, -0.5, -0.8, 0.0, 1.3, 0.0]", text)
    described = scene.parent / "stool_xarm6.toml"
    described.write_text(text)
    path = folder / "plans" / "stool_xarm6.json"
    path.parent.mkdir()
    pregrasp.plan(str(described)).write(str(path))
    return path, json.loads(path.read_text())


def test_a_described_arm_is_placed_by_its_own_description(xarm):
    """The replay's URDF kinematics (pregrasp.sim.arms, not the planner's) put each gripper where the plan's grasps
    are: the supportive tool at G_s where sup1 ends, the master's at its power grasp where mas1 ends."""
    from pregrasp.sim.arms import arm_fk
    from pregrasp.sim.geometry import pose_T
    path, doc = xarm
    plan = doc["plans"][0]
    robots = {r["name"]: r for r in doc["robots"]}
    assert {r["model"] for r in robots.values()} == {"urdf"}
    segs = {s["name"]: s for s in plan["segments"]}

    def tool(arm, seg, point):
        r = robots[arm]
        return pose_T(r["base"]) @ arm_fk(r, doc, path)(segs[seg]["points"][-1]["q"]) @ pose_T(r[point])

    g_s = pose_T(segs["rot"]["points"][0]["object_pose"]) @ pose_T(doc["grasps"]["support"])
    at_g_s = tool(plan["supportive"], "sup1", "precision_point")
    master = [r["name"] for r in doc["robots"]].index(plan["master"])
    g_p = pose_T(plan["object_goal_pose"]) @ pose_T(doc["grasps"]["power"][master])
    at_g_p = tool(plan["master"], "mas1", "power_point")
    for got, want in ((at_g_s, g_s), (at_g_p, g_p)):
        assert abs(got - want).max() < 1e-6


def test_a_described_arm_is_replayed(xarm):
    path, doc = xarm
    r = pregrasp.simulate(path)
    assert [s.name for s in r.segments] == SEGMENTS
    assert r.verdict.passed, r.summary()
    # a gripper the replay does not model is refused by name
    jaws = json.loads(json.dumps(doc))
    jaws["robots"][0]["gripper"] = "urdf"
    with pytest.raises(pregrasp.SimulationError, match="the replay models the Robotiq 2F-85 only"):
        pregrasp.simulate(jaws)


def test_the_model_ships_with_its_licence():
    folder = pathlib.Path(pregrasp.__file__).parent / "_menagerie" / "robotiq_2f85"
    assert "Redistribution and use" in (folder / "LICENSE").read_text()
    assert "75df466bb0e39d8d7fa66b556513cfc676919924" in (folder / "PROVENANCE.md").read_text()
    assert (folder / "2f85.xml").is_file()
    assert len(list((folder / "assets").glob("*.stl"))) == 8
