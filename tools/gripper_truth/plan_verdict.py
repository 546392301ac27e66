"""The verdict of one whole-plan replay row (plan_replay.py, plan_sweep.py): `carried` and the named criteria that
failed. Thresholds and names: tools/gripper_truth/README.md, section "Replay of the whole plan", "Verdict"."""

LIFT_RISE_MIN = 0.045  # m of the 50 mm lift: the part's CoM rises at least this much
TILT_MAX_DEG = 5.0  # the part turns less than this over the lift and hold
MAS1_PUSH_MAX = 0.002  # m: the master's closing moves the pinched part at most this much (CoM) ...
MAS1_TURN_MAX_DEG = 1.0  # ... and turns it at most this much
ROT_EDGE_LIFT_MAX = 0.003  # m: the rotation axis's endpoints rise at most this much during `rot`
HOLDING = "both_sides"  # the only kind of a power grasp that holds (not caged, one-sided or without contact)

# every criterion, in the order they are listed
CRITERIA = ("rot_edge_lift", "mas1_push", "mas1_kind", "sup2_kind", "lift_kind_mas", "lift_kind_sup", "lift_rise",
            "lift_tilt")


def failures(rec):
    """The criteria (names of CRITERIA) that the replay record `rec` of run_plan fails, in CRITERIA order."""
    fail = {
        "rot_edge_lift": rec["rot"]["edge_lift_max"] > ROT_EDGE_LIFT_MAX,
        "mas1_push": rec["mas1_close"]["part_moved"] > MAS1_PUSH_MAX
        or rec["mas1_close"]["part_turned_deg"] > MAS1_TURN_MAX_DEG,
        "mas1_kind": rec["mas1_close"]["kind"] != HOLDING,
        "sup2_kind": rec["sup2_close"]["kind"] != HOLDING,
        "lift_kind_mas": rec["lift"]["kind_end"]["mas"] != HOLDING,
        "lift_kind_sup": rec["lift"]["kind_end"]["sup"] != HOLDING,
        "lift_rise": rec["lift"]["rise"] < LIFT_RISE_MIN,
        "lift_tilt": rec["lift"]["tilt_deg"] >= TILT_MAX_DEG,
    }
    return [c for c in CRITERIA if fail[c]]


def verdict(rec):
    """{"carried": no criterion failed, "failures": [...], "verdict": "carried" | "not carried"}."""
    f = failures(rec)
    return {"carried": not f, "failures": f, "verdict": "not carried" if f else "carried"}


THRESHOLDS = {"lift_rise_min": LIFT_RISE_MIN, "tilt_max_deg": TILT_MAX_DEG, "mas1_push_max": MAS1_PUSH_MAX,
              "mas1_turn_max_deg": MAS1_TURN_MAX_DEG, "rot_edge_lift_max": ROT_EDGE_LIFT_MAX, "holding_kind": HOLDING,
              "criteria": list(CRITERIA)}
