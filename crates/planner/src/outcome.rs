//! What became of one candidate of a run ([`CandidateOutcome`]): the pipeline's verdicts,
//! before they become the plan file's words.

use pregrasp_io::plan_file::PhysicsJson;
use pregrasp_model::Plan;

use crate::carry::{CarryVerdict, Uncarried};
use crate::paths::IntegratedPath;
use crate::poses::{PoseRejection, PowerGraspPose};
use crate::rejection::{FailedRule, PathFailure, Unheld};

/// What became of one candidate.
#[derive(Clone, Debug)]
pub enum CandidateOutcome {
    /// Algorithms 2 and 3 succeeded; `plan` is the plan, `physics` its grip check, `check` the
    /// first rule it failed when re-verified (`None`: valid).
    Planned {
        pose: PowerGraspPose,
        path: Box<IntegratedPath>,
        plan: Box<Plan>,
        /// The grip check's `physics` object of the plan, when it ran.
        physics: Option<Box<PhysicsJson>>,
        /// The carry check of its final state, when it ran: the forces the power grasps close
        /// with, or why none lifts the part with the safety factor (kept without `[physics]
        /// reject_uncarried`; or any reason, with `reject = false`).
        carry: CarryVerdict,
        check: Option<FailedRule>,
        /// How close a grasping gripper comes to the support along the plan (m), from the
        /// same check.
        closest_grasp_to_support: Option<f64>,
    },
    /// Algorithm 3 found μ_rot and the straight lines of its reach motions, but the pinch
    /// cannot hold the part during μ_rot (`[physics] reject`): `reason` says why; no transit
    /// was planned.
    Unheld {
        pose: PowerGraspPose,
        reason: Unheld,
    },
    /// Algorithm 2 found a pose, but the power grasps cannot carry the part there: not at the
    /// gripper's largest force (`[physics] reject`), or not with the safety factor or by no
    /// force at all (`[physics] reject_uncarried`; [`crate::carry`]). Motions were planned only
    /// where the verdict was not known before them, and are dropped.
    Uncarried {
        pose: PowerGraspPose,
        reason: Uncarried,
    },
    /// Algorithm 2 found no pose.
    NoPose(PoseRejection),
    /// Algorithm 2 found a pose, Algorithm 3 no integrated path: the failure that got
    /// furthest.
    NoPath {
        pose: PowerGraspPose,
        failure: PathFailure,
    },
    /// Not planned: [`PlanOptions::only`](crate::pipeline::PlanOptions::only) leaves it out.
    Skipped,
    /// Not planned: the arms' start configurations are already in collision (the plan file's
    /// `reason` names the pair: [`Rejection::StartBlocked`](crate::rejection::Rejection::StartBlocked)), so no candidate can be.
    StartBlocked,
    /// Algorithm 2 found a pose, but Algorithm 3 was not run: `max_plans` plans were kept from
    /// candidates that rank above it whatever it would give (see [`PlanOptions::wave`](crate::pipeline::PlanOptions::wave)).
    NotEvaluated,
}

impl CandidateOutcome {
    /// A valid plan whose power grasps carry the part (the carry check ran and found forces).
    pub fn planned_and_carried(&self) -> bool {
        matches!(
            self,
            CandidateOutcome::Planned {
                carry: Some(Ok(_)),
                check: None,
                ..
            }
        )
    }

    /// Refused for its carry ([`CandidateOutcome::Uncarried`]), or a valid plan whose power
    /// grasps the carry check finds cannot carry the part.
    pub fn carry_refused(&self) -> bool {
        match self {
            CandidateOutcome::Uncarried { .. } => true,
            CandidateOutcome::Planned { carry, check, .. } => {
                check.is_none() && matches!(carry, Some(Err(_)))
            }
            _ => false,
        }
    }
}
