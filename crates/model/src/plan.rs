//! A plan set as the crates share it: the cell it was planned for (support, part, arms,
//! grasps), the rotation-axis candidates of Algorithm 1 and the plans of Algorithm 3, each with
//! four typed segments. Poses are isometries (`p_parent = pose · p_child`), joints radians,
//! times seconds, forces newtons; the plan file (`docs/plan-format.md`) is one way to write it
//! down, which `pregrasp-io` reads and writes.

use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion};
use pregrasp_robot::{FingerPair, Gripper, GripperState, Joints};

use crate::terms::{GraspKind, PlanStatus, RobotModel, RotationDirection};
use crate::terms::{SegmentKind, SegmentName};

/// Everything one planning run produced, or a plan file holds.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanSet {
    pub status: PlanStatus,
    /// Why there is no plan (`status = no_plan`), as the planner or the file says it.
    pub reason: Option<String>,
    /// Height of the support plane `z = support_height` in the world (m).
    pub support_height: f64,
    /// How far P_init hovers above the part's resting pose (m; the scene's `[planner] lift`).
    pub lift: f64,
    /// The planner settings a plan is judged by.
    pub settings: PlanSettings,
    pub object: ObjectSetup,
    /// The two arms, in the scene's order; segments and roles index into it.
    pub arms: Vec<ArmSetup>,
    pub grasps: Grasps,
    pub candidates: Vec<Candidate>,
    /// Best first.
    pub plans: Vec<Plan>,
}

/// The scene's `[planner]` values a plan is judged by (all in metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanSettings {
    /// Δd_s: how far above the support an edge may be and still be an axis.
    pub support_distance: f64,
    /// Length of the straight approach that ends every reach.
    pub approach_distance: f64,
    /// Clearance of arm links and grippers from everything they must not touch.
    pub link_clearance: f64,
    /// Clearance of a grasping gripper from the support.
    pub finger_support_clearance: f64,
}

/// The part as placed in the cell.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectSetup {
    /// The mesh's scale to metres.
    pub scale: f64,
    /// P_init in the world, the lift included.
    pub initial_pose: Isometry3<f64>,
    /// The part's mass when the scene gives it (kg).
    pub mass: Option<f64>,
}

/// One arm with its gripper, as planned for.
#[derive(Clone, Debug, PartialEq)]
pub struct ArmSetup {
    pub name: String,
    pub model: RobotModel,
    /// The controller's base frame in the world.
    pub base: Isometry3<f64>,
    /// The six driven joints' names, base to flange.
    pub joint_names: Vec<String>,
    pub start: Joints,
    /// Where a fingertip grasp holds G_s, in the flange frame.
    pub precision_point: Isometry3<f64>,
    /// Where a power grasp holds a bar, in the flange frame.
    pub power_point: Isometry3<f64>,
    /// The robot description the arm comes from, when the scene names one.
    pub description: Option<DescriptionRef>,
    /// The gripper is the jaws of that description (else the Robotiq 2F-85).
    pub jaws_from_description: bool,
}

/// A robot description as the scene named it (`file` relative to the scene's folder).
#[derive(Clone, Debug, PartialEq)]
pub struct DescriptionRef {
    pub file: String,
    pub base_link: String,
    pub tool_link: String,
    /// Joints held still while the planner drives the other six (rad), by name.
    pub held: Vec<(String, f64)>,
    /// Link pairs not checked for self-collision.
    pub allow_collisions: Vec<[String; 2]>,
}

/// The grasps, as poses of the tool point in the object frame: G_p1, G_p2 (by arm) and G_s.
#[derive(Clone, Debug, PartialEq)]
pub struct Grasps {
    pub power: [Isometry3<f64>; 2],
    pub support: Isometry3<f64>,
}

/// One (axis, direction) pair of Algorithm 1 (a `RotationAxisCandidate` as the plan records it).
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    pub id: usize,
    /// The axis' endpoints in the world at P_init.
    pub axis: [Point3<f64>; 2],
    pub direction: RotationDirection,
    pub length: f64,
    /// θ_max (rad).
    pub theta_max: f64,
    /// S_rot.
    pub score: f64,
    /// θ_goal (rad), when Algorithm 2 found P_obj.
    pub theta_goal: Option<f64>,
}

/// Which arm does what: indices into [`PlanSet::arms`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Roles {
    /// Takes its power grasp in `mas1` while the supportive arm holds the turned part.
    pub master: usize,
    /// Pinches G_s, turns the part (`rot`), then regrasps at its power grasp.
    pub supportive: usize,
}

/// One plan: the four motions of both arms for one candidate.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// [`Candidate::id`].
    pub candidate: usize,
    pub score: f64,
    pub roles: Roles,
    /// P_obj: the part's pose once turned (world).
    pub object_goal_pose: Isometry3<f64>,
    /// `sup1`, `rot`, `mas1`, `sup2`, in that order.
    pub segments: Vec<Segment>,
    /// The grip force (N) the grip check of `rot` recommends for the support grasp, when it
    /// ran and the pinch holds (the plan file's `physics.grip_force_recommended`).
    pub support_grip_force: Option<f64>,
}

impl Plan {
    /// The segment called `name`.
    pub fn segment(&self, name: SegmentName) -> Option<&Segment> {
        self.segments.iter().find(|s| s.name == name)
    }

    /// The grip force (N) to close segment `seg` with: its own [`Segment::grip_force`], else,
    /// for the support grasp's closing, [`Plan::support_grip_force`]; `None` for a segment
    /// that does not close (`rot`) or a closing the plan gives no force for.
    pub fn closing_force(&self, seg: &Segment) -> Option<f64> {
        if !seg.kind.closes_at_end() {
            return None;
        }
        seg.grip_force.or(match seg.grasp {
            GraspKind::Support => self.support_grip_force,
            GraspKind::Power => None,
        })
    }
}

/// One motion of one arm.
#[derive(Clone, Debug, PartialEq)]
pub struct Segment {
    pub name: SegmentName,
    /// Index into [`PlanSet::arms`] of the arm that moves.
    pub arm: usize,
    pub kind: SegmentKind,
    /// The grasp its gripper holds when it ends.
    pub grasp: GraspKind,
    /// Index of the point where the straight retreat from the old grasp ends (`sup2`).
    pub retreat_to: Option<usize>,
    /// Index of the point where the straight approach to the grasp begins.
    pub approach_from: Option<usize>,
    /// How the gripper holds the part once closed (at the last point; throughout `rot`).
    pub closing: Closing,
    /// The grip force (N) a closing segment (`sup1`, `mas1`, `sup2`) closes its gripper with:
    /// what its grasp needs, the safety factor included (for `sup1` the pinch's recommended
    /// force); `None` when the plan does not say (and always for `rot`).
    pub grip_force: Option<f64>,
    pub points: Vec<Waypoint>,
}

/// Where a segment's gripper stops closing on the part, as recorded.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Closing {
    /// Gap between the pad faces (m).
    pub width: Option<f64>,
    /// The 2F-85's finger joints where they stop.
    pub fingers: Option<FingerPair>,
    /// Where the pads bear on the part (`rot`).
    pub pad_contact: Option<PadContact>,
}

impl Closing {
    /// The state `gripper` holds the part with: the recorded fingers, else `gripper` closed in
    /// parallel to the recorded width; `None` if neither is recorded.
    pub fn held(&self, gripper: &Gripper) -> Option<GripperState> {
        match (self.fingers, self.width) {
            (Some(f), _) => Some(GripperState::Closed(f)),
            (None, Some(w)) => Some(gripper.at_gap(w)),
            (None, None) => None,
        }
    }
}

/// Where the two pads of a closed gripper bear on the part. `center`: midway between the two
/// patches' centroids, in the frame of the segment's grasp (m); `torsion_radius`: the smaller
/// patch's mean distance from its centroid (m), the `e` of the soft-finger model; `area`: each
/// patch's area (m²), `[+x pad, −x pad]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PadContact {
    pub center: [f64; 3],
    pub torsion_radius: f64,
    pub area: [f64; 2],
}

/// One point of a segment: time since the segment began, the moving arm's joints, and (during
/// `rot`) the part's world pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waypoint {
    pub t: f64,
    pub q: Joints,
    pub object_pose: Option<Isometry3<f64>>,
}

/// A pose's numbers as a plan file writes them: its translation, and its quaternion
/// `[x, y, z, w]` with the sign chosen so that `w ≥ 0` (equal rotations are written equally).
pub fn pose_numbers(pose: &Isometry3<f64>) -> ([f64; 3], [f64; 4]) {
    let t = pose.translation.vector;
    let mut q = *pose.rotation.quaternion();
    if q.w < 0.0 {
        q = -q;
    }
    ([t.x, t.y, t.z], [q.i, q.j, q.k, q.w])
}

/// A pose as a plan file stores it and reads it back: [`pose_numbers`], the quaternion then
/// normalised. Checks that judge a pose the planner is about to write (the grip check of `rot`,
/// the plan checker) judge this one, so that a reader of the file finds the same numbers.
pub fn as_written(pose: &Isometry3<f64>) -> Isometry3<f64> {
    let ([x, y, z], [i, j, k, w]) = pose_numbers(pose);
    let q = UnitQuaternion::from_quaternion(Quaternion::new(w, i, j, k));
    Isometry3::from_parts(Translation3::new(x, y, z), q)
}
