//! A measured pose brought onto the support ([`settle`]): a camera's few millimetres and a
//! degree or two of roll and pitch are taken back out; more than the tolerance is refused.

use std::path::Path;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pregrasp_io::scene::Scene;
use pregrasp_planner::settle::{settle, SettleError, SettleTolerance};

fn chair() -> (Scene, pregrasp_examples::Mesh) {
    let ex = pregrasp_examples::by_name("chair_side").unwrap();
    let scene = Scene::from_str(&ex.scene_toml, Path::new("chair_side.toml")).unwrap();
    (scene, ex.mesh)
}

/// `pose` with the part tilted by `roll`, `pitch` (degrees) about its centre (the mean of its
/// vertices) and raised by `dz`: a camera's errors.
fn measured(
    mesh: &pregrasp_examples::Mesh,
    pose: &Isometry3<f64>,
    dz: f64,
    roll: f64,
    pitch: f64,
) -> Isometry3<f64> {
    let centre = mesh
        .vertices
        .iter()
        .fold(Vector3::zeros(), |s, v| s + v.coords)
        / mesh.vertices.len() as f64;
    let c = pose * nalgebra::Point3::from(centre);
    let tilt = UnitQuaternion::from_euler_angles(roll.to_radians(), pitch.to_radians(), 0.0);
    let about = Isometry3::from_parts(Translation3::from(c.coords), tilt)
        * Isometry3::from_parts(Translation3::from(-c.coords), UnitQuaternion::identity());
    Isometry3::from_parts(Translation3::new(0.0, 0.0, dz), UnitQuaternion::identity())
        * about
        * pose
}

#[test]
fn a_noisy_measurement_settles_back_onto_the_table() {
    let (scene, mesh) = chair();
    let truth = scene.object.pose;
    let lowest = |p: &Isometry3<f64>| {
        mesh.vertices
            .iter()
            .map(|v| (p * v).z)
            .fold(f64::INFINITY, f64::min)
    };
    assert!(lowest(&truth).abs() < 1e-9, "the example lies on the table");
    for (dz, roll, pitch) in [
        (0.001, 0.0, 0.0),
        (0.003, 1.5, -1.0),
        (-0.002, -0.8, 2.0),
        (0.005, 2.0, 2.0),
    ] {
        let m = measured(&mesh, &truth, dz, roll, pitch);
        let s = settle(&mesh, &m, scene.support_height, &SettleTolerance::default()).unwrap();
        assert!(lowest(&s.pose).abs() < 1e-9, "on the support");
        // The bottom face down again: the settled pose is the true one up to the small change
        // of heading and position a tilt about the centroid leaves.
        let angle = s.pose.rotation.angle_to(&truth.rotation);
        let shift = (s.pose.translation.vector - truth.translation.vector).norm();
        assert!(angle < 0.05f64.to_radians(), "{dz} {roll} {pitch}: {angle}");
        assert!(shift < 5e-4, "{dz} {roll} {pitch}: {shift}");
        let expected_turn = (roll.powi(2) + pitch.powi(2)).sqrt().to_radians();
        assert!(
            (s.turned - expected_turn).abs() < 1e-3,
            "{} vs {expected_turn}",
            s.turned
        );
    }
    // Exactly on the table: nothing moves.
    let s = settle(
        &mesh,
        &truth,
        scene.support_height,
        &SettleTolerance::default(),
    )
    .unwrap();
    assert!(s.moved < 1e-12 && s.turned < 1e-12);
}

#[test]
fn a_measurement_far_from_any_resting_pose_is_refused() {
    let (scene, mesh) = chair();
    let tolerance = SettleTolerance::default();
    for (dz, roll, pitch) in [(0.02, 0.0, 0.0), (0.0, 8.0, 0.0), (-0.015, 0.0, 0.0)] {
        let m = measured(&mesh, &scene.object.pose, dz, roll, pitch);
        match settle(&mesh, &m, scene.support_height, &tolerance) {
            Err(e @ SettleError::TooFar { .. }) => {
                assert!(e.to_string().contains("check the measurement"), "{e}")
            }
            other => panic!("{dz} {roll}: {other:?}"),
        }
    }
}

/// Issue 35's cell loop: the plan's own pose as a camera reports it — ±3 mm in z, ±1° of roll
/// and pitch — settles, replans with the plan's axis, and the new plan passes the check.
#[test]
fn a_noisy_measurement_of_the_plans_own_pose_replans_and_checks() {
    use pregrasp_io::plan_file::PlanStatus;
    use pregrasp_planner::check::check_plan;
    use pregrasp_planner::pipeline::{plan, PlanOptions};
    use pregrasp_planner::replan::replan;

    let (scene, mesh) = chair();
    let nominal = plan(&scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file;
    assert_eq!(nominal.status, PlanStatus::Planned, "{:?}", nominal.reason);
    let tolerance = SettleTolerance::default();
    for (dz, roll, pitch) in [(0.003, 1.0, -1.0), (-0.003, -1.0, 1.0), (0.003, -1.0, -1.0)] {
        let measured_pose = measured(&mesh, &scene.object.pose, dz, roll, pitch);
        let settled = settle(&mesh, &measured_pose, scene.support_height, &tolerance).unwrap();
        let again = replan(
            &scene,
            &mesh,
            &nominal,
            0,
            settled.pose,
            &PlanOptions::default(),
        )
        .unwrap();
        let file = again.report.file;
        assert_eq!(
            file.status,
            PlanStatus::Planned,
            "{dz} {roll} {pitch}: {:?}",
            file.reason
        );
        assert_eq!(
            file.plans[0].candidate, nominal.plans[0].candidate,
            "{dz} {roll} {pitch}: the plan's own axis"
        );
        let report = check_plan(&file, &mesh);
        assert!(report.is_valid(), "{dz} {roll} {pitch}: {:?}", report.rules);
    }
    // 50 mm in the air is not a measurement error: refused, naming the tolerance.
    let high = measured(&mesh, &scene.object.pose, 0.05, 0.0, 0.0);
    let e = settle(&mesh, &high, scene.support_height, &tolerance).unwrap_err();
    assert!(e.to_string().contains("at most 10.0 mm and 5.0°"), "{e}");
}
