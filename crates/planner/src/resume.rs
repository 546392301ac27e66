//! Re-planning what is left of a plan once part of it has run, with the part measured where
//! it is now (`P'`): `--from mas1` (`sup1` and `rot` have run: the supportive gripper holds the
//! part, turned) and `--from sup2` (`mas1` has run too: both grippers hold it).
//!
//! The grippers that hold the part say how they hold it: the supportive arm at `q_s` (the end
//! of `rot`) holds `G_s' = P'⁻¹ · T_flange(q_s) · T_precision`, and after `mas1` the master at
//! `q_m` holds `G_p' = P'⁻¹ · T_flange(q_m) · T_power` — the planned grasps when the
//! measurement gives them back within 1e-9, so that an unchanged pose resumes the nominal plan
//! exactly. The segments that ran are kept as they ran; along `rot` the part is where the
//! gripper held it, `T_flange(q_k) · T_precision · G_s'⁻¹` (the gripper turned about the axis
//! line, so the part it held turned about the same line), and `object.initial_pose` is the
//! first of those poses. What is left is planned at `P'` as Algorithm 3 plans it (the same
//! motion seeds), the grip check runs on `rot` again, and the whole file is re-checked: a
//! measurement the executed rotation cannot explain (the part slid in the pinch by more than
//! the check's tolerances) is refused with the rule it breaks, and one that would have had the
//! part float above or sink into the support when `rot` began (by more than
//! [`REST_TOLERANCE`]) is refused as a bad measurement.

use nalgebra::Isometry3;
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::{
    FingersJson, PadContactJson, PlanFile, PlanJson, PlanStatus, PoseJson, SegmentJson, SegmentName,
};
use pregrasp_io::plan_model::segment_json;
use pregrasp_io::scene::Scene;
use pregrasp_robot::Joints;

use crate::check::check_plan;
use crate::context::{arm_models, PlanningContext};
use crate::hold::HoldCheck;
use crate::output::{
    fingers_of, plan_file_header, power_grip_forces, reach_segment, set_pinch_force,
};
use crate::paths::{final_grasp_free, motion_seed, MAX_IK_TRIES};
use crate::pipeline::PlanReport;
use crate::poses::PowerGraspPose;
use crate::reach::{reach, ReachMotion, ReachQuery};
use crate::rejection::{FailedRule, MotionFailure, PathFailure};
use crate::replan::{held_grasp, RanPlan, ReplanRoute, Replanned, ResumeError};
use pregrasp_model::timeline::Moment;

/// How far (m) the part held as measured may have been from resting on the support when `rot`
/// began: the check's tolerance on the rotation axis ([`crate::check::AXIS_MOTION_TOLERANCE`]).
pub const REST_TOLERANCE: f64 = crate::check::AXIS_MOTION_TOLERANCE;

/// Where a plan resumes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resume {
    /// `sup1` and `rot` have run: `mas1` and `sup2` are planned.
    Mas1,
    /// `sup1`, `rot` and `mas1` have run: `sup2` is planned.
    Sup2,
}

impl Resume {
    /// The first segment planned again.
    pub fn segment(self) -> SegmentName {
        match self {
            Resume::Mas1 => SegmentName::Mas1,
            Resume::Sup2 => SegmentName::Sup2,
        }
    }
}

/// Why what is left of a plan could not be planned again.
#[derive(Clone, Debug, PartialEq)]
pub enum ResumeFailure {
    /// No motion left: the last failure.
    Path(PathFailure),
    /// The plan with the measured part fails a rule of the plan check.
    CheckFailed(FailedRule),
}

impl std::fmt::Display for ResumeFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ResumeFailure::Path(p) => p.fmt(f),
            ResumeFailure::CheckFailed(rule) => {
                write!(f, "the plan with the measured part fails {rule}")
            }
        }
    }
}

/// Re-plans what is left of plan `plan_index` of `nominal` from `from`, the part measured at
/// `object_pose` (see the module documentation). `route` is [`ReplanRoute::KeptCandidate`]
/// when it planned, [`ReplanRoute::CandidateFailed`] (no plan, with the reason) when not.
pub fn replan_remaining(
    scene: &Scene,
    mesh: &Mesh,
    nominal: &PlanFile,
    plan_index: usize,
    object_pose: Isometry3<f64>,
    from: Resume,
) -> Result<Replanned, ResumeError> {
    let ran = RanPlan::new(nominal, plan_index)?;
    // The power grasps the nominal plan was made with (seated on the palm where the planner
    // moved them, `crate::seat`).
    let mut planned = scene.clone();
    planned.grasps.power = nominal.grasps.power.each_ref().map(PoseJson::to_isometry);
    let scene = &planned;
    let plan = ran.plan;
    let (sup1, rot, mas1) = (
        ran.segment(SegmentName::Sup1)?,
        ran.segment(SegmentName::Rot)?,
        ran.segment(SegmentName::Mas1)?,
    );
    let sup = ran.arm(scene, "supportive", &plan.supportive)?;
    let mas = ran.arm(scene, "master", &plan.master)?;
    let arms = arm_models(scene)?;
    let q_s = rot.points.last().expect("a segment with points").q;
    let q_m = mas1.points.last().expect("a segment with points").q;
    let precision = arms[sup].gripper.precision_point();

    // The grasps as the grippers hold them, and the part's start as `rot` then had it.
    let mut moved = scene.clone();
    let p_inv = object_pose.inverse();
    moved.grasps.support = held_grasp(
        p_inv * arms[sup].flange_world(&q_s) * precision,
        &scene.grasps.support,
    );
    if from == Resume::Sup2 {
        let power = arms[mas].gripper.power_point();
        moved.grasps.power[mas] = held_grasp(
            p_inv * arms[mas].flange_world(&q_m) * power,
            &scene.grasps.power[mas],
        );
    }
    let g_s = moved.grasps.support;
    let part_at = |q: &Joints| arms[sup].flange_world(q) * precision * g_s.inverse();
    let moved_rot = g_s != scene.grasps.support;
    if moved_rot {
        // The part the gripper held must have lain on the support when `rot` began.
        let start = part_at(&rot.points[0].q);
        let lowest = mesh
            .vertices
            .iter()
            .map(|v| (start * v).z)
            .fold(f64::INFINITY, f64::min);
        let off = lowest - (scene.support_height + scene.planner.lift);
        if off.abs() > REST_TOLERANCE {
            return Err(ResumeError::Measurement {
                off,
                tolerance: REST_TOLERANCE,
            });
        }
        let lift = Isometry3::translation(0.0, 0.0, -moved.planner.lift);
        moved.object.pose = lift * start;
    }

    let ctx = PlanningContext::new(&moved, mesh)?;
    let starts = ctx.starts();
    let seed = moved.planner.seed;
    let id = plan.candidate;
    let at_goal = |arm: usize, grasp: &Isometry3<f64>, point: Isometry3<f64>, grip| {
        ctx.free_ik(
            arm,
            &(object_pose * grasp * point.inverse()),
            &object_pose,
            grip,
        )
    };
    let pose = PowerGraspPose {
        theta_goal: nominal
            .candidates
            .iter()
            .find(|c| c.id == id)
            .and_then(|c| c.theta_goal)
            .unwrap_or(0.0),
        p_obj: object_pose,
        grasp_axis_distance: [0.0; 2],
        master: mas,
        supportive: sup,
        power_ik: [0, 1].map(|arm| {
            let point = ctx.arm(arm).gripper.power_point();
            at_goal(arm, &moved.grasps.power[arm], point, ctx.power_grip(arm))
        }),
        support_ik: at_goal(sup, &g_s, precision, ctx.support_grip(sup)),
    };

    // What is left, as Algorithm 3 plans it: μ_mas1 with the supportive arm holding the part,
    // then μ_sup2 with the master holding it.
    let mas1_scene = Moment::at_rest(starts, object_pose).holding(sup, q_s, ctx.support_grip(sup));
    let masters: Vec<Joints> = match from {
        Resume::Sup2 => vec![q_m],
        Resume::Mas1 => pose.power_ik[mas]
            .free(&ctx)
            .take(MAX_IK_TRIES)
            .copied()
            .collect(),
    };
    let mut failure = PathFailure::NoPowerIk;
    let failed = |stage, cause| PathFailure::Motion { stage, cause };
    let mut found = None;
    'master: for c_ik_p in masters {
        let mas1_motion: Option<ReachMotion> = match from {
            Resume::Sup2 => None,
            Resume::Mas1 => {
                let query = ReachQuery {
                    arm: mas,
                    scene: &mas1_scene,
                    from: starts[mas],
                    goal: c_ik_p,
                    retreat: false,
                    seed: motion_seed(seed, id, 2),
                };
                match reach(&ctx, &query) {
                    Ok(m) => Some(m),
                    Err(f) => {
                        failure = failed(SegmentName::Mas1, MotionFailure::Reach(f));
                        continue;
                    }
                }
            }
        };
        let sup2_scene =
            Moment::at_rest(starts, object_pose).holding(mas, c_ik_p, ctx.power_grip(mas));
        for goal in pose.power_ik[sup].free(&ctx).take(MAX_IK_TRIES) {
            if let Err(f) = final_grasp_free(&ctx, &sup2_scene, sup, goal) {
                failure = failed(SegmentName::Sup2, f);
                continue;
            }
            let query = ReachQuery {
                arm: sup,
                scene: &sup2_scene,
                from: q_s,
                goal: *goal,
                retreat: true,
                seed: motion_seed(seed, id, 3),
            };
            match reach(&ctx, &query) {
                Ok(sup2) => {
                    found = Some((mas1_motion, sup2));
                    break 'master;
                }
                Err(f) => failure = failed(SegmentName::Sup2, MotionFailure::Reach(f)),
            }
        }
    }

    let mut header = plan_file_header(&moved, PlanStatus::Planned, None);
    header.candidates = nominal.candidates.clone();
    header.grasps.seated = nominal.grasps.seated;
    header.grasps.fingertips = nominal.grasps.fingertips;
    header.grasps.centred = nominal.grasps.centred;
    let no_plan = |mut header: PlanFile, failure: ResumeFailure| {
        header.status = PlanStatus::NoPlan;
        header.reason = Some(format!("replan --from {}: {failure}", from.segment()));
        Replanned {
            report: report(header),
            route: ReplanRoute::CandidateFailed,
        }
    };
    let Some((mas1_motion, sup2)) = found else {
        return Ok(no_plan(header, ResumeFailure::Path(failure)));
    };

    // The file: the segments that ran, then the ones planned now.
    let names = &ctx.names;
    let mut rot_ran = rot.clone();
    if moved_rot {
        for point in &mut rot_ran.points {
            point.object_pose = Some(PoseJson::from(&part_at(&point.q)));
        }
    }
    rot_ran.grip_width = Some(ctx.support_width(sup));
    rot_ran.fingers = fingers_of(ctx.support_grip(sup)).map(FingersJson::from);
    rot_ran.pad_contact = ctx.support_pads[sup].map(PadContactJson::from);
    // The grip and carry checks (the part's mass, once).
    let hold = HoldCheck::new(&moved, mesh, None);
    let carry = hold.carry_check(&ctx).check(&pose.p_obj);
    let power = power_grip_forces(&ctx, &pose, carry.as_ref());
    let mas1_segment: SegmentJson = match &mas1_motion {
        Some(m) => segment_json(
            &names[mas],
            &reach_segment(
                (SegmentName::Mas1, mas),
                (
                    ctx.power_width(mas),
                    ctx.power_grip(mas),
                    power.map(|f| f.mas1),
                ),
                m,
            ),
        ),
        None => mas1.clone(),
    };
    let sup2_segment = segment_json(
        &names[sup],
        &reach_segment(
            (SegmentName::Sup2, sup),
            (
                ctx.power_width(sup),
                ctx.power_grip(sup),
                power.map(|f| f.sup2),
            ),
            &sup2,
        ),
    );
    let segments = vec![sup1.clone(), rot_ran, mas1_segment, sup2_segment];
    let resumed = PlanJson {
        candidate: id,
        score: plan.score,
        master: names[mas].clone(),
        supportive: names[sup].clone(),
        object_goal_pose: PoseJson::from(&pose.p_obj),
        segments,
        physics: None,
        robustness: None,
    };
    let mut file = header;
    file.plans = vec![resumed];
    // The grip check reads the plan as written (the file's poses, read back).
    file.plans[0].physics = file
        .to_model()
        .ok()
        .and_then(|set| hold.check(&set, &set.plans[0]))
        .map(|h| h.json);
    if let (Some(p), Some(Err(why))) = (file.plans[0].physics.as_mut(), &carry) {
        p.warnings.push(why.to_string());
    }
    set_pinch_force(&mut file.plans[0]);
    let verdict = check_plan(&file, mesh);
    if let Some(rule) = FailedRule::first(&verdict) {
        file.plans.clear();
        return Ok(no_plan(file, ResumeFailure::CheckFailed(rule)));
    }
    Ok(Replanned {
        report: report(file),
        route: ReplanRoute::KeptCandidate,
    })
}

/// A report of `file` alone.
fn report(file: PlanFile) -> PlanReport {
    PlanReport {
        file,
        physics_note: None,
        candidates: Vec::new(),
        outcomes: Vec::new(),
        hull: None,
    }
}
