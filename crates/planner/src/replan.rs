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
//!
//! [`replan_from_rot`] is the same after `sup1` has run: the supportive gripper already holds
//! the part, so `sup1` is kept as it ran, the grasp it really holds is `G_s' = P_init'⁻¹ ·
//! T_flange(q) · T_precision` (P_init' from the measured pose, q the arm's joints now), and
//! μ_rot must start at q; `rot`, `mas1` and `sup2` are planned again.

use nalgebra::{Isometry3, Point3, Vector3};
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::{
    CandidateJson, PlanFile, PlanJson, PlanStatus, RotationDirection, SegmentJson, SegmentName,
};
use pregrasp_io::scene::Scene;

use crate::axes::RotationAxisCandidate;
use crate::check::check_plan;
use crate::context::{arm_models, PartKnowledge};
use crate::error::PlanError;
use crate::output::set_pinch_force;
use crate::pipeline::{axes_of, plan, PlanOptions, PlanReport};
use crate::rejection::FailedRule;

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
    direction: RotationDirection,
    p_init: &Isometry3<f64>,
) -> ([Point3<f64>; 2], Vector3<f64>) {
    let inv = p_init.inverse();
    let a = inv * Point3::from(axis[0]);
    let b = inv * Point3::from(axis[1]);
    ([a, b], (b - a).normalize() * direction.sign())
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
    let (ends, dir) = object_axis(&nominal.axis, nominal.direction, nominal_p_init);
    candidates
        .iter()
        .find(|c| {
            let json = c.to_json();
            let (e, d) = object_axis(&json.axis, json.direction, p_init);
            let same = |x: &Point3<f64>, y: &Point3<f64>| (x - y).norm() <= SAME_VERTEX;
            let ends_match = (same(&e[0], &ends[0]) && same(&e[1], &ends[1]))
                || (same(&e[0], &ends[1]) && same(&e[1], &ends[0]));
            ends_match && d.dot(&dir) > 0.0
        })
        .map(|c| c.id)
}

/// The id, among Algorithm 1's candidates for `moved` (the scene at the measured pose), of the
/// rotation axis of plan `plan_index` of `nominal`, if it is still a candidate.
fn candidate_at(
    moved: &Scene,
    mesh: &Mesh,
    nominal: &PlanFile,
    plan_index: usize,
    known: Option<&PartKnowledge>,
) -> Option<usize> {
    let plan = nominal.plans.get(plan_index)?;
    let candidate = nominal.candidates.iter().find(|c| c.id == plan.candidate)?;
    let axes = axes_of(moved, mesh, known);
    matching_candidate(
        candidate,
        &nominal.object.initial_pose.to_isometry(),
        &axes.candidates,
        &axes.p_init,
    )
}

/// Plans `scene` with the part at `object_pose`, keeping the rotation axis of plan
/// `plan_index` of `nominal` when it still works. An error is a scene or mesh the planner
/// cannot work on.
pub fn replan(
    scene: &Scene,
    mesh: &Mesh,
    nominal: &PlanFile,
    plan_index: usize,
    object_pose: Isometry3<f64>,
    options: &PlanOptions,
) -> Result<Replanned, PlanError> {
    let mut moved = scene.clone();
    moved.object.pose = object_pose;
    let matched = candidate_at(&moved, mesh, nominal, plan_index, options.known.as_deref());
    let full = |route| -> Result<Replanned, PlanError> {
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
            ..options.clone()
        },
        &|_| {},
        &|| {},
    )?;
    if kept.file.status == PlanStatus::Planned {
        Ok(Replanned {
            report: kept,
            route: ReplanRoute::KeptCandidate,
        })
    } else {
        full(ReplanRoute::CandidateFailed)
    }
}

/// What a nominal plan lacks for re-planning what is left of it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RanPlanProblem {
    #[error("no {0} segment")]
    NoSegment(SegmentName),
    #[error("{0} has no points")]
    NoPoints(SegmentName),
    #[error("the {role} arm {name:?} is not in the scene")]
    ArmNotInScene { role: &'static str, name: String },
}

/// Why [`replan_from_rot`] cannot start.
#[derive(Debug, thiserror::Error)]
pub enum ResumeError {
    #[error("plans[{0}]: no such plan")]
    NoPlan(usize),
    #[error("plans[{plan}]: {problem}")]
    Plan {
        plan: usize,
        problem: RanPlanProblem,
    },
    /// The scene or mesh cannot be planned at all.
    #[error("{0}")]
    Planning(#[from] PlanError),
    /// The measured pose cannot be where the executed segments left the part: held as
    /// measured, the part would have been `off` (m) above the support (below when negative)
    /// when `rot` began, more than `tolerance` (m).
    #[error(
        "--object-pose: held as measured, the part would have been {:.1} mm {} the support \
         when rot began (at most {:.1} mm is measurement error): it slid in the pinch, or the \
         measurement is off; measure again",
        .off.abs() * 1e3,
        if *.off > 0.0 { "above" } else { "below" },
        .tolerance * 1e3
    )]
    Measurement { off: f64, tolerance: f64 },
}

/// A plan of a nominal file part of which has run (`replan --from rot`, `mas1`, `sup2`): its
/// entry, its segments and its arms, each refused by name when the file lacks it.
pub(crate) struct RanPlan<'a> {
    pub plan: &'a PlanJson,
    index: usize,
}

impl<'a> RanPlan<'a> {
    pub fn new(nominal: &'a PlanFile, index: usize) -> Result<RanPlan<'a>, ResumeError> {
        let plan = nominal.plans.get(index).ok_or(ResumeError::NoPlan(index))?;
        Ok(RanPlan { plan, index })
    }

    fn bad(&self, problem: RanPlanProblem) -> ResumeError {
        ResumeError::Plan {
            plan: self.index,
            problem,
        }
    }

    /// Segment `name`, which has points.
    pub fn segment(&self, name: SegmentName) -> Result<&'a SegmentJson, ResumeError> {
        let segment = (self.plan.segments.iter())
            .find(|s| s.name == name)
            .ok_or_else(|| self.bad(RanPlanProblem::NoSegment(name)))?;
        if segment.points.is_empty() {
            return Err(self.bad(RanPlanProblem::NoPoints(name)));
        }
        Ok(segment)
    }

    /// The index in `scene` of the arm the plan names `name` (its `role`).
    pub fn arm(&self, scene: &Scene, role: &'static str, name: &str) -> Result<usize, ResumeError> {
        (scene.robots.iter())
            .position(|r| r.name == name)
            .ok_or_else(|| {
                self.bad(RanPlanProblem::ArmNotInScene {
                    role,
                    name: name.to_string(),
                })
            })
    }
}

/// The grasp a gripper holds, `measured` through its arm's joints, or the `planned` one when
/// they differ by round-off only (FK of the planned joints gives it back within 1e-15), so
/// that an unchanged pose resumes the nominal plan exactly.
pub(crate) fn held_grasp(measured: Isometry3<f64>, planned: &Isometry3<f64>) -> Isometry3<f64> {
    let off = (measured.translation.vector - planned.translation.vector).norm();
    if off < 1e-9 && measured.rotation.angle_to(&planned.rotation) < 1e-9 {
        *planned
    } else {
        measured
    }
}

/// Re-plans `rot`, `mas1` and `sup2` of plan `plan_index` of `nominal` after its `sup1` has
/// run, with the part measured at `object_pose` (where it lies with the supportive gripper
/// closed on it). Only the plan's own rotation axis is tried (the gripper holds the part where
/// it holds it); the result has the nominal `sup1`, the grasp `G_s'` the gripper really holds,
/// and is re-checked. `route` is [`ReplanRoute::KeptCandidate`] when it planned,
/// [`ReplanRoute::CandidateFailed`] / [`ReplanRoute::CandidateGone`] (and no plan) when not.
pub fn replan_from_rot(
    scene: &Scene,
    mesh: &Mesh,
    nominal: &PlanFile,
    plan_index: usize,
    object_pose: Isometry3<f64>,
) -> Result<Replanned, ResumeError> {
    let ran = RanPlan::new(nominal, plan_index)?;
    let sup1 = ran.segment(SegmentName::Sup1)?;
    let q_sup = sup1.points.last().expect("a segment with points").q;
    let sup = ran.arm(scene, "supportive", &ran.plan.supportive)?;
    let mut moved = scene.clone();
    moved.object.pose = object_pose;
    let arms = arm_models(&moved)?;
    moved.grasps.support = held_grasp(
        moved.initial_object_pose().inverse()
            * arms[sup].flange_world(&q_sup)
            * arms[sup].gripper.precision_point(),
        &moved.grasps.support,
    );

    let matched = candidate_at(&moved, mesh, nominal, plan_index, None);
    let options = PlanOptions {
        max_plans: 1,
        only: Some(matched.into_iter().collect()),
        fixed_rot_start: Some((sup, q_sup)),
        ..PlanOptions::default()
    };
    let mut report = plan(&moved, mesh, &options, &|_| {}, &|| {})?;
    let route = match (matched, report.file.plans.is_empty()) {
        (None, _) => ReplanRoute::CandidateGone,
        (Some(_), true) => ReplanRoute::CandidateFailed,
        (Some(_), false) => ReplanRoute::KeptCandidate,
    };
    if let Some(p) = report.file.plans.first_mut() {
        // The executed sup1 replaces the one planned to reach the same configuration.
        if let Some(seg) = p.segments.iter_mut().find(|s| s.name == SegmentName::Sup1) {
            *seg = sup1.clone();
        }
        set_pinch_force(p);
        let verdict = check_plan(&report.file, mesh);
        if let Some(rule) = FailedRule::first(&verdict) {
            report.file.plans.clear();
            report.file.status = PlanStatus::NoPlan;
            report.file.reason = Some(format!(
                "replan --from rot: with the executed sup1 the plan fails {rule}"
            ));
            return Ok(Replanned {
                report,
                route: ReplanRoute::CandidateFailed,
            });
        }
    }
    if route == ReplanRoute::CandidateGone {
        report.file.status = PlanStatus::NoPlan;
        report.file.reason = Some(
            "replan --from rot: the plan's rotation axis is not a candidate at the measured pose"
                .into(),
        );
    }
    Ok(Replanned { report, route })
}
