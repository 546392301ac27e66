//! `replan --from mas1` / `--from sup2` (issue 35): what is left of a plan, planned again with
//! the part measured where it is once `rot` (and `mas1`) have run.

use std::path::Path;

use nalgebra::{Isometry3, Translation3};
use pregrasp_geometry::Mesh;
use pregrasp_io::mesh_io::load_mesh;
use pregrasp_io::plan_file::{PlanFile, PlanStatus};
use pregrasp_io::scene::Scene;
use pregrasp_planner::check::check_plan;
use pregrasp_planner::pipeline::PlanOptions;
use pregrasp_planner::replan::ResumeError;
use pregrasp_planner::resume::{replan_remaining, Resume};

fn chair() -> (Scene, Mesh, PlanFile) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/chair_side.toml");
    let scene = Scene::load(&path).unwrap();
    let mesh = load_mesh(&scene.object.mesh_path, scene.object.scale)
        .unwrap()
        .mesh;
    let options = PlanOptions::default();
    let file = pregrasp_planner::plan_scene(&scene, &mesh, &options, &|_| {}, &|| {})
        .unwrap()
        .file;
    assert_eq!(file.status, PlanStatus::Planned);
    (scene, mesh, file)
}

#[test]
fn resuming_at_the_planned_pose_gives_the_planned_motions() {
    let (scene, mesh, nominal) = chair();
    let goal = nominal.plans[0].object_goal_pose.to_isometry();
    for from in [Resume::Mas1, Resume::Sup2] {
        let again = replan_remaining(&scene, &mesh, &nominal, 0, goal, from).unwrap();
        let file = again.report.file;
        assert_eq!(
            file.status,
            PlanStatus::Planned,
            "{from:?}: {:?}",
            file.reason
        );
        // The segments that ran are kept; the ones planned again end where the nominal ones
        // do (the pose read back from the file differs from the planner's by round-off, so
        // the lines may be sampled differently).
        let (nominal_segments, segments) = (&nominal.plans[0].segments, &file.plans[0].segments);
        assert_eq!(segments[..2], nominal_segments[..2]);
        if from == Resume::Sup2 {
            assert_eq!(segments[2], nominal_segments[2]);
        }
        for (a, b) in nominal_segments.iter().zip(segments) {
            let (qa, qb) = (a.points.last().unwrap().q, b.points.last().unwrap().q);
            let off = (0..6).map(|j| (qa[j] - qb[j]).abs()).fold(0.0, f64::max);
            assert!(off < 1e-9, "{from:?}: {} ends {off} rad away", a.name);
        }
        assert_eq!(file.object, nominal.object);
        assert_eq!(file.grasps, nominal.grasps);
        assert!(check_plan(&file, &mesh).is_valid());
    }
}

#[test]
fn a_part_measured_millimetres_off_is_planned_where_it_is_and_checked() {
    let (scene, mesh, nominal) = chair();
    let goal = nominal.plans[0].object_goal_pose.to_isometry();
    for (dx, dy) in [(0.003, 0.0), (0.0, -0.003), (0.002, 0.002)] {
        let measured =
            Isometry3::from_parts(Translation3::new(dx, dy, 0.0), Default::default()) * goal;
        for from in [Resume::Mas1, Resume::Sup2] {
            let file = replan_remaining(&scene, &mesh, &nominal, 0, measured, from)
                .unwrap()
                .report
                .file;
            assert_eq!(
                file.status,
                PlanStatus::Planned,
                "{from:?} {dx} {dy}: {:?}",
                file.reason
            );
            let plan = &file.plans[0];
            let d = plan.object_goal_pose.to_isometry().inverse() * measured;
            assert!(
                d.translation.vector.norm() < 1e-12,
                "the goal is the measured pose"
            );
            // sup1 and rot are the ones that ran; the grasp G_s is the one the pinch holds.
            assert_eq!(plan.segments[0], nominal.plans[0].segments[0]);
            for (a, b) in plan.segments[1]
                .points
                .iter()
                .zip(&nominal.plans[0].segments[1].points)
            {
                assert_eq!((a.t, a.q), (b.t, b.q));
            }
            if from == Resume::Sup2 {
                assert_eq!(plan.segments[2], nominal.plans[0].segments[2]);
            }
            let check = check_plan(&file, &mesh);
            assert!(check.is_valid(), "{from:?} {dx} {dy}: {:?}", check.rules);
        }
    }
}

#[test]
fn a_part_the_executed_rotation_cannot_explain_is_refused() {
    let (scene, mesh, nominal) = chair();
    let goal = nominal.plans[0].object_goal_pose.to_isometry();
    let up = Isometry3::translation(0.0, 0.0, 0.03) * goal;
    let Err(err) = replan_remaining(&scene, &mesh, &nominal, 0, up, Resume::Mas1) else {
        panic!("a part 30 mm above where the pinch put it was planned");
    };
    assert!(matches!(err, ResumeError::Measurement { .. }), "{err}");
    assert!(err.to_string().contains("above the support"), "{err}");
}
