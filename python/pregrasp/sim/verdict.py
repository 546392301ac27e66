"""The verdict of one whole-plan replay (`pregrasp.simulate`, tools/gripper_truth/plan_replay.py and plan_sweep.py):
`carried` and the named criteria that failed. Thresholds and names: tools/gripper_truth/README.md, section
"Replay of the whole plan", "Verdict"."""

LIFT = 0.05  # m, the lift the thresholds are stated for
LIFT_RISE_MIN = 0.045  # m of the 50 mm lift: the part's CoM rises at least this much (90 % of any other lift)
TILT_MAX_DEG = 5.0  # the part turns less than this over the lift and hold
MAS1_PUSH_MAX = 0.002  # m: the master's closing moves the pinched part at most this much (CoM) ...
MAS1_TURN_MAX_DEG = 1.0  # ... and turns it at most this much
ROT_EDGE_LIFT_MAX = 0.003  # m: the rotation axis's endpoints rise at most this much during `rot`
HOLDING = "both_sides"  # the only kind of a power grasp that holds (not caged, one-sided or without contact)

# every criterion, in the order they are listed
CRITERIA = ("rot_edge_lift", "mas1_push", "mas1_kind", "sup2_kind", "lift_kind_mas", "lift_kind_sup", "lift_rise",
            "lift_tilt")


def rise_min(lift=LIFT):
    return LIFT_RISE_MIN if lift == LIFT else 0.9 * lift


def explain(rec, lift=LIFT):
    """Every criterion on the replay record `rec` of run_plan: {name: (failed, what was measured against what)}."""
    r, m, s, lf = rec["rot"], rec["mas1_close"], rec["sup2_close"], rec["lift"]
    rmin = rise_min(lift)
    return {
        "rot_edge_lift": (r["edge_lift_max"] > ROT_EDGE_LIFT_MAX,
                          f"the rotation axis rose {r['edge_lift_max'] * 1e3:.1f} mm during rot "
                          f"(at most {ROT_EDGE_LIFT_MAX * 1e3:.0f} mm)"),
        "mas1_push": (m["part_moved"] > MAS1_PUSH_MAX or m["part_turned_deg"] > MAS1_TURN_MAX_DEG,
                      f"the master's closing moved the part {m['part_moved'] * 1e3:.1f} mm and "
                      f"{m['part_turned_deg']:.1f} deg (at most {MAS1_PUSH_MAX * 1e3:.0f} mm, "
                      f"{MAS1_TURN_MAX_DEG:.0f} deg)"),
        "mas1_kind": (m["kind"] != HOLDING, f"the master's power grasp closed {m['kind']} (needs {HOLDING})"),
        "sup2_kind": (s["kind"] != HOLDING, f"the supportive power grasp closed {s['kind']} (needs {HOLDING})"),
        "lift_kind_mas": (lf["kind_end"]["mas"] != HOLDING,
                          f"after the lift the master's grasp is {lf['kind_end']['mas']} (needs {HOLDING})"),
        "lift_kind_sup": (lf["kind_end"]["sup"] != HOLDING,
                          f"after the lift the supportive grasp is {lf['kind_end']['sup']} (needs {HOLDING})"),
        "lift_rise": (lf["rise"] < rmin, f"the part rose {lf['rise'] * 1e3:.1f} mm of the {lift * 1e3:.0f} mm lift "
                                         f"(at least {rmin * 1e3:.1f} mm)"),
        "lift_tilt": (lf["tilt_deg"] >= TILT_MAX_DEG,
                      f"the part tilted {lf['tilt_deg']:.1f} deg over the lift and hold "
                      f"(less than {TILT_MAX_DEG:.0f} deg)"),
    }


def failures(rec, lift=LIFT):
    """The criteria (names of CRITERIA) that the replay record `rec` of run_plan fails, in CRITERIA order."""
    e = explain(rec, lift)
    return [c for c in CRITERIA if e[c][0]]


def verdict(rec, lift=LIFT):
    """{"carried": no criterion failed, "failures": [...], "verdict": "carried" | "not carried"}."""
    f = failures(rec, lift)
    return {"carried": not f, "failures": f, "verdict": "not carried" if f else "carried"}


THRESHOLDS = {"lift_rise_min": LIFT_RISE_MIN, "tilt_max_deg": TILT_MAX_DEG, "mas1_push_max": MAS1_PUSH_MAX,
              "mas1_turn_max_deg": MAS1_TURN_MAX_DEG, "rot_edge_lift_max": ROT_EDGE_LIFT_MAX, "holding_kind": HOLDING,
              "criteria": list(CRITERIA)}
