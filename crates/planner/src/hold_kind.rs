//! How a gripper's closing holds the part, from how each finger's closing ended.

use pregrasp_physics::HoldKind;
use pregrasp_robot::ClosingKind;

/// How a closing holds: one-sided if a finger closed on nothing, caged if a finger's tips met
/// the other's, encompassing if a finger wrapped the bar, else a pinch.
pub fn hold_kind(kinds: &[ClosingKind; 2]) -> HoldKind {
    if kinds.contains(&ClosingKind::Closed) {
        HoldKind::OneSided
    } else if kinds.contains(&ClosingKind::Caged) {
        HoldKind::Caged
    } else if kinds.contains(&ClosingKind::Encompassing) {
        HoldKind::Encompassing
    } else {
        HoldKind::Pinch
    }
}

/// Whether a closing of this kind squeezes the bar from both sides (a pinch or a wrap, not a
/// cage or one side; `None`: it did not close on the part).
pub fn squeezes(kind: Option<HoldKind>) -> bool {
    matches!(kind, Some(HoldKind::Encompassing | HoldKind::Pinch))
}
