//! Scenes that only plan with the 2F-85 as it really closes (issue 32): a bench end whose
//! pinch puts a finger in a hand hole, a ladder whose rail is power-grasped a few degrees off
//! the table, the same ladder with too little rotation allowed, refused for its fingers, and
//! the ladder planned with no clearances at all, which check (with none) must accept.

use pregrasp_io::plan_file::PlanStatus;
use std::path::Path;

use pregrasp_examples::design::PartDesign;
use pregrasp_examples::scene::{scene_toml, SceneLayout};
use pregrasp_examples::{BenchEndParams, LadderParams};
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;
use pregrasp_planner::check::check_plan;
use pregrasp_planner::pipeline::{plan, PlanOptions};

/// Plans `design` laid out as the examples are, with `planner` lines added to its scene.
fn plan_design(name: &str, design: &PartDesign, planner: &str) -> PlanFile {
    let mut text = scene_toml(name, name, "unused.stl", design, &SceneLayout::default());
    if !planner.is_empty() {
        text = text.replace("[planner]", &format!("[planner]\n{planner}"));
    }
    let scene = Scene::from_str(&text, Path::new(&format!("{name}.toml"))).unwrap();
    plan(
        &scene,
        &design.mesh(),
        &PlanOptions::default(),
        &|_| {},
        &|| {},
    )
    .unwrap()
    .file
}

/// θ_goal of the file's best plan (degrees).
fn theta_goal_deg(file: &PlanFile) -> f64 {
    file.candidates[file.plans[0].candidate]
        .theta_goal
        .expect("a planned candidate has θ_goal")
        .to_degrees()
}

/// The bench end of [`BenchEndParams`]: the pinch puts a finger in a 50 mm hand hole.
fn bench_end() -> PartDesign {
    BenchEndParams::default().design()
}

/// The ladder of [`LadderParams`]: 40 × 25 mm rails, grasped on rail B 0.43 m from the axis.
fn ladder() -> PartDesign {
    LadderParams::default().design()
}

#[test]
fn a_bench_end_pinched_with_a_finger_in_its_hand_hole_plans_and_checks() {
    let file = plan_design("bench_end", &bench_end(), "");
    assert_eq!(file.status, PlanStatus::Planned, "{:?}", file.reason);
    let check = check_plan(&file, &bench_end().mesh());
    assert!(check.is_valid(), "{:?}", check.rules);
}

#[test]
fn a_ladder_rail_is_power_grasped_within_9_degrees_and_checks() {
    let file = plan_design("ladder", &ladder(), "");
    assert_eq!(file.status, PlanStatus::Planned, "{:?}", file.reason);
    let theta = theta_goal_deg(&file);
    assert!(theta <= 9.0 + 1e-9, "θ_goal {theta:.1}°");
    let check = check_plan(&file, &ladder().mesh());
    assert!(check.is_valid(), "{:?}", check.rules);
}

#[test]
fn fingers_closing_into_the_table_at_every_allowed_angle_are_refused_for_it() {
    // φ_obj 4°: the rail never rises far enough for the fingers to close under it. (Its
    // closing cages the rail at the scene's depth, so the grasp is held at the fingertips,
    // whose open fingers reach deeper still: the dummies never clear the support.)
    let file = plan_design("ladder_4deg", &ladder(), "max_angle_deg = 4.0");
    assert_eq!(file.status, PlanStatus::NoPlan);
    let reason = file.reason.expect("a reason");
    assert!(
        reason.contains("closing fingers reach the support at every angle")
            || reason.contains("dummies never clear the support"),
        "{reason}"
    );
}

#[test]
fn a_plan_at_zero_clearances_is_accepted_by_check() {
    // The tightest plan the real closing allows: no clearances, no extra steps. The fingers
    // come as close to the table as the closing lets them, and check (the same clearances)
    // must not ask for more.
    let planner = "finger_support_clearance = 0.0\nlink_clearance = 0.0\nextra_steps = 0";
    let file = plan_design("ladder_tight", &ladder(), planner);
    assert_eq!(file.status, PlanStatus::Planned, "{:?}", file.reason);
    let theta = theta_goal_deg(&file);
    assert!(theta <= 6.0 + 1e-9, "θ_goal {theta:.1}°");
    let check = check_plan(&file, &ladder().mesh());
    assert!(check.is_valid(), "{:?}", check.rules);
    let closest = check.closest_grasp_to_support.expect("a grasping gripper");
    assert!(closest < 0.005, "closest grasp to the support {closest}");
}

#[test]
fn a_ladder_plan_made_by_the_parallel_finger_model_passes_check() {
    // Planned by pregrasp 73a7ec8 (fingers closing in parallel to a gap, θ_goal 10°) on the
    // same ladder: another planner's plan, clear under the real closing, is accepted.
    let text = include_str!("fixtures/ladder_planned_by_73a7ec8.json");
    let file = PlanFile::from_json_str(text, "ladder_planned_by_73a7ec8.json").unwrap();
    assert!((theta_goal_deg(&file) - 10.0).abs() < 1e-9);
    let check = check_plan(&file, &ladder().mesh());
    assert!(check.is_valid(), "{:?}", check.rules);
}
