"""`simulate`: a plan replayed in MuJoCo before the robot moves (two Robotiq 2F-85 grippers following the
planned flange poses, the part a free body on the table, then a lift), with typed results. Imports the standard
library only; numpy and MuJoCo are imported when `simulate` runs (`pip install "pregrasp[sim]"`)."""
from __future__ import annotations

import json
import math
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple, Union


MODEL = Path(__file__).resolve().parent.parent / "_menagerie" / "robotiq_2f85" / "2f85.xml"
SEGMENTS = ("sup1", "rot", "mas1", "sup2")
DEFAULT_PINCH = 20.0  # N, the 2F-85's smallest force: a plan without physics and grip_force


class SimulationError(Exception):
    """A plan that cannot be simulated: the file is missing or not a plan, it has no plan at `plan_index`, its mesh
    is not found, or MuJoCo is not installed. The message names the file."""


@dataclass(frozen=True)
class Closing:
    """One gripper closing at the end of a segment (sup1: the pinch; mas1, sup2: the power grasps)."""
    arm: str  # "supportive" or "master"
    force: float  # N, the commanded grip force
    force_from: str  # where it came from: "segment grip_force", "physics.grip_force_recommended", "argument", ...
    kind: str  # both_sides (a squeeze: both pads press) | one_side | caged | caged_no_contact | no_contact
    pad_force: Tuple[float, float]  # N, normal force of the part on the +x and the -x pad (mean of the last 0.1 s)
    other_force: float  # N, on the gripper's other links
    moved_mm: float  # how far the closing itself moved the part (CoM) ...
    turned_deg: float  # ... and turned it


@dataclass(frozen=True)
class SegmentResult:
    """What happened to the part during one segment (its motion and, for sup1, mas1, sup2, its closing; sup2
    includes the supportive gripper's opening before it)."""
    name: str
    robot: str
    moved_mm: float  # part CoM displacement from the segment's start to its end
    turned_deg: float  # part rotation over the same interval
    closing: Optional[Closing]
    details: Dict[str, Any] = field(default_factory=dict)  # the replay's own numbers (SI units, *_deg in degrees)


@dataclass(frozen=True)
class LiftResult:
    lift_mm: float  # how far both flanges rose together (then held 1 s)
    rise_mm: float  # how far the part's CoM rose
    tilt_deg: float  # how far the part turned over the lift and hold
    slip_mm: Dict[str, float]  # the part's motion in each gripper ("master", "supportive")
    kind_end: Dict[str, str]  # each grasp's kind at the end
    on_table: bool  # the part still touches the table at the end


@dataclass(frozen=True)
class Failure:
    criterion: str  # a name of pregrasp.sim.verdict.CRITERIA
    message: str  # what was measured against what


@dataclass(frozen=True)
class Verdict:
    passed: bool  # the part was carried: no criterion failed
    failures: List[Failure]

    def __bool__(self):
        return self.passed


@dataclass(frozen=True)
class SimResult:
    plan_index: int
    candidate: int
    master: str
    supportive: str
    segments: List[SegmentResult]  # sup1, rot, mas1, sup2
    lift: LiftResult
    verdict: Verdict
    record: Dict[str, Any]  # the whole record, as a row of tools/gripper_truth's plan_replay_2f85.json
    sim_seconds: float
    wall_seconds: float

    def segment(self, name: str) -> SegmentResult:
        for s in self.segments:
            if s.name == name:
                return s
        raise KeyError(f"no segment {name!r} (segments: {', '.join(SEGMENTS)})")

    def summary(self) -> str:
        lines = []
        for s in self.segments:
            c = s.closing
            grip = (f", closed {c.kind} at {c.force:.0f} N (pads {c.pad_force[0]:.1f}/{c.pad_force[1]:.1f} N)"
                    if c else "")
            lines.append(f"{s.name:4s} {s.robot}: part moved {s.moved_mm:.1f} mm, "
                         f"turned {s.turned_deg:.1f} deg{grip}")
        lf = self.lift
        lines.append(f"lift {lf.lift_mm:.0f} mm: part rose {lf.rise_mm:.1f} mm, tilted {lf.tilt_deg:.1f} deg")
        lines.append("carried" if self.verdict.passed else
                     "not carried: " + "; ".join(f.message for f in self.verdict.failures))
        return "\n".join(lines)


def _load(plan) -> Tuple[dict, Optional[Path]]:
    if isinstance(plan, dict):
        return plan, None
    if hasattr(plan, "to_json"):  # a pregrasp.Plan: its mesh path is as the planner was given it
        return json.loads(plan.to_json()), None
    path = Path(os.fspath(plan))
    try:
        text = path.read_text()
    except OSError as e:
        raise SimulationError(f"{path}: cannot read the plan file ({e.strerror or e})") from None
    try:
        return json.loads(text), path
    except ValueError as e:
        raise SimulationError(f"{path}: not a plan file (not JSON: {e})") from None


def resolve_mesh(doc, plan_path, mesh_root=None, mesh=None):
    """The part's mesh file: `mesh` if given; else `object.mesh` under `mesh_root`; as written (from the working
    directory); from the plan file's folder by `object.mesh_from_plan`, by `object.mesh`, or beside it."""
    where = plan_path if plan_path else "plan"
    if mesh is not None:
        if not Path(mesh).is_file():
            raise SimulationError(f"{where}: mesh {mesh} not found")
        return Path(mesh)
    obj = doc.get("object") or {}
    rel = obj.get("mesh")
    if not rel:
        raise SimulationError(f"{where}: no object.mesh (pass mesh=)")
    tries = [Path(mesh_root) / rel] if mesh_root else []
    tries.append(Path(rel))
    if plan_path:
        folder = plan_path.resolve().parent
        if obj.get("mesh_from_plan"):
            tries.append(folder / obj["mesh_from_plan"])
        tries += [folder / rel, folder / Path(rel).name]
    for p in tries:
        if p.is_file():
            return p
    raise SimulationError(f"{where}: mesh {rel} not found (tried {', '.join(str(p) for p in tries)}; "
                          "pass mesh_root= or mesh=)")


def _forces(plan, pinch_force, power_force):
    """(force, where it came from) per closing: the argument, else the segment's grip_force, else the plan's
    physics.grip_force_recommended (else 20 N)."""
    segs = {s["name"]: s for s in plan["segments"]}
    rec = (plan.get("physics") or {}).get("grip_force_recommended")
    out = {}
    for name, arg in (("sup1", pinch_force), ("mas1", power_force), ("sup2", power_force)):
        if arg is not None:
            out[name] = (float(arg), "argument")
        elif segs[name].get("grip_force") is not None:
            out[name] = (float(segs[name]["grip_force"]), "segment grip_force")
        elif rec is not None:
            out[name] = (float(rec), "physics.grip_force_recommended")
        else:
            out[name] = (DEFAULT_PINCH, "default (no grip_force, no physics)")
    return out


def prepare_part(doc, mesh_path):
    """The part's convex pieces as (vertices, faces) and their decomposition info (object frame, scaled)."""
    from . import part
    try:
        tri = part.read_stl(mesh_path) * float(doc["object"].get("scale", 1.0))
    except (OSError, ValueError) as e:
        raise SimulationError(f"{mesh_path}: cannot read the mesh ({e})") from None
    try:
        pieces, info = part.decompose_extrusion(tri)
        meshes = [part.prism_mesh(P) for P in pieces]
    except ValueError:
        try:
            meshes, info = part.decompose_coacd(tri)
        except ValueError as e:
            raise SimulationError(f"{mesh_path}: {e}") from None
    return tri, meshes, info


def simulate(plan: Union[str, "os.PathLike[str]", dict, Any], lift: float = 0.05, plan_index: int = 0,
             power_force: Optional[float] = None, pinch_force: Optional[float] = None, *,
             mesh_root=None, mesh=None, model=None, slow: float = 1.0, dt: float = 0.001,
             noslip: int = 10, pad_condim: int = 3) -> SimResult:
    """Replays plan `plan_index` of a plan (a plan file's path, its parsed JSON or a pregrasp.Plan) in MuJoCo:
    both arms' Robotiq 2F-85 grippers follow the planned flange poses through sup1 (the pinch closes), rot, mas1
    (the master's power grasp closes), the supportive gripper opens, sup2 (its power grasp closes); then both rise
    `lift` m together and hold 1 s. The same replay as tools/gripper_truth/plan_replay.py (the truth tables).
    Flange poses: a UR arm's DH kinematics, or a described arm's joint chain read from its URDF (`pregrasp.sim.arms`,
    the file found as the scene named it); a plan whose arm carries its description's own gripper is refused.

    Forces (N): `pinch_force` for sup1, `power_force` for mas1 and sup2; when None, each closing segment's own
    `grip_force`, else the plan's `physics.grip_force_recommended`. `mesh_root` / `mesh`: where the part's mesh is
    when the plan's path does not find it. `model`: another 2f85.xml (default: the vendored Menagerie model).
    `pad_condim`: the pads' contacts, 3 (the truth tables': no torsional friction at a contact point) or 4 (each
    point also resists a twist, mu_pad x 11.6 mm x its normal force); how far plans turn on it:
    docs/physics.md, "The pads' torsion in the whole-plan replay".
    Raises SimulationError for a plan that cannot be simulated."""
    t0 = time.time()
    doc, path = _load(plan)
    where = path if path else "plan"
    if not isinstance(doc, dict) or "plans" not in doc:
        raise SimulationError(f"{where}: not a plan file (no \"plans\")")
    plans = doc.get("plans") or []
    if not plans:
        raise SimulationError(f"{where}: no plan to simulate (status {doc.get('status')!r}"
                              f"{': ' + str(doc['reason']) if doc.get('reason') else ''})")
    if not 0 <= plan_index < len(plans):
        raise SimulationError(f"{where}: no plan {plan_index} (the file has {len(plans)})")
    if not lift > 0 or not math.isfinite(lift):
        raise ValueError(f"lift must be a positive number of metres, found {lift}")
    if pad_condim not in (3, 4):
        raise ValueError(f"pad_condim must be 3 or 4, found {pad_condim}")
    p = plans[plan_index]
    names = [s.get("name") for s in p.get("segments", [])]
    missing = [n for n in SEGMENTS if n not in names]
    if missing:
        raise SimulationError(f"{where}: plan {plan_index} lacks segment(s) {', '.join(missing)}")
    ph = p.get("physics") or {}
    mass = doc.get("object", {}).get("mass") or ph.get("mass")
    if not mass:
        raise SimulationError(f"{where}: the part has no mass (object.mass or physics.mass)")
    try:
        import mujoco  # noqa: F401
    except ImportError:
        raise SimulationError('MuJoCo is not installed: pip install "pregrasp[sim]" (or pip install mujoco)') from None
    from .arms import ArmError, placed_arms
    from .part import mass_properties
    from .run import run_plan
    from .scene import PlanScene
    try:
        arms = placed_arms(doc, path)
    except ArmError as e:
        raise SimulationError(f"{where}: {e}") from None
    tri, meshes, _ = prepare_part(doc, resolve_mesh(doc, path, mesh_root, mesh))
    forces = _forces(p, pinch_force, power_force)
    scene = PlanScene(Path(model) if model else MODEL, doc, meshes, mass_properties(tri, float(mass)),
                      ph.get("mu_pad", 0.8), ph.get("mu_support", 0.4), dt, noslip, pad_condim=pad_condim)
    rec, trace = run_plan(scene, doc, p, {n: f for n, (f, _) in forces.items()}, lift=lift, slow=slow,
                          arms=arms)
    return _result(doc, p, plan_index, lift, forces, rec, trace, time.time() - t0)


def _result(doc, p, k, lift, forces, rec, trace, wall):
    from .run import moved
    from .verdict import explain
    segs = {s["name"]: s for s in p["segments"]}
    arm = {"sup": "supportive", "mas": "master"}
    closing_rec = {"sup1": ("sup", rec["pinch"], None), "mas1": ("mas", rec["mas1_close"], rec["mas1_close"]),
                   "sup2": ("sup", rec["sup2_close"], rec["sup2_close"])}
    com = trace["com"]
    out = []
    for name in SEGMENTS:
        d_mm, d_deg = moved(*trace[name], com)
        closing = None
        if name in closing_rec:
            a, c, mv = closing_rec[name]
            closing = Closing(arm[a], forces[name][0], forces[name][1], c["kind"], (c["N_pos"], c["N_neg"]),
                              c["N_other"], mv["part_moved"] * 1e3 if mv else float("nan"),
                              mv["part_turned_deg"] if mv else float("nan"))
        details = {"rot": rec["rot"], "sup1": rec["pinch"], "mas1": rec["mas1_close"],
                   "sup2": {**rec["sup2_close"], "supportive_open": rec["sup_open"]}}[name]
        out.append(SegmentResult(name, segs[name]["robot"], d_mm * 1e3, d_deg, closing, details))
    lf = rec["lift"]
    lift_res = LiftResult(lift * 1e3, lf["rise"] * 1e3, lf["tilt_deg"],
                          {arm[a]: v * 1e3 for a, v in lf["slip_in_grip"].items()},
                          {arm[a]: v for a, v in lf["kind_end"].items()}, lf["table_force_end"] > 0.0)
    why = explain(rec, lift)
    verdict = Verdict(rec["carried"], [Failure(c, why[c][1]) for c in rec["failures"]])
    return SimResult(k, p["candidate"], p["master"], p["supportive"], out, lift_res, verdict, rec, rec["t_sim"], wall)
