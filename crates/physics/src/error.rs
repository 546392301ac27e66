//! What can stop the grip check of a plan: the plan lacks what it needs, the part's mass is
//! unusable, or the solver fails on a state.

use crate::mass::MassError;
use crate::statics::SolverError;

/// Errors of the analysis: the plan lacks what it needs.
#[derive(Debug, thiserror::Error)]
pub enum PhysicsError {
    #[error("plan {index} does not exist (the file has {count} plan(s))")]
    NoSuchPlan { index: usize, count: usize },
    #[error("plans[{plan}]: no `rot` segment")]
    NoRotation { plan: usize },
    #[error("plans[{plan}].segments[rot].points[{point}]: no object_pose")]
    NoObjectPose { plan: usize, point: usize },
    #[error("plans[{plan}].candidate: no candidate with id {id}")]
    NoCandidate { plan: usize, id: usize },
    #[error("the part's mass must be in (0, {max}] kg, found {0}", max = pregrasp_model::MAX_MASS)]
    BadMass(f64),
    #[error("object mesh: {0}")]
    Mass(#[from] MassError),
    #[error("plans[{plan}], state at t = {t:.3} s: {error}")]
    Solver {
        plan: usize,
        t: f64,
        error: SolverError,
    },
}
