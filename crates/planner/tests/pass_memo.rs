//! The motions a plan's passes share are remembered ([`PassMemo`]): what the memo answers is
//! what [`reach_lines`] and [`rotation_path`] compute, for the moment and the rotation asked —
//! the part's pose, the other arm's joints, the candidate and c_IK^s are part of what it
//! remembers by.

mod common;

use nalgebra::Isometry3;
use pregrasp_model::timeline::Moment;
use pregrasp_planner::axes::rotation_axis_candidates;
use pregrasp_planner::context::PlanningContext;
use pregrasp_planner::pass_memo::PassMemo;
use pregrasp_planner::poses::object_pose_for_power_grasp;
use pregrasp_planner::reach::{reach_lines, ReachFailure, ReachLines, ReachQuery};
use pregrasp_planner::rotate::{rotation_path, RotationFailure, RotationPath};

use common::scenes::example_files;

/// The retreat and the approach, joint by joint.
type Lines = (Vec<[f64; 6]>, Vec<[f64; 6]>);

/// The lines as comparable joint lists, or the failure.
fn joints(r: &Result<ReachLines, ReachFailure>) -> Result<Lines, String> {
    r.as_ref()
        .map(|l| (l.retreat.clone(), l.approach.clone()))
        .map_err(|f| f.to_string())
}

/// Arm `arm`'s reach from `from` to `goal` in `scene`, no retreat.
fn query(arm: usize, scene: &Moment, from: [f64; 6], goal: [f64; 6]) -> ReachQuery<'_> {
    ReachQuery {
        arm,
        scene,
        from,
        goal,
        retreat: false,
        seed: 7,
    }
}

/// Every free configuration of each arm at G_s at P_init (the first three), asked of the memo
/// twice and computed directly: the same lines; then with the part raised into the approach,
/// with the other arm moved and with it holding the part: the memo answers those moments, not
/// the first.
#[test]
fn the_memo_answers_what_reach_lines_computes_for_each_moment() {
    for name in ["chair_side", "shelf_side", "stool_side"] {
        let (scene, mesh) = example_files(name);
        let ctx = PlanningContext::new(&scene, &mesh).unwrap();
        let memo = PassMemo::default();
        let starts = ctx.starts();
        let (mut asked, mut blocked) = (0, 0);
        for arm in 0..2 {
            let point = ctx.arm(arm).gripper.precision_point();
            let flange = ctx.p_init * scene.grasps.support * point.inverse();
            let ik = ctx.free_ik(arm, &flange, &ctx.p_init, ctx.support_grip(arm));
            for goal in ik.free(&ctx).take(3) {
                let query = |scene| query(arm, scene, starts[arm], *goal);
                let rest = Moment::at_rest(starts, ctx.p_init);
                let direct = joints(&reach_lines(&ctx, &query(&rest)));
                assert_eq!(joints(&memo.lines(&ctx, &query(&rest))), direct, "{name}");
                assert_eq!(joints(&memo.lines(&ctx, &query(&rest))), direct, "{name}");

                // The part raised 8 cm, into the approach's clear stretch.
                let raised =
                    Moment::at_rest(starts, Isometry3::translation(0.0, 0.0, 0.08) * ctx.p_init);
                let moved = joints(&memo.lines(&ctx, &query(&raised)));
                assert_eq!(moved, joints(&reach_lines(&ctx, &query(&raised))), "{name}");
                blocked += usize::from(direct.is_ok() && moved.is_err());

                // The other arm turned half a radian about its base.
                let mut other = starts;
                other[1 - arm][0] += 0.5;
                let aside = Moment::at_rest(other, ctx.p_init);
                assert_eq!(
                    joints(&memo.lines(&ctx, &query(&aside))),
                    joints(&reach_lines(&ctx, &query(&aside))),
                    "{name}"
                );

                // Held by the other arm: not a moment at rest, computed as asked.
                let held = rest
                    .clone()
                    .holding(1 - arm, starts[1 - arm], ctx.power_grip(1 - arm));
                assert_eq!(
                    joints(&memo.lines(&ctx, &query(&held))),
                    joints(&reach_lines(&ctx, &query(&held))),
                    "{name}"
                );
                asked += 1;
            }
        }
        assert!(asked >= 2, "{name}: {asked} configurations at G_s");
        // Remembered by the part's pose: a line that holds at P_init fails with the part raised.
        assert!(blocked >= 1, "{name}: no line the raised part blocks");
    }
}

/// A rotation as comparable points, or the failure.
fn points(r: &Result<RotationPath, RotationFailure>) -> Result<(Vec<f64>, Vec<[f64; 6]>), String> {
    r.as_ref()
        .map(|p| (p.theta.clone(), p.q.clone()))
        .map_err(|f| f.to_string())
}

/// Every candidate with a pose, from each of its first c_IK^s, asked of one memo twice and
/// computed directly: the same μ_rot; each c_IK^s and each candidate gets its own (the memo
/// never hands one rotation to another's key).
#[test]
fn the_memo_answers_what_rotation_path_computes_for_each_rotation() {
    for name in ["chair_side", "shelf_side", "stool_side"] {
        let (scene, mesh) = example_files(name);
        let ctx = PlanningContext::new(&scene, &mesh).unwrap();
        let axes = rotation_axis_candidates(
            &mesh,
            &scene.object.pose,
            scene.support_height,
            &scene.planner,
        );
        let memo = PassMemo::default();
        let mut seen = Vec::new();
        for candidate in &axes.candidates {
            let Ok(pose) = object_pose_for_power_grasp(&ctx, candidate) else {
                continue;
            };
            for c_ik_s in pose.support_ik.free(&ctx).take(2) {
                let direct = points(&rotation_path(&ctx, candidate, &pose, c_ik_s));
                for _ in 0..2 {
                    let remembered = points(&memo.rotation(&ctx, candidate, &pose, c_ik_s));
                    assert_eq!(remembered, direct, "{name} candidate {}", candidate.id);
                }
                seen.push(direct);
            }
        }
        // Distinct rotations were asked: a memo keyed too coarsely would have repeated one.
        assert!(seen.len() >= 2, "{name}: {} rotations", seen.len());
        assert!(
            seen.iter().any(|r| r != &seen[0]),
            "{name}: every rotation alike"
        );
    }
}
