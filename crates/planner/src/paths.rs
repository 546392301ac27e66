//! Algorithm 3 of the paper: integrated paths for one candidate.
//!
//! For each c_IK^s ∈ C_IK^s: μ_rot (`RotPath`); with it, μ_sup1 from the supportive arm's start
//! to μ_rot's first configuration (`ReachPath1`); then for each c_IK^p of the master arm, μ_mas1
//! (`ReachPath2`) and μ_sup2 from μ_rot's last configuration to one of the supportive arm's own
//! power-grasp solutions (`ReachPath3`). The first combination whose four motions all exist is
//! the candidate's integrated path (an element of the paper's set Z).

use std::sync::atomic::{AtomicBool, Ordering};

use crate::axes::RotationAxisCandidate;
use crate::clock::Stage;
use crate::context::{PlanningContext, FIXED_START_TOLERANCE};
use crate::pass_memo::PassMemo;
use crate::poses::PowerGraspPose;
use crate::reach::{reach_lines, reach_transit, ReachFailure, ReachMotion, ReachQuery};
use crate::rejection::{MotionFailure, PathFailure};
use crate::rotate::RotationPath;
use pregrasp_io::plan_file::SegmentName;
use pregrasp_model::timeline::Moment;
use pregrasp_motion::CartesianError;

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
    let mut x = seed
        ^ (candidate as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ motion.wrapping_mul(0xD1B5_4A32_D192_ED03);
    // splitmix64 finaliser
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// The failure that got furthest through Algorithm 3 (μ_rot < μ_sup1 < μ_mas1 < μ_sup2), so a
/// rejected candidate says where it came closest to a plan.
struct Furthest(PathFailure);

impl Furthest {
    /// Motion `stage` failed: kept when it got as far as the failure kept so far.
    fn note(&mut self, stage: SegmentName, cause: MotionFailure) {
        let failure = PathFailure::Motion { stage, cause };
        if failure.progress() >= self.0.progress() {
            self.0 = failure;
        }
    }
}

/// Why a candidate has no integrated path.
#[derive(Clone, Debug, PartialEq)]
pub enum NoPath<E> {
    /// No combination of the four motions exists: the failure that got furthest, naming the
    /// motion.
    Motions(PathFailure),
    /// μ_rot exists, but the caller's test of it refused it (the pinch cannot hold the part).
    Refused(E),
}

/// Whether both grippers may close on the part at the end of μ_sup2: the supportive arm `sup`
/// at `goal` in `sup2_scene` (where the master holds the part) is free.
pub(crate) fn final_grasp_free(
    ctx: &PlanningContext,
    sup2_scene: &Moment,
    sup: usize,
    goal: &pregrasp_robot::Joints,
) -> Result<(), MotionFailure> {
    let end = sup2_scene.clone().holding(sup, *goal, ctx.power_grip(sup));
    ctx.check(&end).map_err(MotionFailure::FinalGrasp)
}

/// Algorithm 3 for one candidate: its integrated path with what `accept` said of its μ_rot, or
/// why there is none. μ_rot and μ_sup1's straight lines come from `memo`, which the candidates
/// and the passes of one plan share.
///
/// The straight approach and retreat lines of a combination are validated first: they are cheap
/// and decide most failures. Once they all hold, its μ_rot is put to `accept` (the grip check,
/// which costs more than the lines and less than the transits: a rotation the pinch cannot
/// hold needs no transits), and a refusal ends the candidate. Then the transits (RRT-Connect,
/// the expensive part), each planned once per choice it depends on and reused.
///
/// The grip check and the transits a combination still needs do not depend on each other
/// (each transit has its own seed): where the pool has threads to spare they are computed side
/// by side first (`ahead`), and their verdicts are then read in the order above, so the
/// result is the same on any number of threads; one thread computes each only when it is read.
pub fn integrated_path<T: Send, E: Send>(
    ctx: &PlanningContext,
    memo: &PassMemo,
    candidate: &RotationAxisCandidate,
    pose: &PowerGraspPose,
    accept: impl Fn(&RotationPath) -> Result<T, E> + Sync,
) -> Result<(IntegratedPath, T), NoPath<E>> {
    let sup = pose.supportive;
    let mas = pose.master;
    let starts = ctx.starts();
    let seed = ctx.scene.planner.seed;
    let mut failure = Furthest(PathFailure::NoSupportIk);

    'support: for c_ik_s in pose.support_ik.free(ctx).take(MAX_IK_TRIES) {
        let mut rot = match ctx
            .clock
            .time(Stage::Rot, || memo.rotation(ctx, candidate, pose, c_ik_s))
        {
            Ok(rot) => rot,
            Err(f) => {
                failure.note(SegmentName::Rot, MotionFailure::Rotation(f));
                continue;
            }
        };
        if let Some((arm, q)) = ctx.fixed_rot_start {
            let off = rot.q[0]
                .iter()
                .zip(&q)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            if arm != sup || off > FIXED_START_TOLERANCE {
                failure.note(SegmentName::Rot, MotionFailure::NotAtSup1End);
                continue;
            }
            // The same configuration up to IK round-off: start exactly where the arm stands.
            rot.q[0] = q;
        }
        // What `accept` says of this μ_rot, asked once its lines all hold.
        let mut accepted: Option<T> = None;
        let last = *rot.q.last().expect("μ_rot has points");

        // μ_sup1: supportive arm from start to μ_rot,first; master at start, part at P_init.
        let sup1_scene = Moment::at_rest(starts, ctx.p_init);
        let sup1_query = ReachQuery {
            arm: sup,
            scene: &sup1_scene,
            from: starts[sup],
            goal: rot.q[0],
            retreat: false,
            seed: motion_seed(seed, candidate.id, 1),
        };
        let sup1_lines = match ctx
            .clock
            .time(Stage::Lines, || memo.lines(ctx, &sup1_query))
        {
            Ok(lines) => lines,
            Err(f) => {
                failure.note(SegmentName::Sup1, MotionFailure::Reach(f));
                continue;
            }
        };
        let mut sup1: Option<ReachMotion> = None;

        // μ_mas1 scene: the supportive arm holds the part at P_obj.
        let mas1_scene =
            Moment::at_rest(starts, pose.p_obj).holding(sup, last, ctx.support_grip(sup));

        'master: for c_ik_p in pose.power_ik[mas].free(ctx).take(MAX_IK_TRIES) {
            let mas1_query = ReachQuery {
                arm: mas,
                scene: &mas1_scene,
                from: starts[mas],
                goal: *c_ik_p,
                retreat: false,
                seed: motion_seed(seed, candidate.id, 2),
            };
            let mas1_lines = match ctx
                .clock
                .time(Stage::Lines, || reach_lines(ctx, &mas1_query))
            {
                Ok(lines) => lines,
                Err(f) => {
                    failure.note(SegmentName::Mas1, MotionFailure::Reach(f));
                    continue;
                }
            };
            let mut mas1: Option<ReachMotion> = None;

            // μ_sup2 scene: the master holds the part at P_obj.
            let sup2_scene =
                Moment::at_rest(starts, pose.p_obj).holding(mas, *c_ik_p, ctx.power_grip(mas));

            for goal in pose.power_ik[sup].free(ctx).take(MAX_IK_TRIES) {
                // Both grippers end closed on the part: the final state must be free.
                if let Err(f) = final_grasp_free(ctx, &sup2_scene, sup, goal) {
                    failure.note(SegmentName::Sup2, f);
                    continue;
                }
                let sup2_query = ReachQuery {
                    arm: sup,
                    scene: &sup2_scene,
                    from: last,
                    goal: *goal,
                    retreat: true,
                    seed: motion_seed(seed, candidate.id, 3),
                };
                let sup2_lines = match ctx
                    .clock
                    .time(Stage::Lines, || reach_lines(ctx, &sup2_query))
                {
                    Ok(lines) => lines,
                    Err(f) => {
                        // A retreat from μ_rot's end that the arm cannot follow (no IK, a joint
                        // limit or a branch jump along it) fails whatever the goal and the
                        // master's configuration: the next G_s configuration.
                        let stuck = matches!(&f, ReachFailure::Retreat(e, _) if is_kinematic(e));
                        failure.note(SegmentName::Sup2, MotionFailure::Reach(f));
                        if stuck {
                            continue 'support;
                        }
                        continue;
                    }
                };
                // Every line holds: now the grip check, then the transits, each planned once.
                let refused = AtomicBool::new(false);
                let stopped = || refused.load(Ordering::Relaxed);
                let transit = |query: &ReachQuery, lines| {
                    ctx.clock.time(Stage::Transit, || {
                        reach_transit(ctx, query, lines, &stopped)
                    })
                };
                let (asked, need_sup1, need_mas1) =
                    (accepted.is_some(), sup1.is_none(), mas1.is_none());
                // A transit not yet begun when the grip check refuses the rotation is not
                // begun, and one under way stops: the candidate ends there and reads none of
                // them.
                let (mut early_accept, mut early_sup1, mut early_mas1, mut early_sup2) = ahead(
                    || {
                        (!asked).then(|| {
                            let verdict = accept(&rot);
                            refused.store(verdict.is_err(), Ordering::Relaxed);
                            verdict
                        })
                    },
                    || (need_sup1 && !stopped()).then(|| transit(&sup1_query, &sup1_lines)),
                    || (need_mas1 && !stopped()).then(|| transit(&mas1_query, &mas1_lines)),
                    || (!stopped()).then(|| transit(&sup2_query, &sup2_lines)),
                );
                if accepted.is_none() {
                    let verdict = early_accept.take().unwrap_or_else(|| accept(&rot));
                    accepted = Some(verdict.map_err(NoPath::Refused)?);
                }
                if sup1.is_none() {
                    match early_sup1
                        .take()
                        .unwrap_or_else(|| transit(&sup1_query, &sup1_lines))
                    {
                        Ok(m) => sup1 = Some(m),
                        Err(f) => {
                            failure.note(SegmentName::Sup1, MotionFailure::Reach(f));
                            continue 'support;
                        }
                    }
                }
                if mas1.is_none() {
                    match early_mas1
                        .take()
                        .unwrap_or_else(|| transit(&mas1_query, &mas1_lines))
                    {
                        Ok(m) => mas1 = Some(m),
                        Err(f) => {
                            failure.note(SegmentName::Mas1, MotionFailure::Reach(f));
                            continue 'master;
                        }
                    }
                }
                match early_sup2
                    .take()
                    .unwrap_or_else(|| transit(&sup2_query, &sup2_lines))
                {
                    Ok(sup2) => {
                        let path = IntegratedPath {
                            rot,
                            sup1: sup1.expect("planned above"),
                            mas1: mas1.expect("planned above"),
                            sup2,
                        };
                        return Ok((path, accepted.expect("asked above")));
                    }
                    Err(f) => failure.note(SegmentName::Sup2, MotionFailure::Reach(f)),
                }
            }
        }
    }
    Err(NoPath::Motions(failure.0))
}

/// Whether a straight line failed for the arm's kinematics alone (no IK solution, a joint limit,
/// a branch jump), not for what it met: it fails so in any scene.
fn is_kinematic(e: &CartesianError) -> bool {
    matches!(
        e,
        CartesianError::Unreachable { .. }
            | CartesianError::JointLimit { .. }
            | CartesianError::BranchJump { .. }
    )
}

/// The four computations `a`, `b`, `c`, `d` side by side, when the pool has more than one
/// thread; with one, none (`[None; 4]`): each is then computed when its result is read, and
/// none is computed that would not be.
fn ahead<A: Send, B: Send, C: Send, D: Send>(
    a: impl FnOnce() -> Option<A> + Send,
    b: impl FnOnce() -> Option<B> + Send,
    c: impl FnOnce() -> Option<C> + Send,
    d: impl FnOnce() -> Option<D> + Send,
) -> (Option<A>, Option<B>, Option<C>, Option<D>) {
    if rayon::current_num_threads() < 2 {
        return (None, None, None, None);
    }
    let ((a, b), (c, d)) = rayon::join(|| rayon::join(a, b), || rayon::join(c, d));
    (a, b, c, d)
}
