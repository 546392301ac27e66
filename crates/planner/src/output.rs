//! Turning the pipeline's results into the typed model ([`pregrasp_model`]): the cell a run
//! plans for ([`plan_set`]) and each candidate's [`Plan`]; and the plan file's header
//! ([`plan_file_header`]), the part of the file `pregrasp-io` does not get from the model.

use std::collections::BTreeMap;

use nalgebra::Isometry3;
use pregrasp_io::plan_file::{
    GraspsJson, ObjectJson, PlanFile, PlanJson, PlanStatus, PoseJson, SceneRef, PLAN_FORMAT,
};
use pregrasp_io::plan_model::robot_json;
use pregrasp_io::scene::{RobotSpec, Scene};
use pregrasp_model::{
    as_written, ArmSetup, Closing, DescriptionRef, Grasps, ObjectSetup, Plan, PlanSet,
    PlanSettings, RobotModel, Roles, Segment, SegmentName, Waypoint,
};
use pregrasp_robot::{FingerPair, GripperState, Joints};

use crate::axes::RotationAxisCandidate;
use crate::carry::{CarryForces, Uncarried};
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
            seated: None,
            fingertips: None,
            centred: None,
            slid: None,
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

/// The grip forces (N) the power grasps close with, the safety factor included.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PowerGripForces {
    /// The master arm's, closing `mas1`.
    pub mas1: f64,
    /// The supportive arm's, closing `sup2`.
    pub sup2: f64,
}

/// The grip forces of the power grasps of the plan of `pose`, written as `mas1`'s and `sup2`'s
/// `grip_force`: what the carry check of its final state sets ([`crate::carry`]: each
/// gripper's largest force), also where the part is carried only without the safety factor
/// or by no force (a plan kept without `[physics] reject_uncarried`, flagged in its
/// `physics.warnings`), or beyond that force (kept with `reject = false`); none where the check
/// could not run (a part without mass properties: the exports then use their own setting).
pub fn power_grip_forces(
    ctx: &PlanningContext,
    pose: &PowerGraspPose,
    carry: Option<&Result<CarryForces, Uncarried>>,
) -> Option<PowerGripForces> {
    let set = match carry? {
        Ok(forces) => forces.set,
        Err(_) => [0, 1].map(|arm| ctx.scene.robots[arm].gripper_model().grip_force_range().1),
    };
    Some(PowerGripForces {
        mas1: set[pose.master],
        sup2: set[pose.supportive],
    })
}

/// Gives `sup1` of a plan-file entry the pinch's recommended force of its `physics` (none
/// when it has none): after a replan that kept segments of another plan, `sup1`'s force is
/// this plan's, as [`plan`] writes it.
pub(crate) fn set_pinch_force(entry: &mut PlanJson) {
    let force = entry
        .physics
        .as_ref()
        .and_then(|p| p.grip_force_recommended);
    if let Some(seg) = entry
        .segments
        .iter_mut()
        .find(|s| s.name == SegmentName::Sup1)
    {
        seg.grip_force = force;
    }
}

/// A reach (`sup1`, `mas1`) or regrasp (`sup2`) of arm `arm` ending closed at `grip_width`
/// with `grip_force` (N) when known.
pub(crate) fn reach_segment(
    (name, arm): (SegmentName, usize),
    (grip_width, grip, grip_force): (f64, GripperState, Option<f64>),
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
        grip_force,
        points: points(&m.q, &m.t),
    }
}

/// One plan: the four segments of an integrated path. `support_grip_force`: the force (N)
/// the grip check of `rot` recommends for the pinch, when it ran and the pinch holds — the
/// plan's [`Plan::support_grip_force`] and `sup1`'s `grip_force`; the power grasps' come from
/// [`power_grip_forces`].
pub fn plan(
    ctx: &PlanningContext,
    (candidate_id, score): (usize, f64),
    pose: &PowerGraspPose,
    path: &IntegratedPath,
    support_grip_force: Option<f64>,
    carry: Option<&Result<CarryForces, Uncarried>>,
) -> Plan {
    let (sup, mas) = (pose.supportive, pose.master);
    let power = power_grip_forces(ctx, pose, carry);
    let segments = vec![
        reach_segment(
            (SegmentName::Sup1, sup),
            (
                ctx.support_width(sup),
                ctx.support_grip(sup),
                support_grip_force,
            ),
            &path.sup1,
        ),
        rot_segment(ctx, pose, &path.rot),
        reach_segment(
            (SegmentName::Mas1, mas),
            (
                ctx.power_width(mas),
                ctx.power_grip(mas),
                power.map(|f| f.mas1),
            ),
            &path.mas1,
        ),
        reach_segment(
            (SegmentName::Sup2, sup),
            (
                ctx.power_width(sup),
                ctx.power_grip(sup),
                power.map(|f| f.sup2),
            ),
            &path.sup2,
        ),
    ];
    let mut plan = plan_of(candidate_id, score, pose, segments);
    plan.support_grip_force = support_grip_force;
    plan
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
        grip_force: None,
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
