//! Issue 15 in the planner: every plan carries the quasi-static check of its rotation, and a
//! rotation the pinch cannot hold is rejected with that reason (unless `[physics] reject =
//! false`).

use pregrasp_io::plan_file::{GripVerdict, Outcome, PlanStatus};
use std::path::Path;

use pregrasp_io::scene::Scene;
use pregrasp_physics::{MassError, PhysicsError};
use pregrasp_planner::check::check_plan;
use pregrasp_planner::pipeline::{plan, PlanOptions};

/// The chair example's scene with its `object.mass` replaced and `physics` appended.
fn chair(mass: Option<f64>, physics: &str) -> (Scene, pregrasp_geometry::Mesh) {
    let ex = pregrasp_examples::by_name("chair_side").unwrap();
    let mut text = ex.scene_toml.clone();
    if let Some(m) = mass {
        let line = text
            .lines()
            .find(|l| l.trim_start().starts_with("mass ="))
            .expect("the example gives a mass")
            .to_string();
        text = text.replace(&line, &format!("mass = {m}"));
    }
    text.push_str(physics);
    let scene = Scene::from_str(&text, Path::new("examples/chair_side.toml")).unwrap();
    (scene, ex.mesh)
}

fn run(scene: &Scene, mesh: &pregrasp_geometry::Mesh) -> pregrasp_io::plan_file::PlanFile {
    plan(scene, mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file
}

#[test]
fn every_plan_carries_its_grip_force() {
    let (scene, mesh) = chair(None, "");
    let file = run(&scene, &mesh);
    assert!(!file.plans.is_empty());
    for p in &file.plans {
        let phys = p.physics.as_ref().expect("physics object");
        assert_eq!(phys.verdict, GripVerdict::Holds);
        let (min, req, rec) = (
            phys.grip_force_min.unwrap(),
            phys.grip_force_required.unwrap(),
            phys.grip_force_recommended.unwrap(),
        );
        assert!(min > 0.0);
        assert!((req - phys.safety_factor * min).abs() < 1e-9);
        assert_eq!(rec, req.clamp(20.0, 235.0));
        assert!(phys.pad_friction_use.unwrap() <= 1.0 / phys.safety_factor + 1e-6);
        assert!(phys.support_friction_use.unwrap() <= 1.0 + 1e-6);
    }
}

/// A part 100× heavier than the chair side needs far more than the 2F-85's 235 N: every
/// candidate that planned is rejected for it, and the file says why.
#[test]
fn a_rotation_the_gripper_cannot_hold_is_rejected() {
    let (light, mesh) = chair(None, "");
    let light_file = run(&light, &mesh);
    let (heavy, _) = chair(Some(153.0), "");
    let file = run(&heavy, &mesh);
    assert_eq!(file.status, PlanStatus::NoPlan);
    let reason = file.reason.as_deref().unwrap();
    assert!(reason.contains("physics: cannot hold"), "{reason}");
    // Exactly the candidates that planned before, or were refused only because the part hangs
    // on the pads' twist (`physics::twist`, judged once the grip holds), are the ones rejected for
    // the grip now.
    let physics_rejected: Vec<usize> = file
        .candidates
        .iter()
        .filter(|c| {
            c.outcome
                .to_string()
                .starts_with("rejected: physics: cannot hold")
        })
        .map(|c| c.id)
        .collect();
    let planned_before: Vec<usize> = light_file
        .candidates
        .iter()
        .filter(|c| {
            let outcome = c.outcome.to_string();
            c.outcome == Outcome::Planned
                || outcome.contains("outranked")
                || outcome.starts_with("rejected: physics: lifts off the support")
        })
        .map(|c| c.id)
        .collect();
    assert_eq!(physics_rejected, planned_before);
    // No plan to re-check (a stage never entered has spent exactly nothing).
    assert_eq!(file.timing_ms["recheck"], 0.0);
    assert!(file.timing_ms["hold"] > 0.0);
    // On one thread the grip check comes before the transits: a rotation nobody can hold gets
    // none. (With threads to spare they may be computed beside it, and dropped unread: the
    // same file but its timings.)
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| run(&heavy, &mesh));
    assert_eq!(one.timing_ms["transit"], 0.0);
    assert_eq!(one.timing_ms["recheck"], 0.0);
    let (mut a, mut b) = (one, file.clone());
    a.timing_ms.clear();
    b.timing_ms.clear();
    assert_eq!(a, b);

    // With `reject = false` the same plans are kept, flagged.
    let (kept, _) = chair(Some(153.0), "[physics]\nreject = false\n");
    let file = run(&kept, &mesh);
    assert_eq!(file.status, PlanStatus::Planned);
    for p in &file.plans {
        let phys = p.physics.as_ref().unwrap();
        assert_eq!(phys.verdict, GripVerdict::CannotHold);
        assert_eq!(phys.grip_force_recommended, None);
        assert!(phys.grip_force_required.unwrap() > 235.0);
    }
    assert!(check_plan(&file, &mesh).is_valid());
}

/// The friction the scene gives is the friction the check uses: more pad friction, less grip.
#[test]
fn scene_friction_reaches_the_check() {
    let (scene, mesh) = chair(None, "");
    let base = run(&scene, &mesh);
    let (grippy, _) = chair(None, "[physics]\nmu_pad = 1.6\nsafety_factor = 3\n");
    let file = run(&grippy, &mesh);
    let (a, b) = (
        base.plans[0].physics.as_ref().unwrap(),
        file.plans[0].physics.as_ref().unwrap(),
    );
    assert_eq!((b.mu_pad, b.safety_factor), (1.6, 3.0));
    assert!(b.grip_force_min.unwrap() < a.grip_force_min.unwrap());
    // The motions do not depend on the physics settings.
    assert_eq!(base.plans[0].segments, file.plans[0].segments);
}

/// A real CAD mesh is often not closed: then the part has no known centre of mass, the plans
/// carry no `physics` object, nothing is rejected for it, and the report says why.
#[test]
fn an_open_mesh_plans_without_the_grip_check() {
    let (scene, mut mesh) = chair(None, "");
    let closed = run(&scene, &mesh);
    mesh.triangles.pop();
    let report = plan(&scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {}).unwrap();
    let note = report.physics_note.as_ref().expect("the report says why");
    assert!(
        matches!(
            note.0,
            PhysicsError::Mass(MassError::NotClosed { open }) if open > 0
        ),
        "{note}"
    );
    assert!(note.to_string().contains("not a closed surface"), "{note}");
    let file = report.file;
    assert_eq!(file.status, PlanStatus::Planned);
    assert!(file.plans.iter().all(|p| p.physics.is_none()));
    // Nothing refused for the physics: the closed mesh's plans and the candidates its check
    // refused (the chair's second hangs on the pads' twist).
    let refused = closed
        .candidates
        .iter()
        .filter(|c| c.outcome.to_string().starts_with("rejected: physics"))
        .count();
    assert_eq!((closed.plans.len(), refused), (1, 1));
    assert_eq!(file.plans.len(), closed.plans.len() + refused);
}
