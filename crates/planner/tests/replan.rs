//! Issue 16: re-planning from a measured pose keeps the plan's rotation axis, changes only what
//! the pose demands, and passes the checker; the robustness report is the same for any number
//! of threads.

use pregrasp_io::plan_file::PlanStatus;
use std::path::Path;

use nalgebra::{Isometry3, Point3, Vector3};
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;
use pregrasp_planner::check::check_plan;
use pregrasp_planner::pipeline::{plan, PlanOptions};
use pregrasp_planner::replan::{replan, ReplanRoute};
use pregrasp_planner::robustness::{plan_ranked_by_robustness, robustness, PlacementError};

fn example(name: &str) -> (Scene, pregrasp_geometry::Mesh, PlanFile) {
    let ex = pregrasp_examples::by_name(name).unwrap();
    let scene =
        Scene::from_str(&ex.scene_toml, Path::new(&format!("examples/{name}.toml"))).unwrap();
    let file = plan(&scene, &ex.mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file;
    assert_eq!(file.status, PlanStatus::Planned, "{name}");
    (scene, ex.mesh, file)
}

fn theta_goal(file: &PlanFile) -> f64 {
    file.candidates[file.plans[0].candidate].theta_goal.unwrap()
}

#[test]
fn replan_at_the_nominal_pose_gives_the_nominal_plan() {
    let (scene, mesh, nominal) = example("chair_side");
    let r = replan(
        &scene,
        &mesh,
        &nominal,
        0,
        scene.object.pose,
        &PlanOptions::default(),
    )
    .unwrap();
    assert_eq!(r.route, ReplanRoute::KeptCandidate);
    assert_eq!(r.report.file.plans.len(), 1);
    assert_eq!(r.report.file.plans[0], nominal.plans[0]);
}

/// Moving the part 5 mm along the table moves the rotation with it: the same axis (in the
/// object frame), roles, grasps and θ_goal, P_obj translated by exactly the offset; only the
/// arms' motions are new — and they pass the checker.
#[test]
fn a_shifted_part_keeps_its_axis_and_rotation() {
    for name in ["chair_side", "shelf_side"] {
        let (scene, mesh, nominal) = example(name);
        let shift = Isometry3::translation(0.005, -0.003, 0.0);
        let moved = shift * scene.object.pose;
        let r = replan(&scene, &mesh, &nominal, 0, moved, &PlanOptions::default()).unwrap();
        assert_eq!(r.route, ReplanRoute::KeptCandidate, "{name}");
        let file = &r.report.file;
        let (a, b) = (&nominal.plans[0], &file.plans[0]);
        assert_eq!(
            (&a.master, &a.supportive),
            (&b.master, &b.supportive),
            "{name}"
        );
        assert_eq!(file.grasps, nominal.grasps, "{name}");
        assert!(
            (theta_goal(file) - theta_goal(&nominal)).abs() < 1e-9,
            "{name}"
        );
        let goal_a = shift * a.object_goal_pose.to_isometry();
        let goal_b = b.object_goal_pose.to_isometry();
        assert!((goal_a.translation.vector - goal_b.translation.vector).norm() < 1e-9);
        assert!(goal_a.rotation.angle_to(&goal_b.rotation) < 1e-9);
        assert_ne!(
            a.segments, b.segments,
            "{name}: the arms must move differently"
        );
        let report = check_plan(file, &mesh);
        assert!(report.is_valid(), "{name}: {:?}", report.rules);
    }
}

/// A yawed part: the same hull edge, found again by its object-frame endpoints.
#[test]
fn a_turned_part_keeps_its_axis_and_passes_the_check() {
    let (scene, mesh, nominal) = example("stool_side");
    let centre = scene.object.pose * Point3::new(0.2, 0.2, 0.0);
    let turn = Isometry3::rotation_wrt_point(
        nalgebra::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 2f64.to_radians()),
        centre,
    );
    let r = replan(
        &scene,
        &mesh,
        &nominal,
        0,
        turn * scene.object.pose,
        &PlanOptions::default(),
    )
    .unwrap();
    assert_eq!(r.route, ReplanRoute::KeptCandidate);
    assert!(check_plan(&r.report.file, &mesh).is_valid());
}

#[test]
fn the_robustness_report_is_the_same_for_one_and_two_threads() {
    let (scene, mesh, nominal) = example("chair_side");
    let levels = [PlacementError {
        pos: 0.01,
        yaw: 3f64.to_radians(),
    }];
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| robustness(&scene, &mesh, &nominal, &levels, 3, 7, &|| {}).unwrap())
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one, two);
    assert_eq!(one.samples.len(), 3);
    // The samples differ from each other (the generator is seeded per sample).
    assert_ne!(one.samples[0].dx, one.samples[1].dx);
    assert!(one
        .samples
        .iter()
        .all(|s| s.dx.abs() <= 0.01 && s.dyaw.abs() <= 3f64.to_radians()));
}

/// `[planner] robustness_samples`: every kept plan carries its share, plans are ordered by it,
/// and the option is echoed; off, the plan file is exactly the plain pipeline's.
#[test]
fn robustness_samples_rank_the_plans() {
    let ex = pregrasp_examples::by_name("shelf_side").unwrap();
    let text = ex.scene_toml.replace(
        "[planner]",
        "[planner]\nrobustness_samples = 4\nrobustness_pos = 0.01\nrobustness_yaw_deg = 3",
    );
    assert_ne!(text, ex.scene_toml, "the example has a [planner] table");
    let scene = Scene::from_str(&text, Path::new("examples/shelf_side.toml")).unwrap();
    let file =
        plan_ranked_by_robustness(&scene, &ex.mesh, &PlanOptions::default(), &|_| {}, &|| {})
            .unwrap()
            .file;
    assert_eq!(file.planner.robustness_samples, Some(4));
    assert!(!file.plans.is_empty());
    let shares: Vec<f64> = file
        .plans
        .iter()
        .map(|p| p.robustness.as_ref().unwrap().levels[0].share)
        .collect();
    assert!(shares.windows(2).all(|w| w[0] >= w[1]), "{shares:?}");
    assert!(pregrasp_planner::plan_format::validate(&file).is_ok());

    let (plain_scene, mesh, plain) = example("shelf_side");
    let off = plan_ranked_by_robustness(
        &plain_scene,
        &mesh,
        &PlanOptions::default(),
        &|_| {},
        &|| {},
    )
    .unwrap()
    .file;
    let strip = |mut f: PlanFile| {
        f.timing_ms.clear();
        f
    };
    assert_eq!(strip(off), strip(plain));
}

/// `--from rot`: sup1 has run and the gripper holds the part; the part turns out to lie 1 mm
/// further along the pad's width (tool y) than planned. The executed sup1 is kept, μ_rot starts
/// exactly where the arm stands, the grasp the fingers really hold is recorded, and the plan
/// passes the checker.
#[test]
fn replan_from_rot_keeps_the_executed_sup1() {
    use pregrasp_planner::replan::replan_from_rot;
    let (scene, mesh, nominal) = example("chair_side");
    // Unchanged pose: the rest of the plan is the nominal one.
    let same = replan_from_rot(&scene, &mesh, &nominal, 0, scene.object.pose).unwrap();
    assert_eq!(same.route, ReplanRoute::KeptCandidate);
    let (a, b) = (&nominal.plans[0], &same.report.file.plans[0]);
    for (sa, sb) in a.segments.iter().zip(&b.segments) {
        assert_eq!(sa.points.len(), sb.points.len(), "{}", sa.name);
        for (pa, pb) in sa.points.iter().zip(&sb.points) {
            let d =
                pa.q.iter()
                    .zip(&pb.q)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max);
            assert!(d < 1e-6, "{}: {d}", sa.name);
        }
    }

    let g_s = scene.initial_object_pose() * scene.grasps.support;
    let along = g_s.rotation * Vector3::y() * 0.001;
    let moved = Isometry3::translation(along.x, along.y, 0.0) * scene.object.pose;
    let r = replan_from_rot(&scene, &mesh, &nominal, 0, moved).unwrap();
    assert_eq!(
        r.route,
        ReplanRoute::KeptCandidate,
        "{:?}",
        r.report.file.reason
    );
    let file = &r.report.file;
    let p = &file.plans[0];
    assert_eq!(
        p.segments[0], nominal.plans[0].segments[0],
        "sup1 as executed"
    );
    assert_eq!(
        p.segments[1].points[0].q,
        nominal.plans[0].segments[0].points.last().unwrap().q
    );
    assert_ne!(
        file.grasps.support, nominal.grasps.support,
        "the grasp really held"
    );
    assert!(check_plan(file, &mesh).is_valid());
}

/// The cell's loop: the part's geometry and closings built once ([`PartKnowledge`]) and handed
/// to every replan give the plans a replan from scratch gives, byte for byte but timing; and a
/// knowledge built for other grasps is not used.
#[test]
fn replans_reusing_the_parts_knowledge_are_the_replans_from_scratch() {
    use pregrasp_planner::context::PartKnowledge;
    use pregrasp_planner::robustness::displaced;
    use std::sync::Arc;
    for name in ["chair_side", "stool_side"] {
        let (scene, mesh, nominal) = example(name);
        let known = PlanOptions {
            known: Some(Arc::new(PartKnowledge::new(&scene, &mesh).unwrap())),
            ..PlanOptions::default()
        };
        let centre = scene.object.pose * Point3::new(0.2, 0.2, 0.0);
        for (dx, dy, yaw) in [
            (0.004, -0.002, 1.5f64),
            (-0.005, 0.003, -2.0),
            (0.0, 0.0, 0.5),
        ] {
            let pose = displaced(&scene.object.pose, &centre, dx, dy, yaw.to_radians());
            let fresh = replan(&scene, &mesh, &nominal, 0, pose, &PlanOptions::default()).unwrap();
            let reused = replan(&scene, &mesh, &nominal, 0, pose, &known).unwrap();
            let json = |f: &PlanFile| {
                let mut f = f.clone();
                f.timing_ms.clear();
                f.to_json()
            };
            assert_eq!(fresh.route, reused.route, "{name}");
            assert_eq!(
                json(&fresh.report.file),
                json(&reused.report.file),
                "{name}"
            );
            assert!(check_plan(&reused.report.file, &mesh).is_valid(), "{name}");
        }
    }
    // Knowledge of other grasps does not fit: the closings are built afresh, same plan.
    let (mut scene, mesh, _) = example("chair_side");
    let known = PlanOptions {
        known: Some(Arc::new(PartKnowledge::new(&scene, &mesh).unwrap())),
        ..PlanOptions::default()
    };
    scene.grasps.support.translation.vector.x += 0.01;
    let json = |options: &PlanOptions| {
        let mut f = plan(&scene, &mesh, options, &|_| {}, &|| {}).unwrap().file;
        f.timing_ms.clear();
        f.to_json()
    };
    assert_eq!(json(&PlanOptions::default()), json(&known));
}

/// A whole plan with the part's knowledge handed in (`bench plan`'s "known" runs: every hold
/// the pipeline tries, the chair side's three among them) is the plan made from scratch, byte
/// for byte but timing, and so is a second plan with the same knowledge, its closings all
/// remembered by then.
#[test]
fn plans_with_the_part_known_are_the_plans_from_scratch() {
    use pregrasp_planner::context::PartKnowledge;
    use std::sync::Arc;
    for name in ["chair_side", "shelf_side", "stool_side"] {
        let (scene, mesh, _) = example(name);
        let known = PlanOptions {
            known: Some(Arc::new(PartKnowledge::new(&scene, &mesh).unwrap())),
            ..PlanOptions::default()
        };
        let json = |options: &PlanOptions| {
            let mut f = plan(&scene, &mesh, options, &|_| {}, &|| {}).unwrap().file;
            f.timing_ms.clear();
            f.to_json()
        };
        let fresh = json(&PlanOptions::default());
        assert_eq!(fresh, json(&known), "{name}");
        assert_eq!(fresh, json(&known), "{name}: again");
    }
}
