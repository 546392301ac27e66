//! What the passes of one plan share beyond the part and the arm models: the motions that do
//! not depend on the power grasps, which are all that a plan's passes change (the seatings,
//! [`crate::seat`]; the slides, [`crate::slide`]).
//!
//! - **μ_sup1's straight lines.** μ_sup1 reaches G_s at P_init from the start with both
//!   grippers open and nothing held: its lines depend on the arm, both arms' joints, the part's
//!   pose and the goal. Every candidate asks them for the same IK solutions at G_s, and every
//!   pass asks again (the chair side: eight times for two goals).
//! - **μ_rot.** A rotation depends on its candidate's axis, θ_goal (so P_obj), the supportive
//!   arm and its c_IK^s; a candidate whose pose a later pass finds again (its dummies clear the
//!   support at the same angle) is rotated again otherwise.
//!
//! Both are remembered by the bits of what they depend on; the answers are the functions'
//! own, so a plan is the same with or without them.

use std::collections::HashMap;
use std::sync::Mutex;

use pregrasp_robot::{GripperState, Joints};

use crate::axes::RotationAxisCandidate;
use crate::context::PlanningContext;
use crate::poses::PowerGraspPose;
use crate::reach::{reach_lines, ReachFailure, ReachLines, ReachQuery};
use crate::rotate::{rotation_path, RotationFailure, RotationPath};

/// The motions the passes of one plan share (see the module documentation).
#[derive(Debug, Default)]
pub struct PassMemo {
    at_rest: Mutex<HashMap<RestKey, Result<ReachLines, ReachFailure>>>,
    rotations: Mutex<HashMap<RotationKey, Result<RotationPath, RotationFailure>>>,
}

/// What a line from rest depends on, by bits: the arm, both arms' joints (the moving one's at
/// `from`), the part's pose (translation, quaternion) and the goal.
type RestKey = (usize, [[u64; 6]; 2], [u64; 7], [u64; 6]);

/// What μ_rot depends on, by bits: the candidate, the supportive arm, θ_goal, P_obj and c_IK^s.
type RotationKey = (usize, usize, u64, [u64; 7], [u64; 6]);

impl PassMemo {
    /// [`reach_lines`] of `query`, computed once where its world is at rest — both grippers
    /// open, nothing held, no contact allowed, no retreat: μ_sup1 — and as asked otherwise.
    pub fn lines(
        &self,
        ctx: &PlanningContext,
        query: &ReachQuery,
    ) -> Result<ReachLines, ReachFailure> {
        let Some(key) = rest_key(query) else {
            return reach_lines(ctx, query);
        };
        remembered(&self.at_rest, key, || reach_lines(ctx, query))
    }

    /// [`rotation_path`] of `candidate` at `pose` from `c_ik_s`, computed once.
    pub fn rotation(
        &self,
        ctx: &PlanningContext,
        candidate: &RotationAxisCandidate,
        pose: &PowerGraspPose,
        c_ik_s: &Joints,
    ) -> Result<RotationPath, RotationFailure> {
        let key = (
            candidate.id,
            pose.supportive,
            pose.theta_goal.to_bits(),
            pose_bits(&pose.p_obj),
            c_ik_s.map(f64::to_bits),
        );
        remembered(&self.rotations, key, || {
            rotation_path(ctx, candidate, pose, c_ik_s)
        })
    }
}

/// The answer kept in `memo` under `key`, else `compute`d (outside the lock, so that
/// computations run side by side) and kept.
fn remembered<K: std::hash::Hash + Eq, V: Clone>(
    memo: &Mutex<HashMap<K, V>>,
    key: K,
    compute: impl FnOnce() -> V,
) -> V {
    let known = memo.lock().expect("not poisoned").get(&key).cloned();
    known.unwrap_or_else(|| {
        let answer = compute();
        let mut kept = memo.lock().expect("not poisoned");
        kept.entry(key).or_insert(answer).clone()
    })
}

/// A pose's translation and quaternion, by bits.
fn pose_bits(pose: &nalgebra::Isometry3<f64>) -> [u64; 7] {
    let (t, r) = (pose.translation.vector, pose.rotation.coords);
    [t.x, t.y, t.z, r.x, r.y, r.z, r.w].map(f64::to_bits)
}

/// `query`'s [`RestKey`] where its world is at rest, else `None`.
fn rest_key(query: &ReachQuery) -> Option<RestKey> {
    let m = query.scene;
    let open = m.gripper.iter().all(|g| matches!(g, GripperState::Open));
    if query.retreat || !open || m.contact_allowed != [false; 2] {
        return None;
    }
    let bits = |q: &Joints| q.map(f64::to_bits);
    let mut q = m.q;
    q[query.arm] = query.from;
    Some((
        query.arm,
        q.map(|q| bits(&q)),
        pose_bits(&m.object),
        bits(&query.goal),
    ))
}
