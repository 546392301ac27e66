//! Scenes that only plan with the 2F-85 as it really closes (issue 32): a bench end whose
//! pinch puts a finger in a hand hole, a ladder whose rail is power-grasped a few degrees off
//! the table, the same ladder with too little rotation allowed, refused for its fingers, and
//! the ladder planned with no clearances at all, which check (with none) must accept.

use std::f64::consts::FRAC_PI_2;
use std::path::Path;

use nalgebra::Point2;
use pregrasp_examples::design::{GraspSite, PartDesign};
use pregrasp_examples::scene::{scene_toml, SceneLayout};
use pregrasp_examples::ShelfSideParams;
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

/// The end of a bench: a 25 mm board with hand holes that leave 35 mm handle bars along its
/// edges. The support grasp pinches the handle bar of hole B, 50 mm wide, one finger outside
/// the board, the other in the hole; the power grasps wrap the bars of holes A and C, 75 mm
/// wide (a power grasp's open fingers reach 35 mm past a 35 mm bar at the height of its top
/// face, so a 50 mm hole leaves them no room).
fn bench_end() -> PartDesign {
    let params = ShelfSideParams {
        thickness: 0.025,
        handle_bar_width: 0.035,
        hand_hole_width: 0.075,
        pins_per_row: 0,
        ..ShelfSideParams::default()
    };
    let mut design = params.design();
    let (cx, hl, d, bar) = (
        params.hole_b_centre_x,
        params.hand_hole_length,
        params.depth,
        params.handle_bar_width,
    );
    let (x0, x1, y0, y1) = (cx - hl / 2.0, cx + hl / 2.0, d - bar - 0.050, d - bar);
    let p = Point2::new;
    design.holes[1] = vec![p(x0, y0), p(x0, y1), p(x1, y1), p(x1, y0)];
    design
}

/// A ladder lying on the table: two 40 mm × 25 mm rails 0.45 m apart (outside), four rungs of
/// the same section; one top corner chamfered so that the outer edge of rail A is the longest
/// hull edge (the axis). Both power grasps and the support pinch are on rail B, across it,
/// 0.43 m from the axis.
///
/// Closing on the rail, the fingers cage it (tips meeting under it, 155 mm from the flange)
/// and reach 169.8 mm on the way — 39 mm below the rail, as deep as MuJoCo's closing of the
/// Menagerie model gets there: with the 2.6 mm finger–support clearance the rail must rise
/// 42 mm, 5.6° about the axis, so θ_goal = 6° + n_ext (3°) = 9°. (0.38 m from the axis it
/// would be 10°.)
fn ladder() -> PartDesign {
    let p = Point2::new;
    let (l, w, bar, c) = (1.0, 0.45, 0.040, 0.03);
    let outline = vec![p(0.0, 0.0), p(l, 0.0), p(l, w - c), p(l - c, w), p(0.0, w)];
    let rungs = [0.0, 0.32, 0.64, l - bar];
    let holes = rungs
        .windows(2)
        .map(|r| {
            let (x0, x1, y0, y1) = (r[0] + bar, r[1], bar, w - bar);
            vec![p(x0, y0), p(x0, y1), p(x1, y1), p(x1, y0)]
        })
        .collect();
    let on_rail_b = |bar_name: &'static str, x: f64| GraspSite {
        bar: bar_name,
        point: p(x, w - bar / 2.0),
        closing_angle: FRAC_PI_2,
        bar_width: bar,
    };
    PartDesign {
        outline,
        holes,
        thickness: 0.025,
        axis: [p(0.0, 0.0), p(l, 0.0)],
        support: on_rail_b("rail B, middle", 0.48),
        power_near: on_rail_b("rail B, near end", 0.16),
        power_far: on_rail_b("rail B, far end", 0.80),
    }
}

#[test]
fn a_bench_end_pinched_with_a_finger_in_its_hand_hole_plans_and_checks() {
    let file = plan_design("bench_end", &bench_end(), "");
    assert_eq!(file.status, "planned", "{:?}", file.reason);
    let check = check_plan(&file, &bench_end().mesh());
    assert!(check.is_valid(), "{:?}", check.rules);
}

#[test]
fn a_ladder_rail_is_power_grasped_within_9_degrees_and_checks() {
    let file = plan_design("ladder", &ladder(), "");
    assert_eq!(file.status, "planned", "{:?}", file.reason);
    let theta = theta_goal_deg(&file);
    assert!(theta <= 9.0 + 1e-9, "θ_goal {theta:.1}°");
    let check = check_plan(&file, &ladder().mesh());
    assert!(check.is_valid(), "{:?}", check.rules);
}

#[test]
fn fingers_closing_into_the_table_at_every_allowed_angle_are_refused_for_it() {
    // φ_obj 4°: the rail never rises far enough for the fingers to close under it.
    let file = plan_design("ladder_4deg", &ladder(), "max_angle_deg = 4.0");
    assert_eq!(file.status, "no_plan");
    let reason = file.reason.expect("a reason");
    assert!(
        reason.contains("closing fingers reach the support at every angle"),
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
    assert_eq!(file.status, "planned", "{:?}", file.reason);
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
