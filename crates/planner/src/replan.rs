//! Re-planning from a measured object pose (the paper's §VII-B limitation: the part is placed
//! by hand, so it never lies exactly where the scene says).
//!
//! The nominal plan rotates the part about one edge of its hull (candidate λ with direction
//! ±). After the part has been measured at another pose, the same edge — the same two hull
//! vertices in the object frame, the same signed direction — is looked up in Algorithm 1's
//! candidates at the new pose ([`matching_candidate`]), and only that candidate goes through
//! Algorithms 2 and 3 again (θ_goal, roles, μ_rot and the reach paths are all recomputed for
//! the new pose, then re-checked). If the edge is no longer a candidate or no longer plans,
//! the full pipeline runs on the new pose.

use nalgebra::{Isometry3, Point3, Vector3};
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::{CandidateJson, PlanFile};
use pregrasp_io::scene::Scene;

use crate::axes::{rotation_axis_candidates, RotationAxisCandidate};
use crate::context::ContextError;
use crate::pipeline::{plan, PlanOptions, PlanReport};

/// Two axis endpoints, in the object frame, closer than this (m) are the same hull vertex.
pub const SAME_VERTEX: f64 = 0.002;

/// How a re-plan ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReplanRoute {
    /// The nominal plan's edge and direction were planned again at the new pose.
    KeptCandidate,
    /// The edge is a candidate at the new pose but no longer plans: full pipeline.
    CandidateFailed,
    /// The edge is not a candidate at the new pose (e.g. the part is tilted): full pipeline.
    CandidateGone,
}

impl ReplanRoute {
    pub fn describe(self) -> &'static str {
        match self {
            ReplanRoute::KeptCandidate => "kept the plan's rotation axis",
            ReplanRoute::CandidateFailed => {
                "the plan's rotation axis no longer plans: full pipeline"
            }
            ReplanRoute::CandidateGone => {
                "the plan's rotation axis is no longer a candidate: full pipeline"
            }
        }
    }
}

/// The result of [`replan`].
pub struct Replanned {
    pub report: PlanReport,
    pub route: ReplanRoute,
}

/// The axis of a plan-file candidate in the object frame: its endpoints and its signed unit
/// direction (positive angle = the candidate's direction).
fn object_axis(
    axis: &[[f64; 3]; 2],
    direction: &str,
    p_init: &Isometry3<f64>,
) -> ([Point3<f64>; 2], Vector3<f64>) {
    let inv = p_init.inverse();
    let a = inv * Point3::from(axis[0]);
    let b = inv * Point3::from(axis[1]);
    let sign = if direction == "cw" { -1.0 } else { 1.0 };
    ([a, b], (b - a).normalize() * sign)
}

/// The id of the candidate among `candidates` (Algorithm 1 at the pose whose P_init is
/// `p_init`) that turns the part about the same hull edge in the same sense as `nominal`
/// (a candidate of a plan file whose P_init is `nominal_p_init`).
pub fn matching_candidate(
    nominal: &CandidateJson,
    nominal_p_init: &Isometry3<f64>,
    candidates: &[RotationAxisCandidate],
    p_init: &Isometry3<f64>,
) -> Option<usize> {
    let (ends, dir) = object_axis(&nominal.axis, &nominal.direction, nominal_p_init);
    candidates
        .iter()
        .find(|c| {
            let json = c.to_json();
            let (e, d) = object_axis(&json.axis, &json.direction, p_init);
            let same = |x: &Point3<f64>, y: &Point3<f64>| (x - y).norm() <= SAME_VERTEX;
            let ends_match = (same(&e[0], &ends[0]) && same(&e[1], &ends[1]))
                || (same(&e[0], &ends[1]) && same(&e[1], &ends[0]));
            ends_match && d.dot(&dir) > 0.0
        })
        .map(|c| c.id)
}

/// Plans `scene` with the part at `object_pose`, keeping the rotation axis of plan
/// `plan_index` of `nominal` when it still works.
pub fn replan(
    scene: &Scene,
    mesh: &Mesh,
    nominal: &PlanFile,
    plan_index: usize,
    object_pose: Isometry3<f64>,
    options: &PlanOptions,
) -> Result<Replanned, ContextError> {
    let mut moved = scene.clone();
    moved.object.pose = object_pose;
    let nominal_candidate = nominal
        .plans
        .get(plan_index)
        .and_then(|p| nominal.candidates.iter().find(|c| c.id == p.candidate));
    let axes = rotation_axis_candidates(
        mesh,
        &moved.object.pose,
        moved.support_height,
        &moved.planner,
    );
    let matched = nominal_candidate.and_then(|c| {
        matching_candidate(
            c,
            &nominal.object.initial_pose.to_isometry(),
            &axes.candidates,
            &axes.p_init,
        )
    });
    let full = |route| -> Result<Replanned, ContextError> {
        let report = plan(&moved, mesh, options, &|_| {}, &|| {})?;
        Ok(Replanned { report, route })
    };
    let Some(id) = matched else {
        return full(ReplanRoute::CandidateGone);
    };
    let kept = plan(
        &moved,
        mesh,
        &PlanOptions {
            max_plans: 1,
            only: Some(vec![id]),
        },
        &|_| {},
        &|| {},
    )?;
    if kept.file.status == "planned" {
        Ok(Replanned {
            report: kept,
            route: ReplanRoute::KeptCandidate,
        })
    } else {
        full(ReplanRoute::CandidateFailed)
    }
}
