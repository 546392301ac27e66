//! Turning the pipeline's results into the plan file (`plan-format.md`).

use std::collections::BTreeMap;

use nalgebra::Isometry3;
use pregrasp_io::plan_file::{
    FingersJson, GraspsJson, ObjectJson, PlanFile, PlanJson, PlanStatus, PointJson, PoseJson,
    RobotJson, RobotModel, SceneRef, SegmentJson, SegmentName, UrdfJson, PLAN_FORMAT,
};
use pregrasp_io::scene::Scene;
use pregrasp_robot::{GripperState, Joints};

use crate::context::PlanningContext;
use crate::paths::IntegratedPath;
use crate::poses::PowerGraspPose;
use crate::reach::ReachMotion;
use crate::rotate::RotationPath;
use crate::timing::{scaled, time_along, CONTACT_SCALE};

/// Everything of the plan file that does not depend on the planning result.
pub fn plan_file_header(scene: &Scene, status: PlanStatus, reason: Option<String>) -> PlanFile {
    let robots = scene.robots.clone().map(|r| {
        let gripper = r.gripper_model();
        RobotJson {
            name: r.name.clone(),
            model: r.arm.ur.map_or(RobotModel::Described, RobotModel::Builtin),
            base: PoseJson::from(&r.base),
            joint_names: match &r.urdf {
                Some(u) => u.joint_names.clone(),
                None => r.arm.joint_names.to_vec(),
            },
            start: r.start,
            precision_point: PoseJson::from(&gripper.precision_point()),
            power_point: PoseJson::from(&gripper.power_point()),
            urdf: r.urdf.as_ref().map(|u| UrdfJson {
                file: u.entry.clone(),
                base_link: u.base_link.clone(),
                tool_link: u.tool_link.clone(),
                held: u.held.iter().cloned().collect(),
                allow_collisions: u.allowed.clone(),
            }),
            gripper: r.jaws.as_ref().map(|_| "urdf".to_string()),
        }
    });
    PlanFile {
        format: PLAN_FORMAT.to_string(),
        scene: SceneRef {
            name: scene.name.clone(),
            file: scene.file.display().to_string(),
            file_from_plan: None,
        },
        status,
        reason,
        support_height: scene.support_height,
        planner: scene.planner.to_json(),
        object: ObjectJson {
            mesh: scene.object.mesh_path.display().to_string(),
            mesh_from_plan: None,
            scale: scene.object.scale,
            initial_pose: PoseJson::from(&scene.initial_object_pose()),
            mass: scene.object.mass,
        },
        robots: robots.into_iter().collect(),
        grasps: GraspsJson {
            power: [
                PoseJson::from(&scene.grasps.power[0]),
                PoseJson::from(&scene.grasps.power[1]),
            ],
            support: PoseJson::from(&scene.grasps.support),
            auto: None,
        },
        candidates: Vec::new(),
        plans: Vec::new(),
        timing_ms: BTreeMap::new(),
    }
}

fn points(q: &[Joints], t: &[f64]) -> Vec<PointJson> {
    q.iter()
        .zip(t)
        .map(|(q, &t)| PointJson {
            t,
            q: *q,
            object_pose: None,
        })
        .collect()
}

/// The fingers of a grip as the plan file records them: the 2F-85's joints (a jaw gripper's
/// state is its `grip_width`).
pub(crate) fn fingers_json(grip: GripperState) -> Option<FingersJson> {
    let GripperState::Closed(f) = grip else {
        return None;
    };
    Some(FingersJson {
        driver: f.driver,
        spring_link: f.spring_link,
    })
}

pub(crate) fn reach_segment(
    (name, robot): (SegmentName, &str),
    (grip_width, grip): (f64, GripperState),
    m: &ReachMotion,
) -> SegmentJson {
    SegmentJson {
        name,
        robot: robot.to_string(),
        kind: name.kind(),
        grasp: name.grasp(),
        retreat_to: m.retreat_to,
        approach_from: Some(m.approach_from),
        grip_width: Some(grip_width),
        fingers: fingers_json(grip),
        pad_contact: None,
        points: points(&m.q, &m.t),
    }
}

/// One plan of the file: the four segments of an integrated path.
pub fn plan_json(
    ctx: &PlanningContext,
    candidate_id: usize,
    score: f64,
    pose: &PowerGraspPose,
    path: &IntegratedPath,
) -> PlanJson {
    let sup = &ctx.names[pose.supportive];
    let mas = &ctx.names[pose.master];
    let segments = vec![
        reach_segment(
            (SegmentName::Sup1, sup),
            (
                ctx.support_width(pose.supportive),
                ctx.support_grip(pose.supportive),
            ),
            &path.sup1,
        ),
        rot_segment(ctx, pose, &path.rot),
        reach_segment(
            (SegmentName::Mas1, mas),
            (ctx.power_width(pose.master), ctx.power_grip(pose.master)),
            &path.mas1,
        ),
        reach_segment(
            (SegmentName::Sup2, sup),
            (
                ctx.power_width(pose.supportive),
                ctx.power_grip(pose.supportive),
            ),
            &path.sup2,
        ),
    ];
    plan_entry(ctx, candidate_id, score, pose, segments)
}

/// A plan-file entry of candidate `candidate_id` with these segments (no `physics` yet).
pub(crate) fn plan_entry(
    ctx: &PlanningContext,
    candidate_id: usize,
    score: f64,
    pose: &PowerGraspPose,
    segments: Vec<SegmentJson>,
) -> PlanJson {
    PlanJson {
        candidate: candidate_id,
        score,
        master: ctx.names[pose.master].clone(),
        supportive: ctx.names[pose.supportive].clone(),
        object_goal_pose: PoseJson::from(&pose.p_obj),
        segments,
        physics: None,
        robustness: None,
    }
}

/// μ_rot as the plan file's `rot` segment: the supportive arm's configurations, timed along θ,
/// with the part's pose at each.
pub fn rot_segment(
    ctx: &PlanningContext,
    pose: &PowerGraspPose,
    rot: &RotationPath,
) -> SegmentJson {
    let arm = ctx.arm(pose.supportive);
    let t = time_along(
        &rot.q,
        &rot.theta,
        &scaled(&arm.max_joint_speed(), CONTACT_SCALE),
        &scaled(&arm.max_joint_accel(), CONTACT_SCALE),
    );
    let points = rot
        .q
        .iter()
        .zip(&t)
        .zip(&rot.object)
        .map(
            |((q, &t), object): ((&Joints, &f64), &Isometry3<f64>)| PointJson {
                t,
                q: *q,
                object_pose: Some(PoseJson::from(object)),
            },
        )
        .collect();
    SegmentJson {
        name: SegmentName::Rot,
        robot: ctx.names[pose.supportive].clone(),
        kind: SegmentName::Rot.kind(),
        grasp: SegmentName::Rot.grasp(),
        retreat_to: None,
        approach_from: None,
        grip_width: Some(ctx.support_width(pose.supportive)),
        fingers: fingers_json(ctx.support_grip(pose.supportive)),
        pad_contact: ctx.support_pads[pose.supportive],
        points,
    }
}

/// A plan-file entry with only its `rot` segment: what the grip check reads, before the reach
/// motions exist.
pub fn rot_only_plan_json(
    ctx: &PlanningContext,
    candidate_id: usize,
    score: f64,
    pose: &PowerGraspPose,
    rot: &RotationPath,
) -> PlanJson {
    plan_entry(
        ctx,
        candidate_id,
        score,
        pose,
        vec![rot_segment(ctx, pose, rot)],
    )
}
