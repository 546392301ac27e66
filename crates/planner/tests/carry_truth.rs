//! The carry check held to the whole-plan replay (`tools/gripper_truth/plan_replay.py`, its
//! table `crates/physics/data/replay_truth/plan_replay_2f85.csv`): every row is a plan of an
//! example, replayed in MuJoCo with the power grasps closing at `power_force` and both grippers
//! lifting 50 mm. It *lifts* when the part rises ≥ 45 mm and tilts < 5°.
//!
//! The check, asked of the same grasps at the same P_obj, either finds the plan uncarried (no grip
//! force within the gripper's carries the part) or sets a force (`CarryForces::set`). Both
//! ways:
//! - a plan it refuses does not lift in the replay, at any force the table has;
//! - a plan it keeps lifts in the replay at every force of the table at or above the one it
//!   sets (the gripper's largest, 235 N: `pregrasp_planner::carry` says why).
//!
//! Where the replay lifts at a force below the one the check sets, the check is cautious
//! there: such rows are listed, not failed. The rows where the two disagree are named below
//! and in docs/physics.md ("Carrying the part"). The rows: the examples' table (8: the four
//! plans at their pinch's force and at 235 N) and the sweeps of 30 generated parts
//! (`plan_replay_generated_2f85.csv`, seeds 1–5, 31 plans at 235 N), 30 more
//! (`plan_replay_generated_seeds_6_10_2f85.csv`, seeds 6–10, 30 plans) and 60 more
//! (`plan_replay_generated_seeds_11_15_2f85.csv`, `…_16_20_…`, 57 plans), each part made again
//! here from its family and seed.

mod common;

use common::replay_table::{planned_scene, rows, scene_of};
use common::scenes::example_files;
use pregrasp_io::scene::Scene;
use pregrasp_planner::axes::rotation_axis_candidates;
use pregrasp_planner::context::PlanningContext;
use pregrasp_planner::hold::HoldCheck;

/// The replay's verdict thresholds (issue 48).
const MIN_RISE: f64 = 0.045;
const MAX_TILT_DEG: f64 = 5.0;

#[test]
fn the_carry_check_agrees_with_the_replay_both_ways() {
    let mut all = rows("plan_replay_2f85.csv");
    assert!(all.len() >= 8, "{} rows", all.len());
    // The sweep's rows of generated parts (its example rows repeat the table's at 235 N).
    for table in [
        "plan_replay_generated_2f85.csv",
        "plan_replay_generated_seeds_6_10_2f85.csv",
        "plan_replay_generated_seeds_11_15_2f85.csv",
        "plan_replay_generated_seeds_16_20_2f85.csv",
    ] {
        all.extend(
            rows(table)
                .into_iter()
                .filter(|r| r["family"] != "example" && !r["candidate"].is_empty()),
        );
    }
    let (mut refused, mut kept, mut cautious) = (0, 0, Vec::new());
    let mut departures = Vec::new();
    for row in &all {
        let name = row.get("part").unwrap_or(&row["example"]);
        let (scene, mesh) = scene_of(row);
        // The power grasps as the planner plans with them (seated on the palm).
        let scene = planned_scene(&scene, &mesh);
        let ctx = PlanningContext::new(&scene, &mesh).unwrap();
        let axes = rotation_axis_candidates(
            &mesh,
            &scene.object.pose,
            scene.support_height,
            &scene.planner,
        );
        let id: usize = row["candidate"].parse().unwrap();
        let candidate = axes.candidates.iter().find(|c| c.id == id).unwrap();
        let theta = row["rot.turn_plan_deg"]
            .parse::<f64>()
            .unwrap()
            .to_radians();
        let p_obj = candidate.rotated_pose(&ctx.p_init, theta);
        let carry = HoldCheck::new(&scene, &mesh, None).carry_check(&ctx);
        let force: f64 = row["power_force"].parse().unwrap();
        let rise: f64 = row["lift.rise"].parse().unwrap();
        let tilt: f64 = row["lift.tilt_deg"].parse().unwrap();
        let lifts = rise >= MIN_RISE && tilt < MAX_TILT_DEG;
        let what = format!(
            "{name} plan {} at {force:.0} N (replay: rose {:.1} mm, tilted {tilt:.1}°)",
            row["plan"],
            rise * 1e3
        );
        match carry.check(&p_obj).expect("the examples have a mass") {
            Err(why) => {
                if lifts {
                    departures.push(format!("{name} plan {}: not carried, lifts", row["plan"]));
                    println!("{what}: {why}");
                } else {
                    println!("{what}: {why}");
                    refused += 1;
                }
            }
            Ok(forces) => {
                let set = forces.set[0].max(forces.set[1]);
                println!("{what}: N_min {:.1} N, sets {set:.0} N", forces.minimum);
                if force >= set {
                    if lifts {
                        kept += 1;
                    } else {
                        departures.push(format!("{name} plan {}: carried, fails", row["plan"]));
                    }
                } else if lifts {
                    cautious.push(format!("{what}: the check sets {set:.0} N"));
                }
            }
        }
    }
    println!("agree: {refused} not carried, {kept} carried; cautious: {cautious:#?}");
    println!("departures: {departures:#?}");
    // Both ways: rows of each verdict agree, and the departures are the ones named in
    // docs/physics.md — a change of the model that adds or removes one shows here.
    // Replayed with the planner that holds caging grasps at the fingertips (`seat`): 126 rows,
    // 1 + 110 agree, 4 lift below the force the plan sets (the examples at their pinch's
    // force), 11 depart, all carried yet failing: the panels that tilt in both hands (panel_10,
    // panel_13, panel_18, panel_19), h_frame_4 and stool_15 (the master's closing ends caged),
    // and five whose master, held at the fingertips, lets the part turn 10–12° when the
    // supportive gripper opens, so that `sup2` closes on nothing (frame_6, h_frame_1,
    // h_frame_12, h_frame_16, u_frame_8): the hand-over, which the carry check does not see.
    assert_eq!((refused, kept, cautious.len()), (1, 110, 4));
    assert_eq!(
        departures,
        [
            "h_frame_1 plan 0: carried, fails",
            "h_frame_4 plan 0: carried, fails",
            "frame_6 plan 0: carried, fails",
            "panel_10 plan 0: carried, fails",
            "u_frame_8 plan 0: carried, fails",
            "h_frame_12 plan 0: carried, fails",
            "panel_13 plan 0: carried, fails",
            "stool_15 plan 0: carried, fails",
            "h_frame_16 plan 0: carried, fails",
            "panel_18 plan 0: carried, fails",
            "panel_19 plan 0: carried, fails",
        ]
    );
}

/// h_frame_19's power grasps both cage its 21 mm bars (22 mm stock), at the scene's depth and at
/// the fingertips alike, and cannot slide (the replay: rise 27.8 of 50 mm, tilted 8.9°): its
/// plan says so in `physics.warnings`, and with `[physics] reject_uncarried` it has no plan,
/// for that reason.
/// (The shelf side was this test's part until its grasps were held at the fingertips, where
/// they pinch its panel bars and carry it.)
#[test]
fn uncarried_plans_are_flagged_or_refused() {
    use pregrasp_planner::pipeline::{plan, PlanOptions};
    let row = [("family", "h_frame"), ("seed", "19")]
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .into();
    let (mut scene, mesh) = scene_of(&row);
    let run = |scene: &Scene| {
        plan(scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {})
            .unwrap()
            .file
    };
    let kept = run(&scene);
    assert!(!kept.plans.is_empty());
    for p in &kept.plans {
        let warnings = &p.physics.as_ref().unwrap().warnings;
        assert!(
            warnings.iter().any(|w| w.starts_with("carry: ")),
            "{warnings:?}"
        );
    }
    scene.physics.reject_uncarried = true;
    let refused = run(&scene);
    assert!(refused.plans.is_empty());
    let reason = refused.reason.unwrap();
    assert!(reason.contains("caged"), "{reason}");
    // The chair side carries: the flag changes nothing there (one plan: its second candidate
    // hangs on the pads' twist, `physics::twist`).
    let (mut scene, mesh) = example_files("chair_side");
    let before = plan(&scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file
        .plans
        .len();
    scene.physics.reject_uncarried = true;
    let after = plan(&scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file
        .plans
        .len();
    assert_eq!((before, after), (1, 1));
}
