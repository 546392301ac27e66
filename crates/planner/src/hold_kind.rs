//! How a gripper's closing holds the part, from how each finger's closing ended.

use pregrasp_physics::HoldKind;
use pregrasp_robot::ClosingKind;

/// Half the 2F-85 pad's width (m), along the bar it holds (a jaw's patch is taken alike).
pub const PAD_HALF_WIDTH: f64 = 0.011;

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
