//! End-to-end properties of the pipeline (Algorithms 1–3 + plan file + checker).

use pregrasp_io::plan_file::{Outcome, PlanStatus};
use std::path::Path;

use nalgebra::{Isometry3, Point2, Translation3, UnitQuaternion};
use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;
use pregrasp_planner::check::check_plan;
use pregrasp_planner::pipeline::{plan, PlanOptions};

fn example(name: &str) -> (Scene, Mesh) {
    let ex = pregrasp_examples::by_name(name).expect("built-in example");
    let scene = Scene::from_str(&ex.scene_toml, Path::new(&format!("examples/{name}.toml")))
        .expect("example scene parses");
    (scene, ex.mesh)
}

fn run(scene: &Scene, mesh: &Mesh) -> PlanFile {
    plan(scene, mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file
}

/// The plan file without its timings (the only part allowed to differ between runs).
fn without_timing(file: &PlanFile) -> String {
    let mut f = file.clone();
    f.timing_ms.clear();
    f.to_json()
}

fn assert_valid(file: &PlanFile, mesh: &Mesh) {
    let report = check_plan(file, mesh);
    for rule in &report.rules {
        assert_ne!(
            rule.ok,
            Some(false),
            "rule {} failed: {}",
            rule.rule,
            rule.detail
        );
    }
}

/// Every built-in example plans, and every plan it keeps passes the checker; plans are ranked
/// best first. Fails as soon as an example stops producing a valid plan.
#[test]
fn every_example_plans_and_its_plans_pass_the_check() {
    for name in pregrasp_examples::NAMES {
        let (scene, mesh) = example(name);
        let file = run(&scene, &mesh);
        assert_eq!(
            file.status,
            PlanStatus::Planned,
            "{name}: {:?}",
            file.reason
        );
        assert!(!file.plans.is_empty(), "{name}");
        assert_valid(&file, &mesh);
        for w in file.plans.windows(2) {
            assert!(
                w[0].score >= w[1].score,
                "{name}: plans not ranked by S_rot"
            );
        }
        // The chosen candidate's θ_goal lies within its θ_max and is a multiple of Δφ.
        let best = &file.candidates[file.plans[0].candidate];
        let goal = best.theta_goal.expect("a planned candidate has θ_goal");
        assert!(goal > 0.0 && goal <= best.theta_max, "{name}");
        let steps = goal / scene.planner.step;
        assert!(
            (steps - steps.round()).abs() < 1e-9,
            "{name}: θ_goal {goal} not a multiple of Δφ"
        );
    }
}

#[test]
fn same_plan_for_one_and_two_threads_and_across_runs() {
    let (scene, mesh) = example("chair_side");
    let in_pool = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| without_timing(&run(&scene, &mesh)))
    };
    let one = in_pool(1);
    let two = in_pool(2);
    assert_eq!(one, two);
    assert_eq!(two, in_pool(2));
}

/// A 0.6 m bar whose two power grasps sit at its two ends: every hull edge near the support is
/// within Δd_a of one of them.
#[test]
fn power_grasps_on_the_axes_give_no_plan_with_the_distance_reason() {
    let (mut scene, _) = example("chair_side");
    let outline = [
        Point2::new(0.0, 0.0),
        Point2::new(0.6, 0.0),
        Point2::new(0.6, 0.05),
        Point2::new(0.0, 0.05),
    ];
    let bar = pregrasp_examples::extrude(&outline, &[], 0.03);
    let down = UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
    scene.grasps.power = [
        Isometry3::from_parts(Translation3::new(0.02, 0.025, 0.015), down),
        Isometry3::from_parts(Translation3::new(0.58, 0.025, 0.015), down),
    ];
    let file = run(&scene, &bar);
    assert_eq!(file.status, PlanStatus::NoPlan);
    assert_eq!(
        file.reason.as_deref(),
        Some("no candidate: every power grasp within Δd_a of every axis")
    );
    assert!(!file.candidates.is_empty());
    assert!(file
        .candidates
        .iter()
        .all(|c| c.outcome.to_string().contains("within Δd_a")));
}

/// A part the scene places above the support has no edge within Δd_s of it: the reason says how
/// far above, and which keys place it; a part that rests keeps the bare reason.
#[test]
fn a_part_off_the_support_gives_no_candidate_naming_the_gap() {
    let (mut scene, mesh) = example("chair_side");
    scene.support_height = -0.03;
    let file = run(&scene, &mesh);
    assert_eq!(file.status, PlanStatus::NoPlan);
    let reason = file.reason.expect("a reason");
    assert!(
        reason.starts_with("Algorithm 1: no rotation-axis candidate")
            && reason.contains("the part's lowest point is 30.0 mm above the support")
            && reason.contains("`support.height` -0.03 m"),
        "{reason}"
    );
    // Resting on the support, with every hull edge too short: no gap to name.
    let (mut scene, mesh) = example("chair_side");
    scene.planner.min_axis_length = 10.0;
    let reason = run(&scene, &mesh).reason.expect("a reason");
    assert_eq!(
        reason,
        "Algorithm 1: no rotation-axis candidate (no convex-hull edge within Δd_s of the \
         support and longer than Δl)"
    );
}

#[test]
fn support_grasp_off_the_part_gives_no_plan_naming_the_grasp() {
    let (mut scene, mesh) = example("chair_side");
    // Two metres beyond the part: the fingers would close on nothing.
    scene.grasps.support.translation.vector.x += 2.0;
    let file = run(&scene, &mesh);
    assert_eq!(file.status, PlanStatus::NoPlan);
    let reason = file.reason.expect("a reason");
    assert!(
        reason.starts_with("grasp: support grasp of arm")
            && reason.ends_with("close on nothing (no part between the fingers)"),
        "{reason}"
    );
}

#[test]
fn support_grasp_from_below_the_table_gives_no_plan_naming_the_closing() {
    let (mut scene, mesh) = example("chair_side");
    // Approached from below, through the table: the fingers still close on the bar, but
    // they would close inside the support.
    let flip = UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0);
    scene.grasps.support.rotation *= flip;
    let file = run(&scene, &mesh);
    assert_eq!(file.status, PlanStatus::NoPlan);
    let reason = file.reason.expect("a reason");
    assert!(
        reason.starts_with("grasp: support grasp of arm")
            && reason.contains("closing fingers reach")
            && reason.ends_with("mm into the support at P_init"),
        "{reason}"
    );
}

mod edited_plans_fail_the_check {
    use super::*;

    fn planned() -> (PlanFile, Mesh) {
        let (scene, mesh) = example("chair_side");
        let mut file = run(&scene, &mesh);
        assert_eq!(file.status, PlanStatus::Planned);
        file.plans.truncate(1);
        assert_valid(&file, &mesh);
        (file, mesh)
    }

    fn failed_rules(file: &PlanFile, mesh: &Mesh) -> Vec<u8> {
        check_plan(file, mesh)
            .rules
            .iter()
            .filter(|r| r.ok == Some(false))
            .map(|r| r.rule)
            .collect()
    }

    #[test]
    fn a_joint_past_its_limit_fails_rule_1() {
        let (mut file, mesh) = planned();
        let seg = &mut file.plans[0].segments[2];
        let k = seg.points.len() / 2;
        seg.points[k].q[2] = 3.3; // elbow limit is ±π
        assert!(failed_rules(&file, &mesh).contains(&1));
    }

    #[test]
    fn a_point_moved_into_the_table_fails_rule_2() {
        let (mut file, mesh) = planned();
        let seg = &mut file.plans[0].segments[0];
        let k = seg.approach_from.unwrap() / 2;
        // Swing the shoulder down until the forearm lies in the table.
        seg.points[k].q[1] = 0.6;
        assert!(failed_rules(&file, &mesh).contains(&2));
    }

    /// The table raised until the pinching fingertips are 1 mm inside it: rule 2 fails on the
    /// supportive gripper against the support (the part is then below the table too: rule 3).
    #[test]
    fn fingertips_1_mm_inside_the_table_fail_rule_2() {
        let (mut file, mesh) = planned();
        let report = check_plan(&file, &mesh);
        let closest = report.closest_grasp_to_support.expect("states checked");
        assert!(
            closest >= 0.002,
            "planned with the 2 mm clearance: {closest}"
        );
        file.support_height += closest + 0.001;
        let report = check_plan(&file, &mesh);
        let rule2 = report.rules.iter().find(|r| r.rule == 2).unwrap();
        assert_eq!(rule2.ok, Some(false));
        assert!(
            rule2.detail.contains("/gripper_") && rule2.detail.ends_with("touches support"),
            "{}",
            rule2.detail
        );
        assert!(report.closest_grasp_to_support.unwrap() <= -0.001 + 1e-9);
    }

    #[test]
    fn a_tool_pose_5_mm_off_fails_rule_4() {
        let (mut file, mesh) = planned();
        file.grasps.support.xyz[0] += 0.005;
        assert_eq!(failed_rules(&file, &mesh), vec![4]);
    }

    #[test]
    fn an_object_pose_below_the_support_fails_rule_3() {
        let (mut file, mesh) = planned();
        let seg = &mut file.plans[0].segments[1];
        let k = seg.points.len() / 2;
        seg.points[k].object_pose.as_mut().unwrap().xyz[2] -= 0.01;
        assert!(failed_rules(&file, &mesh).contains(&3));
    }
}

/// Algorithm 3 in waves: once `max_plans` plans are kept from candidates whose scores beat
/// every candidate not yet run, the rest are not evaluated — and the plans kept are the ones a
/// run over every candidate keeps, for any wave size and thread count.
#[test]
fn waves_stop_once_the_kept_plans_outrank_the_rest_and_keep_the_same_plans() {
    let (scene, mesh) = example("chair_side");
    let with = |max_plans: usize, wave: usize, threads: usize| -> PlanFile {
        let options = PlanOptions {
            max_plans,
            wave,
            ..PlanOptions::default()
        };
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| plan(&scene, &mesh, &options, &|_| {}, &|| {}).unwrap())
            .file
    };
    let every = with(1, usize::MAX, 2);
    let first = with(1, 1, 1);
    assert_eq!(first.status, PlanStatus::Planned);
    assert_eq!(
        serde_json::to_string(&first.plans).unwrap(),
        serde_json::to_string(&every.plans).unwrap(),
        "the same plan kept"
    );
    let skipped: Vec<usize> = first
        .candidates
        .iter()
        .filter(|c| c.outcome.to_string().starts_with("not evaluated"))
        .map(|c| c.id)
        .collect();
    assert!(
        !skipped.is_empty(),
        "a wave of one stops after the first plan"
    );
    let kept = first.plans[0].candidate;
    for &id in &skipped {
        assert!(first.candidates[id].score < first.candidates[kept].score);
        // Run over every candidate, each skipped one was outranked or failed.
        assert_ne!(every.candidates[id].outcome, Outcome::Planned);
    }
    // Deterministic for any thread count; a wave holding every candidate skips none.
    assert_eq!(without_timing(&first), without_timing(&with(1, 1, 2)));
    assert!(every
        .candidates
        .iter()
        .all(|c| !c.outcome.to_string().starts_with("not evaluated")));
}
