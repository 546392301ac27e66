//! Rule 2 for the open gripper next to its grasp: contact, never penetration. Where the
//! format lets a gripper touch the part it is about to grasp — every state of the last
//! [`CONTACT_ZONE`](pregrasp_model::timeline::CONTACT_ZONE) of a straight approach, the
//! grasp itself before the fingers close, the start of `sup2`'s retreat with the hand opened —
//! the fully open hand (every finger link or jaw, and the palm/housing) may touch the part but
//! lie at most [`OPEN_CONTACT_DEPTH`] inside it
//! ([`pregrasp_collision::inside`] states how deep a link lies, and how it is found).
//!
//! Frames: the flange's world pose at the state's joints (`ArmModel::flange_world`) is taken
//! into the object frame by the part's world pose there: `flange_in_object = object⁻¹ ·
//! flange_world`.

use nalgebra::Isometry3;
use pregrasp_collision::{open_inside, OPEN_CONTACT_DEPTH};
use pregrasp_robot::Joints;

use super::walk::PlanCheck;

/// Where an open-hand state lies on its segment, for the message.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum OpenAt {
    /// On the straight approach, within its contact zone.
    Approach,
    /// At the grasp, the fingers about to close.
    Grasp,
    /// On the straight retreat that begins `sup2`, within its contact zone.
    Retreat,
}

impl<'a> PlanCheck<'a> {
    /// The open gripper of arm `arm` at joints `q`, the part at `object` (world): no link more
    /// than [`OPEN_CONTACT_DEPTH`] inside the part, else rule 2 fails naming the link and its
    /// depth at `at` (the state's words).
    pub(super) fn open_hand(
        &mut self,
        arm: usize,
        q: &Joints,
        object: &Isometry3<f64>,
        place: OpenAt,
        at: impl FnOnce() -> String,
    ) {
        let Some(part) = self.world.object() else {
            return;
        };
        *self.open_states += 1;
        let flange_in_object = object.inverse() * self.arms[arm].flange_world(q);
        if let Some(d) = open_inside(part, &self.arms[arm].gripper, &flange_in_object) {
            let place = match place {
                OpenAt::Approach => "on the straight approach",
                OpenAt::Grasp => "at the grasp, before the fingers close",
                OpenAt::Retreat => "on the retreat, the hand opened",
            };
            self.collisions.fail(format!(
                "{}, {place}: the open {} of arm {} is {:.1} mm inside the part (at most {:.1} mm)",
                at(),
                d.link,
                self.name(arm),
                d.depth * 1e3,
                OPEN_CONTACT_DEPTH * 1e3
            ));
        }
    }
}
