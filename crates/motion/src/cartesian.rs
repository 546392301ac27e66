//! Straight-line Cartesian moves of the tool (e.g. stand-off → grasp along the
//! approach axis) by inverse kinematics on interpolated poses.

use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use thiserror::Error;

use crate::space::State;
use crate::validity::{MotionValidator, StateValidator};

/// Step sizes and the branch-continuity bound of [`straight_line`].
#[derive(Clone, Debug, PartialEq)]
pub struct CartesianSettings {
    /// Largest tool translation between interpolated poses (metres).
    pub max_translation_step: f64,
    /// Largest tool rotation between interpolated poses (radians).
    pub max_rotation_step: f64,
    /// Largest `max_i |Δq_i|` allowed between consecutive IK solutions (radians);
    /// more means the IK jumped to another branch.
    pub max_joint_jump: f64,
}

impl Default for CartesianSettings {
    /// 5 mm, 2°, 0.3 rad.
    fn default() -> Self {
        Self {
            max_translation_step: 0.005,
            max_rotation_step: 2f64.to_radians(),
            max_joint_jump: 0.3,
        }
    }
}

/// Why a straight line cannot be followed. `fraction` is the interpolation parameter
/// `s ∈ [0, 1]` of the failing pose (0 = start pose, 1 = goal pose).
#[derive(Clone, Debug, PartialEq, Error)]
pub enum CartesianError {
    /// The IK found no solution for the pose at `fraction`.
    #[error("no IK solution at fraction {fraction:.3} of the line")]
    Unreachable { fraction: f64 },
    /// The IK solution at `fraction` is outside the joint limits.
    #[error("IK solution outside the joint limits at fraction {fraction:.3}")]
    JointLimit { fraction: f64 },
    /// The IK solution at `fraction` is more than `max_joint_jump` from the previous one.
    #[error("IK branch jump of {jump:.3} rad at fraction {fraction:.3}")]
    BranchJump { fraction: f64, jump: f64 },
    /// The state (or the edge leading to it) at `fraction` is invalid.
    #[error("collision at fraction {fraction:.3} of the line")]
    Collision { fraction: f64 },
    /// A setting is not finite and positive.
    #[error("invalid Cartesian settings: {0}")]
    InvalidSettings(&'static str),
}

/// The pose at fraction `s` of the geodesic from `a` to `b`: translation linear,
/// rotation `R_a · exp(s · log(R_a⁻¹ R_b))` (slerp along the shortest arc, total for
/// any pair of rotations including half turns).
pub fn interpolate_pose(a: &Isometry3<f64>, b: &Isometry3<f64>, s: f64) -> Isometry3<f64> {
    let t = a.translation.vector.lerp(&b.translation.vector, s);
    let delta = (a.rotation.inverse() * b.rotation).scaled_axis();
    let r = a.rotation * UnitQuaternion::from_scaled_axis(delta * s);
    Isometry3::from_parts(Translation3::from(t), r)
}

/// Follows the straight tool line from `fk(start_q)` to `goal_pose`.
///
/// The line is cut into `n` equal steps with translation ≤ `max_translation_step` and
/// rotation ≤ `max_rotation_step` each ([`interpolate_pose`]). At each pose the IK is
/// seeded with the previous solution (`ik_nearest(pose, seed)` must return the
/// solution nearest to `seed`, or `None`); the solution must stay within the joint
/// limits, within `max_joint_jump` of the previous one in every joint (branch
/// continuity), and the joint-space edge from the previous solution must pass
/// `motion`. The IK's accuracy is the caller's contract: it is not re-checked here.
///
/// Returns the `n + 1` joint states, `start_q` first.
pub fn straight_line<V: StateValidator<6> + ?Sized>(
    fk: impl Fn(&State<6>) -> Isometry3<f64>,
    ik_nearest: impl Fn(&Isometry3<f64>, &State<6>) -> Option<State<6>>,
    motion: &MotionValidator<6, V>,
    start_q: &State<6>,
    goal_pose: &Isometry3<f64>,
    settings: &CartesianSettings,
) -> Result<Vec<State<6>>, CartesianError> {
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(settings.max_translation_step) {
        return Err(CartesianError::InvalidSettings("max_translation_step"));
    }
    if !positive(settings.max_rotation_step) {
        return Err(CartesianError::InvalidSettings("max_rotation_step"));
    }
    if !positive(settings.max_joint_jump) {
        return Err(CartesianError::InvalidSettings("max_joint_jump"));
    }
    if !motion.check_state(start_q) {
        return Err(CartesianError::Collision { fraction: 0.0 });
    }
    let start_pose = fk(start_q);
    let dist = (goal_pose.translation.vector - start_pose.translation.vector).norm();
    let angle = start_pose.rotation.angle_to(&goal_pose.rotation);
    let steps = (dist / settings.max_translation_step)
        .ceil()
        .max((angle / settings.max_rotation_step).ceil());
    let n = (steps as usize).max(1);

    let mut out = Vec::with_capacity(n + 1);
    out.push(*start_q);
    let mut prev = *start_q;
    for k in 1..=n {
        let s = k as f64 / n as f64;
        let pose = if k == n {
            *goal_pose
        } else {
            interpolate_pose(&start_pose, goal_pose, s)
        };
        let q = ik_nearest(&pose, &prev).ok_or(CartesianError::Unreachable { fraction: s })?;
        if !motion.space.contains(&q) {
            return Err(CartesianError::JointLimit { fraction: s });
        }
        let jump = (0..6).map(|i| (q[i] - prev[i]).abs()).fold(0.0, f64::max);
        // `q` is within bounds, so finite: `jump` is not NaN.
        if jump > settings.max_joint_jump {
            return Err(CartesianError::BranchJump { fraction: s, jump });
        }
        if !motion.check_edge(&prev, &q) {
            return Err(CartesianError::Collision { fraction: s });
        }
        out.push(q);
        prev = q;
    }
    Ok(out)
}
