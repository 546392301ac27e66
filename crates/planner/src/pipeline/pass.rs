//! One pass of the pipeline: the scene's power grasps seated by one rule ([`crate::seat`]),
//! Algorithm 1 → 2 → 3 for every candidate, ranked into a plan report.

use std::sync::Arc;
use std::time::Instant;

use pregrasp_collision::{ArmModel, ObjectGeometry};
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::{Outcome, PlanStatus};
use pregrasp_io::plan_model::plan_json;
use pregrasp_io::scene::Scene;
use pregrasp_model::timeline::Moment;
use pregrasp_model::{Plan, PlanSet};
use rayon::prelude::*;

use super::{CandidateOutcome, Pass, PlanOptions, PlanReport};
use crate::axes::{rotation_axis_candidates_with_hull, AxesResult, RotationAxisCandidate};
use crate::carry::CarryVerdict;
use crate::check::PlanChecker;
use crate::clock::Stage;
use crate::context::{PartKnowledge, PlanningContext};
use crate::error::{check_mesh, PlanError};
use crate::hold::{HoldCheck, HoldResult};
use crate::no_plan::no_plan_reason;
use crate::output::{self, plan_file_header, plan_set, rot_only_plan};
use crate::pass_memo::PassMemo;
use crate::paths::{integrated_path, NoPath};
use crate::poses::{object_pose_for_power_grasp, PoseRejection, PowerGraspPose};
use crate::ranking::{rank, ranked_beyond, required_force};
use crate::rejection::{FailedRule, Rejection, Unheld};
use crate::rotate::RotationPath;
use crate::seat::SeatRule;

/// What a pass built that the next passes of the same mesh and robots reuse (their scenes
/// differ in the power grasps alone): the part's collision geometry, the arm models and the
/// motions that do not depend on the power grasps ([`PassMemo`]).
#[derive(Clone)]
pub(super) struct Built {
    pub(super) part: Arc<ObjectGeometry>,
    pub(super) arms: Arc<[ArmModel; 2]>,
    pub(super) memo: Arc<PassMemo>,
}

/// Algorithm 2's answer for one candidate: its pose, or why it has none.
type PoseOutcome = Result<PowerGraspPose, PoseRejection>;

/// [`plan`] with the scene's power grasps (seated by `rule`, [`crate::seat`]), not slid; and
/// the part's collision geometry and the arm models it planned with (`built` when given, else
/// the known part's geometry, else built here), for a second plan of the same mesh. With
/// `probe`, it stops where Algorithm 2 shows no candidate's power grasps carry the part
/// ([`Pass::NoneCarries`]).
pub(super) fn plan_grasps_as_given(
    scene: &Scene,
    mesh: &Mesh,
    options: &PlanOptions,
    (built, rule, probe): (Option<Built>, SeatRule, bool),
    on_candidates: &(dyn Fn(usize) + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<(Pass, Built), PlanError> {
    check_mesh(mesh)?;
    let t0 = Instant::now();
    let axes = axes_of(scene, mesh, options.known.as_deref());
    let t_axes = t0.elapsed();

    let t_ctx = Instant::now();
    // The power grasps seated on the palm (`seat`): the plan is made with them.
    let known = options.known.as_deref().filter(|k| k.fits_mesh(mesh));
    // The part's geometry and what closings need (built once a process) beside the arm models:
    // else each arm's first closing in the seating waits for the other's to build them.
    let built = match built {
        Some(built) => built,
        None => {
            let (part, arms) = rayon::join(
                || {
                    for robot in &scene.robots {
                        pregrasp_collision::prepare_closing(&robot.gripper_model());
                    }
                    match known {
                        Some(k) => Ok(k.part()),
                        None => ObjectGeometry::new(mesh)
                            .map(Arc::new)
                            .map_err(PlanError::Mesh),
                    }
                },
                || crate::context::arm_models(scene),
            );
            Built {
                part: part?,
                arms: Arc::new(arms?),
                memo: Arc::default(),
            }
        }
    };
    let (part, arms) = (built.part.clone(), &*built.arms);
    // A part known from an earlier plan (a replan loop) keeps its seating. A new part's
    // closings at G_s do not depend on it: they run beside it.
    let seating = || match options
        .known
        .as_deref()
        .and_then(|k| k.seating(scene, mesh, rule))
    {
        Some(seated) => (seated, None),
        None => {
            let (seated, power) = crate::seat::planned_scene(scene, &part, arms, rule);
            (seated, Some(power))
        }
    };
    let ((seated, power), support) = match known {
        Some(_) => (seating(), None),
        None => rayon::join(seating, || {
            Some(crate::context::support_closings(
                &part,
                arms,
                &scene.grasps.support,
            ))
        }),
    };
    // The scene's power grasps, before seating: the plan file says how each moved across.
    let given = scene.grasps.power;
    let scene = seated.as_ref().map_or(scene, |(s, _)| s);
    let mut ctx = PlanningContext::with_part(
        scene,
        mesh,
        options.known.as_deref(),
        Some(part),
        crate::context::KnownClosings { support, power },
        Some(arms.clone()),
    )?;
    let t_grips = t_ctx.elapsed();
    ctx.fixed_rot_start = options.fixed_rot_start;
    let ctx = ctx;
    let candidates = axes.candidates;
    on_candidates(candidates.len());

    let t1 = Instant::now();
    let start = Moment::at_rest(ctx.starts(), ctx.p_init);
    let start_problem = ctx.check(&start).err().map(Rejection::StartBlocked);
    let wanted = |c: &RotationAxisCandidate| {
        options
            .only
            .as_ref()
            .is_none_or(|only| only.contains(&c.id))
    };
    // One hull for the whole plan: Algorithm 1's, for the checker's lowest points and the
    // grip check's support contacts (none when the mesh has no hull: each falls back alike).
    let hull = (!axes.hull.vertices.is_empty()).then_some(&axes.hull.vertices[..]);
    let hold_check = HoldCheck::new(scene, mesh, hull);
    let carry_check = hold_check.carry_check(&ctx);
    // Every candidate gets an outcome below, whatever happens here: ranking reads them all. A
    // probe asks the carry check of each pose Algorithm 2 finds (a small cone program, about
    // 0.15 ms) as soon as it is found, beside the other candidates' poses; the candidates
    // planned later reuse the verdicts.
    let (poses, carries): (Vec<Option<PoseOutcome>>, Vec<Option<CarryVerdict>>) =
        if start_problem.is_some() {
            candidates.iter().map(|_| (None, None)).unzip()
        } else {
            candidates
                .par_iter()
                .map(|c| {
                    let pose = wanted(c).then(|| object_pose_for_power_grasp(&ctx, c));
                    let carry = match &pose {
                        Some(Ok(pose)) if probe => Some(carry_check.check(&pose.p_obj)),
                        _ => None,
                    };
                    (pose, carry)
                })
                .unzip()
        };
    let t_poses = t1.elapsed();

    let t2 = Instant::now();
    let header = {
        let mut h = plan_file_header(scene, PlanStatus::Planned, None);
        // Moved deeper (seated on the palm) or out (held at the fingertips): each its own key.
        let moved = seated.as_ref().map_or([0.0; 2], |(_, moved)| *moved);
        let split = |out: f64| {
            let part = moved.map(|m| (out * m).max(0.0));
            (part != [0.0; 2]).then_some(part)
        };
        (h.grasps.seated, h.grasps.fingertips) = (split(1.0), split(-1.0));
        // Moved across the bar onto its mid-plane (off it, or held at the fingertips), to the
        // micrometre.
        let across = [0, 1].map(|k| {
            let x = (given[k].inverse() * scene.grasps.power[k]).translation.x;
            (x * 1e6).round() / 1e6 + 0.0
        });
        h.grasps.centred = (across != [0.0; 2]).then_some(across);
        h.candidates = candidates
            .iter()
            .map(RotationAxisCandidate::to_json)
            .collect();
        h
    };
    let part = ctx.world.part();
    let set = plan_set(scene, &candidates);
    let checker =
        PlanChecker::sharing_models(&set, mesh, ctx.world.arms(), part, Some(&ctx.grips), hull);
    let reject_uncarried = scene.physics.reject && scene.physics.reject_uncarried;
    // Power grasps that cannot carry the part at the gripper's largest force are refused with
    // `[physics] reject`; those short of the safety factor, or that no force carries, with
    // `reject_uncarried` ([`Uncarried::beyond_gripper`]).
    let refusal = |carry: &CarryVerdict| match *carry {
        Some(Err(why)) if scene.physics.reject && (reject_uncarried || why.beyond_gripper()) => {
            Some(why)
        }
        _ => None,
    };
    // `known`: the carry check's verdict at this pose where a probe has it already.
    let evaluate = |candidate: &RotationAxisCandidate, pose: PowerGraspPose, known: Option<_>| {
        // The carry check needs P_obj alone: where its verdict is known, or with `[physics]
        // reject_uncarried`, it comes first, and a candidate it refuses gets no motions;
        // otherwise it is asked only of a candidate that gets them.
        let carry_of =
            |pose: &PowerGraspPose| known.unwrap_or_else(|| carry_check.check(&pose.p_obj));
        let first = reject_uncarried || known.is_some();
        let mut carry = None;
        if first {
            carry = carry_of(&pose);
            if let Some(reason) = refusal(&carry) {
                progress();
                return CandidateOutcome::Uncarried { pose, reason };
            }
        }
        // The grip check reads μ_rot alone: Algorithm 3 asks it once a candidate's straight
        // lines hold, and a rotation the pinch cannot hold gets no transits.
        let hold = |rot: &RotationPath| {
            let plan = rot_only_plan(&ctx, candidate.id, candidate.score, &pose, rot);
            match ctx
                .clock
                .time(Stage::Hold, || hold_check.check(&set, &plan))
            {
                Some(HoldResult {
                    rejection: Some(reason),
                    ..
                }) => Err(Unheld(reason)),
                held => Ok(held.map(|h| h.json)),
            }
        };
        let outcome = match integrated_path(&ctx, &built.memo, candidate, &pose, hold) {
            Ok((path, physics)) => {
                let pinch = physics.as_ref().and_then(|p| p.grip_force_recommended);
                let id = (candidate.id, candidate.score);
                if !first {
                    carry = carry_of(&pose);
                    if let Some(reason) = refusal(&carry) {
                        progress();
                        return CandidateOutcome::Uncarried { pose, reason };
                    }
                }
                let plan = output::plan(&ctx, id, &pose, &path, pinch, carry.as_ref());
                let (check, closest_grasp_to_support) = match &checker {
                    Ok(checker) => ctx
                        .clock
                        .time(Stage::Recheck, || verify(checker, &set, &plan)),
                    Err(e) => (
                        Some(FailedRule {
                            rule: 0,
                            detail: e.to_string(),
                        }),
                        None,
                    ),
                };
                CandidateOutcome::Planned {
                    pose,
                    path: Box::new(path),
                    plan: Box::new(plan),
                    physics: physics.map(Box::new),
                    carry,
                    check,
                    closest_grasp_to_support,
                }
            }
            Err(NoPath::Motions(failure)) => CandidateOutcome::NoPath { pose, failure },
            Err(NoPath::Refused(reason)) => CandidateOutcome::Unheld { pose, reason },
        };
        progress();
        outcome
    };
    // Algorithm 2's verdicts are final; candidates with a pose go to Algorithm 3 in waves.
    let mut outcomes: Vec<CandidateOutcome> = Vec::with_capacity(poses.len());
    let mut pending: Vec<(usize, PowerGraspPose)> = Vec::new();
    for (k, pose) in poses.into_iter().enumerate() {
        outcomes.push(match pose {
            None if start_problem.is_some() => CandidateOutcome::StartBlocked,
            None => CandidateOutcome::Skipped,
            Some(Err(rejection)) => CandidateOutcome::NoPose(rejection),
            Some(Ok(pose)) => {
                pending.push((k, pose));
                CandidateOutcome::NotEvaluated
            }
        });
    }
    for (k, o) in outcomes.iter().enumerate() {
        if !matches!(o, CandidateOutcome::NotEvaluated) && k < candidates.len() {
            progress();
        }
    }
    // A probe plans the candidates whose power grasps carry the part first, and stops where
    // none of them gets a plan: the pass would be uncarried. Their outcomes are kept for the
    // waves below, which take them where they come to those candidates.
    let mut early: Vec<Option<CandidateOutcome>> = outcomes.iter().map(|_| None).collect();
    let verdict = |k: usize| carries[k].as_ref().map(|v| v.as_ref().map(|r| r.is_ok()));
    let all_known = pending
        .iter()
        .all(|(k, _)| verdict(*k).is_some_and(|v| v.is_some()));
    if probe && !pending.is_empty() && all_known {
        let carried: Vec<(usize, PowerGraspPose)> = pending
            .iter()
            .filter(|(k, _)| verdict(*k) == Some(Some(true)))
            .cloned()
            .collect();
        let done: Vec<(usize, CandidateOutcome)> = carried
            .into_par_iter()
            .map(|(k, pose)| (k, evaluate(&candidates[k], pose, carries[k])))
            .collect();
        let planned = done.iter().any(|(_, o)| o.planned_and_carried());
        if !planned {
            let fingertips = seated
                .as_ref()
                .is_some_and(|(_, m)| m.iter().any(|&m| m < 0.0));
            return Ok((Pass::NoneCarries { fingertips }, built));
        }
        for (k, outcome) in done {
            early[k] = Some(outcome);
        }
    }
    let wave = options.wave.max(1);
    let mut pending = pending.into_iter().peekable();
    while pending.peek().is_some() {
        let batch: Vec<(usize, PowerGraspPose, Option<CandidateOutcome>)> = pending
            .by_ref()
            .take(wave)
            .map(|(k, pose)| (k, pose, early[k].take()))
            .collect();
        let done: Vec<(usize, CandidateOutcome)> = batch
            .into_par_iter()
            .map(|(k, pose, known)| {
                let outcome = known.unwrap_or_else(|| evaluate(&candidates[k], pose, carries[k]));
                (k, outcome)
            })
            .collect();
        for (k, outcome) in done {
            outcomes[k] = outcome;
        }
        if let Some(&(next, _)) = pending.peek() {
            if ranked_beyond(
                &candidates,
                &outcomes,
                options.max_plans,
                candidates[next].score,
            ) {
                break;
            }
        }
    }
    for _ in pending {
        progress();
    }
    let t_paths = t2.elapsed();

    // Ranking: candidates are sorted best first by S_rot; among equal scores the plan that
    // needs the smaller grip force comes first.
    let mut file = header;
    let mut kept = 0;
    let scores: Vec<f64> = candidates.iter().map(|c| c.score).collect();
    for i in rank(&scores, |i| required_force(&outcomes[i])) {
        let (candidate, outcome) = (&candidates[i], &outcomes[i]);
        let mut json = candidate.to_json();
        match outcome {
            CandidateOutcome::Planned {
                pose,
                plan,
                physics,
                check,
                carry,
                ..
            } => {
                json.theta_goal = Some(pose.theta_goal);
                if let Some(rule) = check {
                    let rejection = Rejection::CheckFailed(rule.clone());
                    json.outcome = Outcome::rejected(rejection.named(&ctx.names).to_string());
                } else if kept < options.max_plans {
                    json.outcome = Outcome::Planned;
                    let mut entry = plan_json(&set.arms, plan);
                    entry.physics = physics.as_deref().cloned();
                    if let (Some(p), Some(Err(why))) = (entry.physics.as_mut(), carry) {
                        p.warnings.push(why.to_string());
                    }
                    file.plans.push(entry);
                    kept += 1;
                } else {
                    json.outcome = Outcome::rejected(format!(
                        "outranked (only the best {} plans are kept)",
                        options.max_plans
                    ));
                }
            }
            CandidateOutcome::NoPose(rejection) => {
                json.theta_goal = None;
                json.outcome = Outcome::rejected(rejection.named(&ctx.names).to_string());
            }
            CandidateOutcome::NoPath { pose, failure } => {
                json.theta_goal = Some(pose.theta_goal);
                json.outcome = Outcome::rejected(failure.to_string());
            }
            CandidateOutcome::Unheld { pose, reason } => {
                json.theta_goal = Some(pose.theta_goal);
                json.outcome = Outcome::rejected(reason.to_string());
            }
            CandidateOutcome::Uncarried { pose, reason } => {
                json.theta_goal = Some(pose.theta_goal);
                json.outcome = Outcome::rejected(reason.to_string());
            }
            CandidateOutcome::Skipped => {
                json.theta_goal = None;
                json.outcome =
                    Outcome::not_evaluated("not re-planned (the plan keeps another candidate)");
            }
            CandidateOutcome::StartBlocked => {
                json.theta_goal = None;
                json.outcome = Outcome::rejected(match &start_problem {
                    Some(problem) => problem.named(&ctx.names).to_string(),
                    None => "start configurations in collision".to_string(),
                });
            }
            CandidateOutcome::NotEvaluated => {
                json.theta_goal = None;
                json.outcome = Outcome::not_evaluated(format!(
                    "the best {} plans came from candidates with higher S_rot",
                    options.max_plans
                ));
            }
        }
        file.candidates[candidate.id] = json;
    }
    if file.plans.is_empty() {
        file.status = PlanStatus::NoPlan;
        file.reason = Some(match &start_problem {
            Some(problem) => problem.named(&ctx.names).to_string(),
            None => no_plan_reason(&ctx, &outcomes),
        });
    }
    let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
    file.timing_ms.insert("axes".into(), ms(t_axes));
    file.timing_ms.insert("grips".into(), ms(t_grips));
    file.timing_ms.insert("poses".into(), ms(t_poses));
    file.timing_ms.insert("paths".into(), ms(t_paths));
    for (key, spent) in ctx.clock.ms() {
        file.timing_ms.insert(key.into(), spent);
    }
    file.timing_ms.insert("total".into(), ms(t0.elapsed()));
    let report = PlanReport {
        file,
        physics_note: hold_check.into_unchecked(),
        candidates,
        outcomes,
        hull: (!axes.hull.vertices.is_empty()).then_some(axes.hull),
    };
    Ok((Pass::Planned(Box::new(report)), built))
}

/// Algorithm 1 for `scene` on `mesh`, on the hull `known` has of this mesh when it has one.
pub(crate) fn axes_of(scene: &Scene, mesh: &Mesh, known: Option<&PartKnowledge>) -> AxesResult {
    let hull = known.filter(|k| k.fits_mesh(mesh)).and_then(|k| k.hull());
    rotation_axis_candidates_with_hull(
        mesh,
        hull.map(|h| &**h),
        &scene.object.pose,
        scene.support_height,
        &scene.planner,
    )
}

/// The first rule `plan` (checked as a plan of `header`) fails, if any, and how close a
/// grasping gripper comes to the support along it (from the same check).
fn verify(checker: &PlanChecker, set: &PlanSet, plan: &Plan) -> (Option<FailedRule>, Option<f64>) {
    let report = checker.check_own_plans(set, std::slice::from_ref(plan));
    (FailedRule::first(&report), report.closest_grasp_to_support)
}
