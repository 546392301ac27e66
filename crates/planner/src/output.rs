//! Turning the pipeline's results into the typed model ([`pregrasp_model`]): the cell a run
//! plans for ([`plan_set`]) and each candidate's [`Plan`]; and the plan file's header
//! ([`plan_file_header`]), the part of the file `pregrasp-io` does not get from the model.

use std::collections::BTreeMap;

use nalgebra::Isometry3;
use pregrasp_io::plan_file::{
    GraspsJson, ObjectJson, PlanFile, PlanStatus, PoseJson, SceneRef, PLAN_FORMAT,
};
use pregrasp_io::plan_model::robot_json;
use pregrasp_io::scene::{RobotSpec, Scene};
use pregrasp_model::{
    as_written, ArmSetup, Closing, DescriptionRef, Grasps, ObjectSetup, Plan, PlanSet,
    PlanSettings, RobotModel, Roles, Segment, SegmentName, Waypoint,
};
use pregrasp_robot::{FingerPair, GripperState, Joints};

use crate::axes::RotationAxisCandidate;
use crate::context::PlanningContext;
use crate::paths::IntegratedPath;
use crate::poses::PowerGraspPose;
use crate::reach::ReachMotion;
use crate::rotate::RotationPath;
use crate::timing::{scaled, time_along, CONTACT_SCALE};

/// An arm of the scene as the model states it.
pub fn arm_setup(r: &RobotSpec) -> ArmSetup {
    let gripper = r.gripper_model();
    ArmSetup {
        name: r.name.clone(),
        model: r.arm.ur.map_or(RobotModel::Described, RobotModel::Builtin),
        base: r.base,
        joint_names: match &r.urdf {
            Some(u) => u.joint_names.clone(),
            None => r.arm.joint_names.to_vec(),
        },
        start: r.start,
        precision_point: gripper.precision_point(),
        power_point: gripper.power_point(),
        description: r.urdf.as_ref().map(|u| DescriptionRef {
            file: u.entry.clone(),
            base_link: u.base_link.clone(),
            tool_link: u.tool_link.clone(),
            held: u.held.to_vec(),
            allow_collisions: u.allowed.clone(),
        }),
        jaws_from_description: r.jaws.is_some(),
    }
}

/// The cell `scene` plans for, with Algorithm 1's `candidates` and no plans yet: what the plan
/// checker and the grip check judge a candidate's plan against. Built once per run; every pose
/// as the plan file will hold it ([`as_written`]), so that the checks judge the numbers a
/// reader of the file finds.
pub fn plan_set(scene: &Scene, candidates: &[RotationAxisCandidate]) -> PlanSet {
    let p = &scene.planner;
    let arms = scene
        .robots
        .iter()
        .map(|r| {
            let a = arm_setup(r);
            ArmSetup {
                base: as_written(&a.base),
                precision_point: as_written(&a.precision_point),
                power_point: as_written(&a.power_point),
                ..a
            }
        })
        .collect();
    PlanSet {
        status: PlanStatus::Planned,
        reason: None,
        support_height: scene.support_height,
        lift: p.lift,
        settings: PlanSettings {
            support_distance: p.support_distance,
            approach_distance: p.approach_distance,
            link_clearance: p.link_clearance,
            finger_support_clearance: p.finger_support_clearance,
        },
        object: ObjectSetup {
            scale: scene.object.scale,
            initial_pose: as_written(&scene.initial_object_pose()),
            mass: scene.object.mass,
        },
        arms,
        grasps: Grasps {
            power: scene.grasps.power.each_ref().map(as_written),
            support: as_written(&scene.grasps.support),
        },
        candidates: candidates
            .iter()
            .map(RotationAxisCandidate::to_model)
            .collect(),
        plans: Vec::new(),
    }
}

/// Everything of the plan file that does not depend on the planning result.
pub fn plan_file_header(scene: &Scene, status: PlanStatus, reason: Option<String>) -> PlanFile {
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
        robots: scene
            .robots
            .iter()
            .map(|r| robot_json(&arm_setup(r)))
            .collect(),
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

fn points(q: &[Joints], t: &[f64]) -> Vec<Waypoint> {
    q.iter()
        .zip(t)
        .map(|(q, &t)| Waypoint {
            t,
            q: *q,
            object_pose: None,
        })
        .collect()
}

/// The fingers of a grip as the plan records them: the 2F-85's joints (a jaw gripper's state
/// is its closing width).
pub(crate) fn fingers_of(grip: GripperState) -> Option<FingerPair> {
    match grip {
        GripperState::Closed(f) => Some(f),
        _ => None,
    }
}

/// A reach (`sup1`, `mas1`) or regrasp (`sup2`) of arm `arm` ending closed at `grip_width`.
pub(crate) fn reach_segment(
    (name, arm): (SegmentName, usize),
    (grip_width, grip): (f64, GripperState),
    m: &ReachMotion,
) -> Segment {
    Segment {
        name,
        arm,
        kind: name.kind(),
        grasp: name.grasp(),
        retreat_to: m.retreat_to,
        approach_from: Some(m.approach_from),
        closing: Closing {
            width: Some(grip_width),
            fingers: fingers_of(grip),
            pad_contact: None,
        },
        points: points(&m.q, &m.t),
    }
}

/// One plan: the four segments of an integrated path.
pub fn plan(
    ctx: &PlanningContext,
    candidate_id: usize,
    score: f64,
    pose: &PowerGraspPose,
    path: &IntegratedPath,
) -> Plan {
    let (sup, mas) = (pose.supportive, pose.master);
    let segments = vec![
        reach_segment(
            (SegmentName::Sup1, sup),
            (ctx.support_width(sup), ctx.support_grip(sup)),
            &path.sup1,
        ),
        rot_segment(ctx, pose, &path.rot),
        reach_segment(
            (SegmentName::Mas1, mas),
            (ctx.power_width(mas), ctx.power_grip(mas)),
            &path.mas1,
        ),
        reach_segment(
            (SegmentName::Sup2, sup),
            (ctx.power_width(sup), ctx.power_grip(sup)),
            &path.sup2,
        ),
    ];
    plan_of(candidate_id, score, pose, segments)
}

/// A plan of candidate `candidate_id` with these segments.
pub(crate) fn plan_of(
    candidate_id: usize,
    score: f64,
    pose: &PowerGraspPose,
    segments: Vec<Segment>,
) -> Plan {
    Plan {
        candidate: candidate_id,
        score,
        roles: Roles {
            master: pose.master,
            supportive: pose.supportive,
        },
        object_goal_pose: pose.p_obj,
        segments,
        support_grip_force: None,
    }
}

/// μ_rot as the plan's `rot` segment: the supportive arm's configurations, timed along θ,
/// with the part's pose at each.
pub fn rot_segment(ctx: &PlanningContext, pose: &PowerGraspPose, rot: &RotationPath) -> Segment {
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
            |((q, &t), object): ((&Joints, &f64), &Isometry3<f64>)| Waypoint {
                t,
                q: *q,
                object_pose: Some(*object),
            },
        )
        .collect();
    Segment {
        name: SegmentName::Rot,
        arm: pose.supportive,
        kind: SegmentName::Rot.kind(),
        grasp: SegmentName::Rot.grasp(),
        retreat_to: None,
        approach_from: None,
        closing: Closing {
            width: Some(ctx.support_width(pose.supportive)),
            fingers: fingers_of(ctx.support_grip(pose.supportive)),
            pad_contact: ctx.support_pads[pose.supportive],
        },
        points,
    }
}

/// A plan of candidate `candidate_id` with only its `rot` segment: what the grip check reads,
/// before the reach motions exist. Its poses are as the plan file will hold them
/// ([`as_written`]).
pub fn rot_only_plan(
    ctx: &PlanningContext,
    candidate_id: usize,
    score: f64,
    pose: &PowerGraspPose,
    rot: &RotationPath,
) -> Plan {
    let mut segment = rot_segment(ctx, pose, rot);
    for p in &mut segment.points {
        p.object_pose = p.object_pose.as_ref().map(as_written);
    }
    let mut plan = plan_of(candidate_id, score, pose, vec![segment]);
    plan.object_goal_pose = as_written(&pose.p_obj);
    plan
}
