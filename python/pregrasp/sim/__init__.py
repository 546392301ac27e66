"""The whole-plan replay in MuJoCo (`simulate`; `pregrasp.simulate` is the same function).

Importing it costs the standard library only; numpy and MuJoCo (the `sim` extra: pip install "pregrasp[sim]")
are imported when a plan is simulated. It never imports pregrasp's native extension, so
tools/gripper_truth/plan_replay.py loads it from the source tree by path and runs the same replay as users do."""
from .api import (
    Closing,
    Failure,
    LiftResult,
    SegmentResult,
    SimResult,
    SimulationError,
    Verdict,
    simulate,
)

__all__ = ["Closing", "Failure", "LiftResult", "SegmentResult", "SimResult", "SimulationError", "Verdict", "simulate"]
