//! Algorithm 3 of the paper: integrated paths for one candidate.
//!
//! For each c_IK^s ∈ C_IK^s: μ_rot (`RotPath`); with it, μ_sup1 from the supportive arm's start
//! to μ_rot's first configuration (`ReachPath1`); then for each c_IK^p of the master arm, μ_mas1
//! (`ReachPath2`) and μ_sup2 from μ_rot's last configuration to one of the supportive arm's own
//! power-grasp solutions (`ReachPath3`). The first combination whose four motions all exist is
//! the candidate's integrated path (an element of the paper's set Z).

use pregrasp_robot::{GripperState, Joints};

use crate::axes::RotationAxisCandidate;
use crate::context::PlanningContext;
use crate::poses::PowerGraspPose;
use crate::reach::{reach, ReachMotion, ReachQuery};
use crate::rotate::{rotation_path, RotationPath};
use crate::timeline::Moment;

/// At most this many alternatives of each IK set are tried (they are sorted by distance to the
/// arm's start, so the first ones are the natural choices).
pub const MAX_IK_TRIES: usize = 6;

/// The four motions of one plan.
#[derive(Clone, Debug)]
pub struct IntegratedPath {
    pub rot: RotationPath,
    pub sup1: ReachMotion,
    pub mas1: ReachMotion,
    pub sup2: ReachMotion,
}

/// A per-candidate seed derived from the scene's seed, so that every candidate's random
/// choices are independent of which thread evaluates it and of the other candidates.
pub fn motion_seed(seed: u64, candidate: usize, motion: u64) -> u64 {
    let mut x = seed ^ (candidate as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ motion.wrapping_mul(0xD1B5_4A32_D192_ED03);
    // splitmix64 finaliser
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// The failure that got furthest through Algorithm 3 (μ_rot < μ_sup1 < μ_mas1 < μ_sup2), so a
/// rejected candidate says where it came closest to a plan.
struct Furthest {
    stage: u8,
    reason: String,
}

impl Furthest {
    fn note(&mut self, stage: u8, reason: String) {
        if stage >= self.stage {
            self.stage = stage;
            self.reason = reason;
        }
    }
}

/// Algorithm 3 for one candidate: its integrated path, or why there is none (the failure
/// that got furthest, naming the motion).
pub fn integrated_path(
    ctx: &PlanningContext,
    candidate: &RotationAxisCandidate,
    pose: &PowerGraspPose,
) -> Result<IntegratedPath, String> {
    let sup = pose.supportive;
    let mas = pose.master;
    let starts = ctx.starts();
    let seed = ctx.scene.planner.seed;
    let mut failure = Furthest { stage: 0, reason: String::from("no support-grasp IK solution") };

    for c_ik_s in pose.support_ik.iter().take(MAX_IK_TRIES) {
        let rot = match rotation_path(ctx, candidate, pose, c_ik_s) {
            Ok(rot) => rot,
            Err(f) => {
                failure.note(1, f.describe());
                continue;
            }
        };
        let first = rot.q[0];
        let last = *rot.q.last().expect("μ_rot has points");

        // μ_sup1: supportive arm from start to μ_rot,first; master at start, part at P_init.
        let scene = Moment {
            q: starts,
            gripper: [GripperState::Open; 2],
            object: ctx.p_init,
            contact_allowed: [false; 2],
        };
        let query = ReachQuery {
            arm: sup,
            scene: &scene,
            from: starts[sup],
            goal: first,
            retreat: false,
            seed: motion_seed(seed, candidate.id, 1),
        };
        let sup1 = match reach(ctx, &query) {
            Ok(m) => m,
            Err(f) => {
                failure.note(2, format!("μ_sup1: {}", f.describe()));
                continue;
            }
        };

        for c_ik_p in pose.power_ik[mas].iter().take(MAX_IK_TRIES) {
            // μ_mas1: master from start to c_IK^p; supportive holds the part at P_obj.
            let mut scene = Moment {
                q: starts,
                gripper: [GripperState::Open; 2],
                object: pose.p_obj,
                contact_allowed: [false; 2],
            };
            scene.q[sup] = last;
            scene.gripper[sup] = GripperState::Closed;
            scene.contact_allowed[sup] = true;
            let query = ReachQuery {
                arm: mas,
                scene: &scene,
                from: starts[mas],
                goal: *c_ik_p,
                retreat: false,
                seed: motion_seed(seed, candidate.id, 2),
            };
            let mas1 = match reach(ctx, &query) {
                Ok(m) => m,
                Err(f) => {
                    failure.note(3, format!("μ_mas1: {}", f.describe()));
                    continue;
                }
            };
            match regrasp(ctx, candidate, pose, &last, c_ik_p) {
                Ok(sup2) => return Ok(IntegratedPath { rot, sup1, mas1, sup2 }),
                Err(f) => failure.note(4, f),
            }
        }
    }
    Err(failure.reason)
}

/// μ_sup2: the supportive arm releases G_s, backs out and power-grasps its own G_p while the
/// master holds the part at P_obj.
fn regrasp(
    ctx: &PlanningContext,
    candidate: &RotationAxisCandidate,
    pose: &PowerGraspPose,
    from: &Joints,
    master_q: &Joints,
) -> Result<ReachMotion, String> {
    let sup = pose.supportive;
    let mas = pose.master;
    let mut scene = Moment {
        q: ctx.starts(),
        gripper: [GripperState::Open; 2],
        object: pose.p_obj,
        contact_allowed: [false; 2],
    };
    scene.q[mas] = *master_q;
    scene.gripper[mas] = GripperState::Closed;
    scene.contact_allowed[mas] = true;
    let mut last_failure = format!("μ_sup2: no power-grasp IK solution for arm {}", ctx.names[sup]);
    for goal in pose.power_ik[sup].iter().take(MAX_IK_TRIES) {
        // Both grippers end closed on the part: the final state must be free.
        let mut end = scene.clone();
        end.q[sup] = *goal;
        end.gripper[sup] = GripperState::Closed;
        end.contact_allowed[sup] = true;
        if let Err(c) = ctx.check(&end) {
            last_failure = format!("μ_sup2: final grasp: {} touches {}", c.a, c.b);
            continue;
        }
        let query = ReachQuery {
            arm: sup,
            scene: &scene,
            from: *from,
            goal: *goal,
            retreat: true,
            seed: motion_seed(ctx.scene.planner.seed, candidate.id, 3),
        };
        match reach(ctx, &query) {
            Ok(m) => return Ok(m),
            Err(f) => last_failure = format!("μ_sup2: {}", f.describe()),
        }
    }
    Err(last_failure)
}
