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
use crate::context::{world_state, PlanningContext, FINE_RESOLUTION};
use crate::poses::PowerGraspPose;
use pregrasp_collision::WorldState;
use pregrasp_model::timeline::{lerp_joints, substeps, Moment};

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

/// The words after `"μ_rot: "` in the plan file.
impl std::fmt::Display for RotationFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RotationFailure::Unreachable { theta } => write!(
                f,
                "support grasp unreachable at θ = {:.1}°",
                theta.to_degrees()
            ),
            RotationFailure::JointJump {
                theta,
                joint,
                delta,
            } => write!(
                f,
                "joint {} jumps {:.1}° at θ = {:.1}°",
                joint + 1,
                delta.to_degrees(),
                theta.to_degrees()
            ),
            RotationFailure::Collision { theta, a, b } => {
                write!(f, "{a} touches {b} at θ = {:.1}°", theta.to_degrees())
            }
        }
    }
}

/// The moment of μ_rot at angle `theta` with the supportive arm at `q`, holding G_s at the
/// width it closes on.
pub fn rotation_moment(
    ctx: &PlanningContext,
    pose: &PowerGraspPose,
    object: Isometry3<f64>,
    q: Joints,
) -> Moment {
    Moment::at_rest(ctx.starts(), object).holding(
        pose.supportive,
        q,
        ctx.support_grip(pose.supportive),
    )
}

/// How many times a step of Δφ may be halved where the continuing IK branch moves fast (near a
/// wrist singularity the joints turn quickly but continuously): down to Δφ / 16.
pub const MAX_STEP_HALVINGS: u32 = 4;

/// `RotPath`: μ_rot from one c_IK^s, or why there is none.
///
/// Built backwards from θ_goal in steps of Δφ; a step whose IK solution jumps by more than
/// `max_joint_step` is halved (up to [`MAX_STEP_HALVINGS`] times) so a fast but continuous
/// branch is followed with more points instead of being refused. Every state between points
/// is checked at [`FINE_RESOLUTION`]: the gripper holds a pinch a few millimetres above the
/// table. The states are collected along the path (from θ_goal down) and checked in one
/// pass ([`pregrasp_collision::CollisionWorld::first_contact_in`], in halves side by side):
/// the first one in contact, if it comes before the branch is lost, is the failure.
pub fn rotation_path(
    ctx: &PlanningContext,
    candidate: &RotationAxisCandidate,
    pose: &PowerGraspPose,
    c_ik_s: &Joints,
) -> Result<RotationPath, RotationFailure> {
    let params = &ctx.scene.planner;
    let n = (pose.theta_goal / params.step).round() as usize;
    let tracker = Tracker {
        ctx,
        candidate,
        pose,
    };
    // Points from θ_goal down to 0 (reversed at the end), and every state to check with its
    // angle, in the same order.
    let mut theta = vec![pose.theta_goal];
    let mut q = vec![*c_ik_s];
    let mut object = vec![pose.p_obj];
    let mut states = States {
        theta: vec![pose.theta_goal],
        world: vec![world_state(&rotation_moment(
            ctx, pose, pose.p_obj, *c_ik_s,
        ))],
    };
    let mut lost = None;
    for k in (0..n).rev() {
        let th = k as f64 * params.step;
        let (from_theta, from_q) = (*theta.last().expect("≥ 1"), *q.last().expect("≥ 1"));
        let stepped = tracker.step(from_theta, &from_q, th, 0, &mut states, &mut |t, qi, o| {
            theta.push(t);
            q.push(qi);
            object.push(o);
        });
        if let Err(e) = stepped {
            lost = Some(e);
            break;
        }
    }
    if let Some(k) = crate::halves::first_contact(&ctx.world, &states.world) {
        let c = ctx
            .world
            .check(&states.world[k])
            .expect_err("the first state in contact");
        return Err(RotationFailure::Collision {
            theta: states.theta[k],
            a: c.a,
            b: c.b,
        });
    }
    if let Some(e) = lost {
        return Err(e);
    }
    theta.reverse();
    q.reverse();
    object.reverse();
    Ok(RotationPath { theta, q, object })
}

/// The states of μ_rot to check, in path order, with their rotation angles.
struct States {
    theta: Vec<f64>,
    world: Vec<WorldState>,
}

struct Tracker<'a> {
    ctx: &'a PlanningContext<'a>,
    candidate: &'a RotationAxisCandidate,
    pose: &'a PowerGraspPose,
}

impl Tracker<'_> {
    /// From `(from_theta, from_q)` to angle `to`, emitting the points reached (excluding the
    /// start) and collecting the states between them, halving the step where the branch
    /// moves too fast.
    #[allow(clippy::too_many_arguments)]
    fn step(
        &self,
        from_theta: f64,
        from_q: &Joints,
        to: f64,
        depth: u32,
        states: &mut States,
        emit: &mut dyn FnMut(f64, Joints, Isometry3<f64>),
    ) -> Result<(), RotationFailure> {
        let ctx = self.ctx;
        let sup = self.pose.supportive;
        let arm = ctx.arm(sup);
        let max_step = ctx.scene.planner.max_joint_step;
        let obj = self.candidate.rotated_pose(&ctx.p_init, to);
        let target = arm.base.inverse()
            * obj
            * ctx.scene.grasps.support
            * arm.gripper.precision_point().inverse();
        let next = arm
            .kin
            .ik_nearest(&target, from_q)
            .ok_or(RotationFailure::Unreachable { theta: to })?;
        let jump = (0..6)
            .map(|j| (j, (next[j] - from_q[j]).abs()))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .expect("6 joints");
        if jump.1 > max_step {
            if depth < MAX_STEP_HALVINGS {
                let mid = 0.5 * (from_theta + to);
                let mut reached = (from_theta, *from_q);
                self.step(
                    from_theta,
                    from_q,
                    mid,
                    depth + 1,
                    states,
                    &mut |t, qi, o| {
                        reached = (t, qi);
                        emit(t, qi, o)
                    },
                )?;
                return self.step(reached.0, &reached.1, to, depth + 1, states, emit);
            }
            return Err(RotationFailure::JointJump {
                theta: to,
                joint: jump.0,
                delta: jump.1,
            });
        }
        // Interpolated states between the two points (joints linearly, angle linearly), from
        // the previous point's side to the new point.
        let weights = ctx.spaces[sup].weights;
        let steps = substeps(&next, from_q, &weights, FINE_RESOLUTION);
        for s in (0..steps).rev() {
            let f = s as f64 / steps as f64;
            let qi = lerp_joints(&next, from_q, f);
            let ti = to + f * (from_theta - to);
            let oi = self.candidate.rotated_pose(&ctx.p_init, ti);
            states.theta.push(ti);
            states
                .world
                .push(world_state(&rotation_moment(ctx, self.pose, oi, qi)));
        }
        emit(to, next, obj);
        Ok(())
    }
}
