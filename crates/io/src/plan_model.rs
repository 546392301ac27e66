//! The plan file and the typed model ([`pregrasp_model`]) converted into each other: a file
//! read from disk becomes a [`PlanSet`] for `check`, `physics`, `export` and `view`; the
//! planner's [`Plan`]s become the file's `plans` entries. Names become arm indices on the way
//! in and indices names on the way out; poses become isometries (`PoseJson::to_isometry`) and
//! back (`PoseJson::from`).

use pregrasp_model::{
    ArmSetup, Candidate, Closing, DescriptionRef, Grasps, ObjectSetup, PadContact, Plan, PlanSet,
    PlanSettings, Roles, Segment, Waypoint,
};
use pregrasp_robot::FingerPair;

use crate::plan_file::{
    CandidateJson, FingersJson, PadContactJson, PlanFile, PlanJson, PointJson, PoseJson, RobotJson,
    SegmentJson, UrdfJson,
};
use crate::scene::{DEFAULT_FINGER_SUPPORT_CLEARANCE, DEFAULT_LINK_CLEARANCE};

/// What keeps a plan file from being a plan set: a name that is not one of its robots.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ModelError {
    #[error("plans[{plan}].{role}: {name:?} is not one of the file's robots")]
    UnknownRole {
        plan: usize,
        role: &'static str,
        name: String,
    },
    #[error("plans[{plan}].segments[{segment}].robot: {name:?} is not one of the file's robots")]
    UnknownRobot {
        plan: usize,
        segment: usize,
        name: String,
    },
}

impl PlanFile {
    /// The file as a typed plan set (it has passed [`crate::plan_format::validate`] when it was
    /// read with [`PlanFile::read`]).
    pub fn to_model(&self) -> Result<PlanSet, ModelError> {
        let arm = |name: &str| self.robots.iter().position(|r| r.name == name);
        let mut plans = Vec::with_capacity(self.plans.len());
        for (k, p) in self.plans.iter().enumerate() {
            let role = |role: &'static str, name: &str| {
                arm(name).ok_or_else(|| ModelError::UnknownRole {
                    plan: k,
                    role,
                    name: name.to_string(),
                })
            };
            let roles = Roles {
                master: role("master", &p.master)?,
                supportive: role("supportive", &p.supportive)?,
            };
            let segments = p
                .segments
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    let a = arm(&s.robot).ok_or_else(|| ModelError::UnknownRobot {
                        plan: k,
                        segment: i,
                        name: s.robot.clone(),
                    })?;
                    Ok(segment_of(s, a))
                })
                .collect::<Result<Vec<_>, ModelError>>()?;
            plans.push(Plan {
                candidate: p.candidate,
                score: p.score,
                roles,
                object_goal_pose: p.object_goal_pose.to_isometry(),
                segments,
                support_grip_force: p.physics.as_ref().and_then(|g| g.grip_force_recommended),
            });
        }
        Ok(PlanSet {
            status: self.status,
            reason: self.reason.clone(),
            support_height: self.support_height,
            lift: self.planner.lift,
            settings: PlanSettings {
                support_distance: self.planner.support_distance,
                approach_distance: self.planner.approach_distance,
                link_clearance: self
                    .planner
                    .link_clearance
                    .unwrap_or(DEFAULT_LINK_CLEARANCE),
                finger_support_clearance: self
                    .planner
                    .finger_support_clearance
                    .unwrap_or(DEFAULT_FINGER_SUPPORT_CLEARANCE),
            },
            object: ObjectSetup {
                scale: self.object.scale,
                initial_pose: self.object.initial_pose.to_isometry(),
                mass: self.object.mass,
            },
            arms: self.robots.iter().map(arm_of).collect(),
            grasps: Grasps {
                power: [
                    self.grasps.power[0].to_isometry(),
                    self.grasps.power[1].to_isometry(),
                ],
                support: self.grasps.support.to_isometry(),
            },
            candidates: self.candidates.iter().map(candidate_of).collect(),
            plans,
        })
    }
}

fn arm_of(r: &RobotJson) -> ArmSetup {
    ArmSetup {
        name: r.name.clone(),
        model: r.model,
        base: r.base.to_isometry(),
        joint_names: r.joint_names.clone(),
        start: r.start,
        precision_point: r.precision_point.to_isometry(),
        power_point: r.power_point.to_isometry(),
        description: r.urdf.as_ref().map(|u| DescriptionRef {
            file: u.file.clone(),
            base_link: u.base_link.clone(),
            tool_link: u.tool_link.clone(),
            held: u.held.iter().map(|(k, v)| (k.clone(), *v)).collect(),
            allow_collisions: u.allow_collisions.clone(),
        }),
        jaws_from_description: r.gripper.as_deref() == Some("urdf"),
    }
}

/// The file's `robots[]` entry of an arm.
pub fn robot_json(a: &ArmSetup) -> RobotJson {
    RobotJson {
        name: a.name.clone(),
        model: a.model,
        base: PoseJson::from(&a.base),
        joint_names: a.joint_names.clone(),
        start: a.start,
        precision_point: PoseJson::from(&a.precision_point),
        power_point: PoseJson::from(&a.power_point),
        urdf: a.description.as_ref().map(|u| UrdfJson {
            file: u.file.clone(),
            base_link: u.base_link.clone(),
            tool_link: u.tool_link.clone(),
            held: u.held.iter().cloned().collect(),
            allow_collisions: u.allow_collisions.clone(),
        }),
        gripper: a.jaws_from_description.then(|| "urdf".to_string()),
    }
}

fn candidate_of(c: &CandidateJson) -> Candidate {
    Candidate {
        id: c.id,
        axis: c.axis.map(nalgebra::Point3::from),
        direction: c.direction,
        length: c.length,
        theta_max: c.theta_max,
        score: c.score,
        theta_goal: c.theta_goal,
    }
}

fn segment_of(s: &SegmentJson, arm: usize) -> Segment {
    Segment {
        name: s.name,
        arm,
        kind: s.kind,
        grasp: s.grasp,
        retreat_to: s.retreat_to,
        approach_from: s.approach_from,
        closing: Closing {
            width: s.grip_width,
            fingers: s.fingers.map(|f| FingerPair {
                driver: f.driver,
                spring_link: f.spring_link,
            }),
            pad_contact: s.pad_contact.map(|p| PadContact {
                center: p.center,
                torsion_radius: p.torsion_radius,
                area: p.area,
            }),
        },
        grip_force: s.grip_force,
        points: s
            .points
            .iter()
            .map(|p| Waypoint {
                t: p.t,
                q: p.q,
                object_pose: p.object_pose.as_ref().map(PoseJson::to_isometry),
            })
            .collect(),
    }
}

impl From<FingerPair> for FingersJson {
    fn from(f: FingerPair) -> Self {
        FingersJson {
            driver: f.driver,
            spring_link: f.spring_link,
        }
    }
}

impl From<PadContact> for PadContactJson {
    fn from(p: PadContact) -> Self {
        PadContactJson {
            center: p.center,
            torsion_radius: p.torsion_radius,
            area: p.area,
        }
    }
}

/// The file's entry of `plan` (no `physics`, no `robustness`: the planner adds them), with the
/// arms' names from `arms`.
pub fn plan_json(arms: &[ArmSetup], plan: &Plan) -> PlanJson {
    PlanJson {
        candidate: plan.candidate,
        score: plan.score,
        master: arms[plan.roles.master].name.clone(),
        supportive: arms[plan.roles.supportive].name.clone(),
        object_goal_pose: PoseJson::from(&plan.object_goal_pose),
        segments: plan
            .segments
            .iter()
            .map(|s| segment_json(&arms[s.arm].name, s))
            .collect(),
        physics: None,
        robustness: None,
    }
}

/// The file's entry of segment `s` of the arm called `robot`.
pub fn segment_json(robot: &str, s: &Segment) -> SegmentJson {
    SegmentJson {
        name: s.name,
        robot: robot.to_string(),
        kind: s.kind,
        grasp: s.grasp,
        retreat_to: s.retreat_to,
        approach_from: s.approach_from,
        grip_width: s.closing.width,
        grip_force: s.grip_force,
        fingers: s.closing.fingers.map(FingersJson::from),
        pad_contact: s.closing.pad_contact.map(PadContactJson::from),
        points: s
            .points
            .iter()
            .map(|p| PointJson {
                t: p.t,
                q: p.q,
                object_pose: p.object_pose.as_ref().map(PoseJson::from),
            })
            .collect(),
    }
}
