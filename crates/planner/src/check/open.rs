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
use pregrasp_collision::{open_inside, OpenHand, OpenMemo, OPEN_CONTACT_DEPTH};
use pregrasp_robot::Joints;

use super::walk::PlanCheck;

/// Largest travel (m) of any point of an open gripper between two states judged for
/// penetration: half the 0.5 mm allowed.
pub(super) const OPEN_STEP: f64 = 0.0005;

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
    ///
    /// States are judged at most [`OPEN_STEP`] of gripper travel apart (`judged`: the flange,
    /// object frame, at the last judged state of the segment, and the memo of the open hand's
    /// free boxes along it); the grasp itself always is.
    /// Between two judged states no point of the open hand moves more than [`OPEN_STEP`], and
    /// the depth is 1-Lipschitz in that motion (a distance to a surface, or to a piece's
    /// face): a link at most 0.5 mm deep at both is at most 0.75 mm deep between them.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn open_hand(
        &mut self,
        arm: usize,
        q: &Joints,
        object: &Isometry3<f64>,
        place: OpenAt,
        judged: &mut (Option<Isometry3<f64>>, OpenMemo),
        at: impl FnOnce() -> String,
    ) {
        let Some(part) = self.world.object() else {
            return;
        };
        let gripper = &self.arms[arm].gripper;
        let flange_in_object = object.inverse() * self.arms[arm].flange_world(q);
        let travel = |from: &Isometry3<f64>| {
            let shift = (flange_in_object.translation.vector - from.translation.vector).norm();
            shift
                + flange_in_object.rotation.angle_to(&from.rotation) * OpenHand::of(gripper).reach()
        };
        let due =
            place == OpenAt::Grasp || judged.0.as_ref().is_none_or(|j| travel(j) >= OPEN_STEP);
        if !due {
            return;
        }
        judged.0 = Some(flange_in_object);
        *self.open_states += 1;
        if let Some(d) = open_inside(part, gripper, &flange_in_object, &mut judged.1) {
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
