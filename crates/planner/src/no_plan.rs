//! Why a scene has no plan: the stage at which every candidate failed, in the words of the plan
//! file's `reason` (and what the user can do about it).

use crate::context::PlanningContext;
use crate::outcome::CandidateOutcome;
use crate::poses::PoseRejection;

/// Names the stage at which every candidate failed: the words of the plan file's `reason`.
pub(crate) fn no_plan_reason(ctx: &PlanningContext, all: &[CandidateOutcome]) -> String {
    let outcomes: Vec<&CandidateOutcome> = all
        .iter()
        .filter(|o| !matches!(o, CandidateOutcome::Skipped))
        .collect();
    if all.is_empty() {
        return format!(
            "Algorithm 1: no rotation-axis candidate (no convex-hull edge within Δd_s of the \
             support and longer than Δl){}",
            off_the_support(ctx).unwrap_or_default()
        );
    }
    let rejections: Vec<&PoseRejection> = outcomes
        .iter()
        .filter_map(|o| match o {
            CandidateOutcome::NoPose(r) => Some(r),
            _ => None,
        })
        .collect();
    if rejections.len() == outcomes.len() {
        use PoseRejection::*;
        // Name the furthest stage any candidate reached: Δd_a, then the dummies, then IK.
        let stage = |r: &PoseRejection| match r {
            GraspNearAxis { .. } => 0,
            CannotClose { support: false, .. } => 1,
            DummiesNeverClear { .. } => 2,
            CannotClose { support: true, .. } | SupportClosingMeetsSupport { .. } => 3,
            PowerGraspUnreachable { .. } | SupportGraspUnreachable { .. } => 4,
        };
        let furthest = rejections.iter().map(|r| stage(r)).max().unwrap_or(0);
        let at: Vec<&PoseRejection> = rejections
            .iter()
            .copied()
            .filter(|r| stage(r) == furthest)
            .collect();
        let arms = |support: bool| -> String {
            let names: std::collections::BTreeSet<&str> = at
                .iter()
                .filter_map(|r| match r {
                    SupportGraspUnreachable { arm } if support => Some(ctx.names[*arm].as_str()),
                    PowerGraspUnreachable { arm } if !support => Some(ctx.names[*arm].as_str()),
                    _ => None,
                })
                .collect();
            names.into_iter().collect::<Vec<_>>().join(" / ")
        };
        return match furthest {
            0 => "no candidate: every power grasp within Δd_a of every axis".to_string(),
            1 | 3 => format!("grasp: {}", at[0].named(&ctx.names)),
            2 if at
                .iter()
                .all(|r| matches!(r, DummiesNeverClear { fingers: true, .. })) =>
            {
                "Algorithm 2: the power grasps' closing fingers reach the support at every angle \
                 up to θ_max"
                    .to_string()
            }
            2 => "Algorithm 2: the gripper dummies never clear the support within θ_max".to_string(),
            _ if at.iter().all(|r| matches!(r, SupportGraspUnreachable { .. })) => {
                format!("IK: support grasp unreachable for arm {} at every P_obj", arms(true))
            }
            _ if at.iter().all(|r| matches!(r, PowerGraspUnreachable { .. })) => {
                format!("IK: power grasp unreachable for arm {} at every P_obj", arms(false))
            }
            _ => format!(
                "IK: power grasp unreachable for arm {} and support grasp for arm {} at the P_obj of \
                 the other candidates",
                arms(false),
                arms(true)
            ),
        };
    }
    // The first candidate the physics refused, for its rotation's hold or for its carry.
    let refused = outcomes.iter().find(|o| {
        matches!(
            o,
            CandidateOutcome::Unheld { .. } | CandidateOutcome::Uncarried { .. }
        )
    });
    match refused {
        Some(CandidateOutcome::Unheld { reason, .. }) => {
            return format!(
                "no planned rotation holds the part (best candidate: {reason}); measure the mass \
                 and friction and set them in [physics], or set [physics] reject = false to keep \
                 such plans"
            );
        }
        Some(CandidateOutcome::Uncarried { reason, .. }) => {
            // Power grasps beyond the gripper's force are refused by `reject`; those short of
            // the safety factor, or that no force carries, by `reject_uncarried`.
            let key = if reason.beyond_gripper() {
                "reject"
            } else {
                "reject_uncarried"
            };
            return format!(
                "the power grasps cannot lift the part at any P_obj (best candidate: {reason}); \
                 place them on bars the fingers can squeeze, nearer the centre of mass, or set \
                 [physics] {key} = false to keep such plans"
            );
        }
        _ => {}
    }
    let first = outcomes.iter().find_map(|o| match o {
        CandidateOutcome::NoPath { failure, .. } => Some(failure),
        _ => None,
    });
    match first {
        Some(failure) => {
            format!("Algorithm 3: no integrated path for any candidate (best candidate: {failure})")
        }
        None => "Algorithm 3: no integrated path for any candidate (best candidate: -)".into(),
    }
}

/// Where the part, as the scene places it, does not rest on the support: how far its lowest
/// point lies above the support plane (or below it) when that is more than Δd_s
/// (`support_distance`), in words that say which keys to look at. `None` where it rests.
fn off_the_support(ctx: &PlanningContext) -> Option<String> {
    let pose = &ctx.scene.object.pose;
    let lowest = ctx
        .mesh
        .vertices
        .iter()
        .map(|v| (pose * v).z)
        .fold(f64::INFINITY, f64::min);
    let gap = lowest - ctx.scene.support_height;
    if !gap.is_finite() || gap.abs() <= ctx.scene.planner.support_distance {
        return None;
    }
    let (how, side) = if gap > 0.0 {
        ("above", "it does not rest on it")
    } else {
        ("below", "it lies in it")
    };
    Some(format!(
        ": the part's lowest point is {:.1} mm {how} the support (`support.height` {} m, \
         `object.pose` z {} m), {side}",
        gap.abs() * 1e3,
        ctx.scene.support_height,
        pose.translation.z
    ))
}
