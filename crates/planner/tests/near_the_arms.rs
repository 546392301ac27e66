//! Parts close to the arms (issue 20): the link shapes follow the real links, so a part 40 mm
//! from a robot's foot plans and its plan passes the checker.

use pregrasp_io::plan_file::PlanStatus;
use std::path::Path;

use nalgebra::Point3;
use pregrasp_examples::scene::{object_pose, scene_toml};
use pregrasp_examples::{ChairSideParams, SceneLayout};
use pregrasp_io::scene::Scene;
use pregrasp_planner::check::check_plan;
use pregrasp_planner::pipeline::{plan, PlanOptions};

/// Radius of the UR5e foot (m): a Ø151 mm cylinder.
const FOOT_RADIUS: f64 = 0.0755;

/// Smallest horizontal distance (m) from the vertical axis through `base` to the part's
/// vertices, with the part laid out by `layout`.
fn distance_to_foot_axis(layout: &SceneLayout, base: [f64; 3]) -> (f64, Point3<f64>) {
    let design = ChairSideParams::default().design();
    let pose = object_pose(&design, layout);
    design
        .mesh()
        .vertices
        .iter()
        .map(|v| {
            let w = pose * v;
            ((w.x - base[0]).hypot(w.y - base[1]), w)
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .expect("vertices")
}

#[test]
fn a_part_40_mm_from_a_foot_plans() {
    // Slide the chair side towards the arms until its nearest corner is 40 mm from the right
    // arm's foot (the old square base model reached 114 mm from the axis, +8 mm of margins).
    let mut layout = SceneLayout::default();
    let base = layout.arms[1].base_xyz;
    let target = FOOT_RADIUS + 0.040;
    for _ in 0..8 {
        let (d, nearest) = distance_to_foot_axis(&layout, base);
        let dy = nearest.y - base[1];
        let dx = nearest.x - base[0];
        let want_dx = (target * target - dy * dy).max(0.0).sqrt();
        let _ = d;
        layout.axis_x += want_dx - dx;
    }
    let (d, _) = distance_to_foot_axis(&layout, base);
    assert!(
        (d - target).abs() < 5e-4,
        "nearest vertex {d} m from the foot axis"
    );

    let design = ChairSideParams::default().design();
    let text = scene_toml(
        "near_foot",
        "chair side by the foot",
        "unused.stl",
        &design,
        &layout,
    );
    let scene = Scene::from_str(&text, Path::new("near_foot.toml")).unwrap();
    let mesh = design.mesh();
    let report = plan(&scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {}).unwrap();
    let file = report.file;
    assert_eq!(file.status, PlanStatus::Planned, "{:?}", file.reason);
    let check = check_plan(&file, &mesh);
    assert!(check.is_valid(), "{:?}", check.rules);
}

/// The two arms 0.34 m apart over a shelf side: a gripper passes within 35 mm of the other
/// arm's wrist, and the plan holds the checker. (Measured between the shapes' boxes, which
/// bound the finger links' convex pieces by up to a few millimetres.)
#[test]
fn a_gripper_passes_within_35_mm_of_the_other_wrist() {
    use pregrasp_collision::shape::pair_distance;
    use pregrasp_planner::context::arm_models;
    use pregrasp_robot::GripperState;

    let mut layout = SceneLayout {
        axis_x: 0.32,
        ..SceneLayout::default()
    };
    layout.arms[0].base_xyz[1] = 0.17;
    layout.arms[1].base_xyz[1] = -0.17;
    let design = pregrasp_examples::ShelfSideParams::default().design();
    let text = scene_toml(
        "close_arms",
        "shelf side, arms close",
        "unused.stl",
        &design,
        &layout,
    );
    let scene = Scene::from_str(&text, Path::new("close_arms.toml")).unwrap();
    let mesh = design.mesh();
    let file = plan(&scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file;
    assert_eq!(file.status, PlanStatus::Planned, "{:?}", file.reason);
    let check = check_plan(&file, &mesh);
    assert!(check.is_valid(), "{:?}", check.rules);

    // Closest approach of either gripper to the other arm's wrist links along the plans.
    let arms = arm_models(&scene).unwrap();
    let mut closest = f64::INFINITY;
    for plan_entry in &file.plans {
        let mut q = [scene.robots[0].start, scene.robots[1].start];
        for seg in &plan_entry.segments {
            let arm = usize::from(seg.robot != scene.robots[0].name);
            for w in seg.points.windows(2) {
                for f in [0.0, 0.25, 0.5, 0.75] {
                    q[arm] = std::array::from_fn(|j| w[0].q[j] + f * (w[1].q[j] - w[0].q[j]));
                    let grip = arms[arm].placed_shapes(&q[arm], GripperState::Open);
                    let other = arms[1 - arm].placed_shapes(&q[1 - arm], GripperState::Open);
                    for (_, g) in grip.iter().filter(|(n, _)| n.contains("/gripper")) {
                        for (_, o) in other.iter().filter(|(n, _)| n.contains("wrist")) {
                            closest = closest.min(pair_distance(g, o));
                        }
                    }
                }
            }
            q[arm] = seg.points.last().unwrap().q;
        }
    }
    assert!(
        closest <= 0.035 && closest >= scene.planner.link_clearance,
        "closest gripper–wrist approach {:.1} mm",
        closest * 1e3
    );
}
