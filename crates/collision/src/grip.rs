//! The width a gripper closes on: from the part's real mesh, at a grasp.
//!
//! A Robotiq 2F-85 closing on a part stops where its pads (or the finger tips that carry them)
//! first touch it. With the flange at a grasp, the fingers are closed step by step from the full
//! stroke — each finger where the linkage puts it at that gap, so the pads rise as they close —
//! until a contact shape touches the part's surface; the contact gap is then refined by
//! bisection to [`GAP_TOLERANCE`]. The fingers are symmetric about the flange axis (the grasp
//! centres the part between them).

use nalgebra::Isometry3;
use pregrasp_robot::{Gripper2F85, GripperState, Primitive};

use crate::object::ObjectGeometry;

/// Resolution of the contact gap (m).
pub const GAP_TOLERANCE: f64 = 2e-5;

/// Step of the coarse closing search (m): thinner than any bar worth grasping.
const COARSE_STEP: f64 = 0.001;

/// Why a gripper cannot close on the part at a grasp.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum GripFailure {
    /// The fully open fingers already touch the part: it is wider than the 85 mm stroke there,
    /// or material lies where an open finger must go.
    #[error("the open fingers already touch the part (wider than the stroke, or material where a finger goes)")]
    OpenTouches,
    /// The fingers close fully without touching the part.
    #[error("the pads close on nothing (no part between the fingers)")]
    ClosesOnNothing,
}

/// Whether the gripper's contact shapes (pads and finger tips) touch the part at `gap`, with
/// the flange at `flange_in_object` (flange → object frame).
fn contact_at(
    object: &ObjectGeometry,
    gripper: &Gripper2F85,
    contacts: &[usize],
    flange_in_object: &Isometry3<f64>,
    gap: f64,
) -> bool {
    let mut touches = false;
    gripper.for_each_shape(GripperState::Closed { gap }, |k, _, prim| {
        if touches || !contacts.contains(&k) {
            return;
        }
        if let Primitive::Cuboid { pose, half_extents } = prim {
            touches = object.box_touches(&(flange_in_object * pose), &half_extents);
        }
    });
    touches
}

/// The gap (m) at which the gripper, its flange at `flange_in_object` (flange → object frame),
/// closes on the part: the largest gap at which a pad or finger tip touches the part's surface.
pub fn closing_gap(
    object: &ObjectGeometry,
    gripper: &Gripper2F85,
    flange_in_object: &Isometry3<f64>,
) -> Result<f64, GripFailure> {
    let contacts = gripper.contact_shapes();
    let touch = |gap: f64| contact_at(object, gripper, &contacts, flange_in_object, gap);
    let stroke = gripper.fingers().stroke();
    if touch(stroke) {
        return Err(GripFailure::OpenTouches);
    }
    let mut open = stroke;
    let mut gap = stroke;
    while gap > 0.0 {
        gap = (gap - COARSE_STEP).max(0.0);
        if touch(gap) {
            // The first contact lies in (gap, open]: bisect it.
            let mut closed = gap;
            while open - closed > GAP_TOLERANCE {
                let mid = 0.5 * (open + closed);
                if touch(mid) {
                    closed = mid;
                } else {
                    open = mid;
                }
            }
            return Ok(open);
        }
        open = gap;
    }
    Err(GripFailure::ClosesOnNothing)
}
