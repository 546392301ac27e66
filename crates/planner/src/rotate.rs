//! μ_rot (paper §VI-A, `RotPath`): the supportive arm turns the part about the axis from P_init
//! to P_obj while holding G_s with a fingertip grasp, the axis resting on the support.
//!
//! As in the paper the path is built backwards from a solution c_IK^s at P_obj: at every step of
//! Δφ towards P_init the IK branch that continues the previous configuration is taken; the path is
//! valid only if no joint changes by more than `max_joint_step` between neighbouring points and
//! every state — and every interpolated state between points — is collision-free (part at its
//! rotated pose, the supportive gripper closed on it, the master arm at its start).

use nalgebra::Isometry3;
use pregrasp_robot::Joints;

use crate::axes::RotationAxisCandidate;
use crate::context::{PlanningContext, MOTION_RESOLUTION};
use crate::poses::PowerGraspPose;
use crate::timeline::{lerp_joints, substeps, Moment};

/// μ_rot from P_init (index 0) to P_obj (last index).
#[derive(Clone, Debug)]
pub struct RotationPath {
    /// Rotation angle θ of each point (rad), from 0 to θ_goal.
    pub theta: Vec<f64>,
    /// Supportive-arm configuration of each point.
    pub q: Vec<Joints>,
    /// Object world pose of each point.
    pub object: Vec<Isometry3<f64>>,
}

/// Why no μ_rot exists from one c_IK^s.
#[derive(Clone, Debug, PartialEq)]
pub enum RotationFailure {
    /// G_s is out of reach at angle θ.
    Unreachable { theta: f64 },
    /// The continuing IK branch jumps by more than `max_joint_step` at angle θ.
    JointJump {
        theta: f64,
        joint: usize,
        delta: f64,
    },
    /// A collision at angle θ, between the named bodies.
    Collision { theta: f64, a: String, b: String },
}

impl RotationFailure {
    pub fn describe(&self) -> String {
        match self {
            RotationFailure::Unreachable { theta } => {
                format!(
                    "μ_rot: support grasp unreachable at θ = {:.1}°",
                    theta.to_degrees()
                )
            }
            RotationFailure::JointJump {
                theta,
                joint,
                delta,
            } => format!(
                "μ_rot: joint {} jumps {:.1}° at θ = {:.1}°",
                joint + 1,
                delta.to_degrees(),
                theta.to_degrees()
            ),
            RotationFailure::Collision { theta, a, b } => {
                format!("μ_rot: {a} touches {b} at θ = {:.1}°", theta.to_degrees())
            }
        }
    }
}

/// The moment of μ_rot at angle `theta` with the supportive arm at `q`.
pub fn rotation_moment(
    ctx: &PlanningContext,
    pose: &PowerGraspPose,
    object: Isometry3<f64>,
    q: Joints,
) -> Moment {
    Moment::at_rest(ctx.starts(), object).holding(pose.supportive, q)
}

/// `RotPath`: μ_rot from one c_IK^s, or why there is none.
pub fn rotation_path(
    ctx: &PlanningContext,
    candidate: &RotationAxisCandidate,
    pose: &PowerGraspPose,
    c_ik_s: &Joints,
) -> Result<RotationPath, RotationFailure> {
    let sup = pose.supportive;
    let arm = ctx.arm(sup);
    let params = &ctx.scene.planner;
    let tool_in_grasp = arm.gripper.precision_point().inverse();
    let base_inv = arm.base.inverse();
    let n = (pose.theta_goal / params.step).round() as usize;
    let weights = ctx.spaces[sup].weights;

    let mut theta = vec![0.0; n + 1];
    let mut q = vec![[0.0; 6]; n + 1];
    let mut object = vec![ctx.p_init; n + 1];
    theta[n] = pose.theta_goal;
    q[n] = *c_ik_s;
    object[n] = pose.p_obj;
    let check = |moment: &Moment, th: f64| -> Result<(), RotationFailure> {
        ctx.check(moment).map_err(|c| RotationFailure::Collision {
            theta: th,
            a: c.a,
            b: c.b,
        })
    };
    check(&rotation_moment(ctx, pose, object[n], q[n]), theta[n])?;

    for k in (0..n).rev() {
        let th = k as f64 * params.step;
        let obj = candidate.rotated_pose(&ctx.p_init, th);
        let target = base_inv * obj * ctx.scene.grasps.support * tool_in_grasp;
        let next = arm
            .kin
            .ik_nearest(&target, &q[k + 1])
            .ok_or(RotationFailure::Unreachable { theta: th })?;
        for j in 0..6 {
            let delta = (next[j] - q[k + 1][j]).abs();
            if delta > params.max_joint_step {
                return Err(RotationFailure::JointJump {
                    theta: th,
                    joint: j,
                    delta,
                });
            }
        }
        // Interpolated states between the two points: joints linearly, angle linearly.
        let steps = substeps(&next, &q[k + 1], &weights, MOTION_RESOLUTION);
        for s in 0..steps {
            let f = s as f64 / steps as f64;
            let qi = lerp_joints(&next, &q[k + 1], f);
            let ti = th + f * (theta[k + 1] - th);
            let oi = candidate.rotated_pose(&ctx.p_init, ti);
            check(&rotation_moment(ctx, pose, oi, qi), ti)?;
        }
        theta[k] = th;
        q[k] = next;
        object[k] = obj;
    }
    Ok(RotationPath { theta, q, object })
}
