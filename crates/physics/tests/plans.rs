//! The check on real plans: the built-in examples planned by the pipeline.
//!
//! Run with `--nocapture` to see the numbers `docs/physics.md` quotes.

use pregrasp_io::plan_file::SegmentName;
use std::path::Path;

use pregrasp_geometry::Mesh;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;
use pregrasp_model::PlanSet;
use pregrasp_physics::{
    analyse_plan, screen_plan, GripWarning, MassSource, PartMass, PhysicsSettings, PlanPhysics,
    StateStatus, Verdict,
};
use pregrasp_planner::hold::physics_json;
use pregrasp_planner::pipeline::{plan, PlanOptions};

fn planned(name: &str) -> (PlanFile, Mesh) {
    let ex = pregrasp_examples::by_name(name).expect("built-in example");
    let scene = Scene::from_str(&ex.scene_toml, Path::new(&format!("examples/{name}.toml")))
        .expect("example scene parses");
    let file = plan(
        &scene,
        &ex.mesh,
        &PlanOptions {
            max_plans: 1,
            ..PlanOptions::default()
        },
        &|_| {},
        &|| {},
    )
    .unwrap()
    .file;
    assert!(!file.plans.is_empty(), "{name}: planned");
    (file, ex.mesh)
}

/// Example `name` planned with `[physics] reject = false` (a plan is kept whatever the grip
/// check says): the file, the index in it of candidate `id`'s plan, and the mesh.
fn kept_plan(name: &str, id: usize) -> (PlanFile, usize, Mesh) {
    let ex = pregrasp_examples::by_name(name).expect("built-in example");
    let text = format!("{}\n[physics]\nreject = false\n", ex.scene_toml);
    let scene = Scene::from_str(&text, Path::new(&format!("examples/{name}.toml"))).unwrap();
    let options = PlanOptions {
        max_plans: 5,
        ..PlanOptions::default()
    };
    let file = plan(&scene, &ex.mesh, &options, &|_| {}, &|| {})
        .unwrap()
        .file;
    let k = file
        .plans
        .iter()
        .position(|p| p.candidate == id)
        .expect("kept");
    (file, k, ex.mesh)
}

/// The file as the plan model (as every reader of a plan file gets it).
fn model(file: &PlanFile) -> PlanSet {
    file.to_model().expect("the planner's robots")
}

fn check(file: &PlanFile, mesh: &Mesh, settings: &PhysicsSettings) -> PlanPhysics {
    let part = PartMass::resolve(file.object.mass, mesh, None, settings.density).unwrap();
    analyse_plan(&model(file), 0, &part, settings).unwrap()
}

fn show(name: &str, r: &PlanPhysics) {
    let w = &r.states[r.worst];
    println!(
        "{name}: mass {:.2} kg ({}), grip width {:.1} mm, {} states; worst θ {:.1}°: N_min {:.2} N, \
         support n {:.2} N t {:.2} N (use {:.2}); N_max {:.2} N → set {:.1} N, pads use {:.2}; {}",
        r.part.mass,
        r.part.source,
        r.grip_width * 1e3,
        r.states.len(),
        w.theta_deg,
        w.n_min.unwrap_or(f64::NAN),
        w.support_normal.unwrap_or(f64::NAN),
        w.support_tangential.unwrap_or(f64::NAN),
        w.support_friction_use.unwrap_or(f64::NAN),
        r.n_max.unwrap_or(f64::NAN),
        r.recommended.unwrap_or(f64::NAN),
        w.pad_friction_use.unwrap_or(f64::NAN),
        r.verdict.describe(),
    );
    for s in r.states.iter().filter(|s| s.point.is_some()) {
        println!(
            "  θ {:6.2}°  N_min {:7.3} N  support n {:6.2} t {:6.3} use {:.3}  contacts {}",
            s.theta_deg,
            s.n_min.unwrap_or(f64::NAN),
            s.support_normal.unwrap_or(f64::NAN),
            s.support_tangential.unwrap_or(f64::NAN),
            s.support_friction_use.unwrap_or(f64::NAN),
            s.support_contacts
        );
    }
    for w in &r.warnings {
        println!("  warning: {w}");
    }
}

/// Every example's plan holds with the default friction, both support contacts touch in every
/// state, and the recommended force lies in the gripper's range.
#[test]
fn example_plans_hold() {
    let settings = PhysicsSettings::default();
    for name in pregrasp_examples::NAMES {
        let (file, mesh) = planned(name);
        let r = check(&file, &mesh, &settings);
        show(name, &r);
        let rot_points = file.plans[0]
            .segments
            .iter()
            .find(|s| s.name == SegmentName::Rot)
            .unwrap()
            .points
            .len();
        // Interpolated states only where the worst can hide, and they find the same worst as
        // interpolating everywhere.
        let all = check(
            &file,
            &mesh,
            &PhysicsSettings {
                refine_all: true,
                ..settings
            },
        );
        assert_eq!(
            all.states.len(),
            rot_points + (rot_points - 1) * settings.substeps
        );
        assert!(r.states.len() >= rot_points && r.states.len() < all.states.len());
        assert_eq!(r.verdict, all.verdict, "{name}");
        assert_eq!(r.n_max, all.n_max, "{name}");
        assert_eq!(r.states[r.worst].t, all.states[all.worst].t, "{name}");
        // The planner wrote the same numbers into the plan file, and the carry check's verdict
        // on the power grasps beside them (all three carry: the shelf's, which cage their bars
        // at the scene's depth, are held at the fingertips).
        let mut written = file.plans[0].physics.clone().unwrap();
        let carry = written
            .warnings
            .iter()
            .filter(|w| w.starts_with("carry: "))
            .count();
        written.warnings.retain(|w| !w.starts_with("carry: "));
        assert_eq!(carry, 0, "{name}");
        assert_eq!(written, physics_json(&r), "{name}");
        assert!(r.states.iter().all(|s| s.support_contacts == 2), "{name}");
        assert_eq!(r.verdict, Verdict::Holds, "{name}");
        assert!(r.warnings.is_empty(), "{name}: {:?}", r.warnings);
        let rec = r.recommended.unwrap();
        assert!((20.0..=235.0).contains(&rec));
        assert!(rec >= settings.safety_factor * r.n_max.unwrap() - 1e-9 || rec == 20.0);
        // The part is heavier than nothing: the support carries weight in every state.
        assert!(r.states.iter().all(|s| s.support_normal.unwrap() > 0.0));
    }
}

/// (d) The plan claims an axis 20 mm above the part's real edge: at no state is an axis
/// endpoint on the support, so the pads alone would have to hold the part. It is flagged
/// (a warning, and a verdict other than "holds").
#[test]
fn an_axis_lifted_off_the_edge_is_flagged() {
    let settings = PhysicsSettings::default();
    let (mut file, mesh) = planned("chair_side");
    let honest = check(&file, &mesh, &settings);
    let id = file.plans[0].candidate;
    let cand = file.candidates.iter_mut().find(|c| c.id == id).unwrap();
    for p in cand.axis.iter_mut() {
        p[2] += 0.020;
    }
    let lifted = check(&file, &mesh, &settings);
    show("chair_side, axis lifted 20 mm", &lifted);
    assert!(lifted.states.iter().all(|s| s.support_contacts == 0));
    assert!(lifted.flagged());
    assert!(matches!(
        lifted.warnings[0],
        GripWarning::NoSupportContact { .. }
    ));
    assert!(lifted.warnings[0].to_string().contains("pads alone"));
    assert_ne!(lifted.verdict, Verdict::Holds);
    // Where the pads alone can hold at all, it takes far more force than with the support.
    for (a, b) in honest.states.iter().zip(&lifted.states) {
        if let (StateStatus::Held, Some(nb)) = (b.status, b.n_min) {
            assert!(nb > a.n_min.unwrap());
        }
    }
}

/// Less support friction never needs less grip; a heavier part needs proportionally more.
#[test]
fn grip_force_grows_with_weight_and_less_support_friction() {
    let (file, mesh) = planned("stool_side");
    let base = PhysicsSettings::default();
    let part = PartMass::resolve(file.object.mass, &mesh, None, base.density).unwrap();
    let r0 = analyse_plan(&model(&file), 0, &part, &base).unwrap();
    let heavy = PartMass {
        mass: 2.0 * part.mass,
        ..part.clone()
    };
    let r1 = analyse_plan(&model(&file), 0, &heavy, &base).unwrap();
    for (a, b) in r0.states.iter().zip(&r1.states) {
        let (na, nb) = (a.n_min.unwrap(), b.n_min.unwrap());
        assert!((nb - 2.0 * na).abs() <= 1e-6 * nb.max(1.0), "{na} vs {nb}");
    }
    let slippery = PhysicsSettings {
        mu_support: 0.1,
        ..base
    };
    let r2 = analyse_plan(&model(&file), 0, &part, &slippery).unwrap();
    for (a, b) in r0.states.iter().zip(&r2.states) {
        if let Some(nb) = b.n_min {
            assert!(nb >= a.n_min.unwrap() * (1.0 - 1e-6) - 1e-9);
        }
    }
}

/// A plan file without `object.mass` falls back on 700 kg/m³ × the mesh's volume, and says so.
#[test]
fn mass_falls_back_on_density() {
    let (mut file, mesh) = planned("shelf_side");
    let given = file.object.mass.unwrap();
    file.object.mass = None;
    let part = PartMass::resolve(file.object.mass, &mesh, None, 700.0).unwrap();
    assert!(matches!(part.source, MassSource::Density { density, .. } if density == 700.0));
    assert!(part.source.to_string().contains("700 kg/m³ × mesh volume"));
    assert!((part.mass - 700.0 * part.volume).abs() < 1e-12);
    // The example scenes give wood's mass from the same outline: the same order.
    assert!(part.mass > 0.3 * given && part.mass < 3.0 * given);
    let forced = PartMass::resolve(file.object.mass, &mesh, Some((5.0, "--mass")), 700.0).unwrap();
    assert_eq!(forced.mass, 5.0);
}

/// The plan turns the part about a line 20 mm above its real edge (the axis it claims is that
/// line): the edge resting on the table is dragged over it, and the plan is flagged as sliding.
#[test]
fn a_rotation_about_a_line_20_mm_above_the_edge_slides() {
    use nalgebra::{Isometry3, Translation3, Vector3};
    use pregrasp_io::plan_file::PoseJson;

    let settings = PhysicsSettings::default();
    let (mut file, mesh) = planned("chair_side");
    let id = file.plans[0].candidate;
    let cand = file.candidates.iter_mut().find(|c| c.id == id).unwrap();
    for p in cand.axis.iter_mut() {
        p[2] += 0.020;
    }
    let pivot = Vector3::from(cand.axis[0]);
    let p_init = file.object.initial_pose.to_isometry();
    let rot = file.plans[0]
        .segments
        .iter_mut()
        .find(|s| s.name == SegmentName::Rot)
        .unwrap();
    for point in &mut rot.points {
        let pose = point.object_pose.as_ref().unwrap().to_isometry();
        // The same rotation as planned, about the lifted line instead of the edge.
        let turn = (pose * p_init.inverse()).rotation;
        let about = Translation3::from(pivot)
            * Isometry3::from_parts(Translation3::identity(), turn)
            * Translation3::from(-pivot);
        point.object_pose = Some(PoseJson::from(&(about * p_init)));
    }
    let lifted = check(&file, &mesh, &settings);
    show("chair_side, turned 20 mm above the edge", &lifted);
    assert_eq!(lifted.verdict, Verdict::SlidesAtSupport);
    assert!(
        lifted
            .warnings
            .iter()
            .any(|w| matches!(w, GripWarning::EdgeSlides { .. })),
        "{:?}",
        lifted.warnings
    );
    // The honest plan: the edge stays put, no such warning.
    let (honest_file, _) = planned("chair_side");
    let honest = check(&honest_file, &mesh, &settings);
    assert_eq!(honest.verdict, Verdict::Holds);
    assert!(!honest
        .warnings
        .iter()
        .any(|w| matches!(w, GripWarning::EdgeSlides { .. })));
}

/// The screening the planner uses when a failure means rejection: a rotation that holds gets
/// the whole report; one that does not stops at its first failing point, which is the report's
/// worst state, with the answers the whole analysis gives up to it.
#[test]
fn screening_stops_at_the_first_failing_point() {
    let (file, mesh) = planned("stool_side");
    let base = PhysicsSettings::default();
    let part = PartMass::resolve(file.object.mass, &mesh, None, base.density).unwrap();
    let whole = analyse_plan(&model(&file), 0, &part, &base).unwrap();
    assert_eq!(whole.verdict, Verdict::Holds);
    assert_eq!(screen_plan(&model(&file), 0, &part, &base).unwrap(), whole);

    // The stool's candidate 2 with point pads (its pad contact patches left out, so they
    // resist no twist) slides at the support (kept here).
    let (mut kept, k, _) = kept_plan("stool_side", 2);
    for seg in &mut kept.plans[k].segments {
        seg.pad_contact = None;
    }
    let (file, slippery) = (&kept, base);
    let whole = analyse_plan(&model(file), k, &part, &slippery).unwrap();
    assert_eq!(whole.verdict, Verdict::SlidesAtSupport);
    let points: Vec<_> = whole.states.iter().filter(|s| s.point.is_some()).collect();
    let first = points
        .iter()
        .position(|s| s.status != StateStatus::Held)
        .expect("a failing point");
    let screened = screen_plan(&model(file), k, &part, &slippery).unwrap();
    assert!(screened.stopped_at_failure && !whole.stopped_at_failure);
    assert_eq!(screened.states.len(), first + 1);
    assert_eq!(screened.worst, first);
    for (a, b) in screened.states.iter().zip(&points) {
        assert_eq!((a.point, a.status, a.n_min), (b.point, b.status, b.n_min));
    }
    assert_ne!(screened.verdict, Verdict::Holds);
    let why = screened.rejection().expect("refused");
    assert!(why.to_string().contains("from θ ="), "{why}");
}

/// A screening also stops at the first point whose grip, with the safety factor, is more than
/// the gripper's most: the rotation is refused from there whatever follows, as the whole
/// analysis refuses it.
#[test]
fn screening_stops_where_the_grip_needs_more_than_the_gripper_has() {
    let (file, mesh) = planned("stool_side");
    let base = PhysicsSettings::default();
    let part = PartMass::resolve(file.object.mass, &mesh, None, base.density).unwrap();
    let whole = analyse_plan(&model(&file), 0, &part, &base).unwrap();
    // A gripper whose most is just short of what the first point needs (the examples' rotations
    // need the most at their start).
    let need = |s: &pregrasp_physics::StateReport| base.safety_factor * s.n_min.unwrap();
    let first = need(&whole.states[0]);
    let weak = PhysicsSettings {
        grip_force: (base.grip_force.0.min(first / 2.0), first * 0.95),
        ..base
    };
    let whole = analyse_plan(&model(&file), 0, &part, &weak).unwrap();
    assert_eq!(whole.verdict, Verdict::CannotHold);
    assert!(whole.states.len() > 10);
    let points: Vec<_> = whole.states.iter().filter(|s| s.point.is_some()).collect();
    let over = points
        .iter()
        .position(|s| need(s) > weak.grip_force.1)
        .expect("a point over the most");
    let screened = screen_plan(&model(&file), 0, &part, &weak).unwrap();
    assert!(screened.stopped_at_failure);
    assert_eq!(screened.states.len(), over + 1);
    assert_eq!(screened.worst, over);
    assert_eq!(screened.verdict, Verdict::CannotHold);
    assert_eq!(screened.states[over].n_min, points[over].n_min);
    let why = screened.rejection().expect("refused").to_string();
    assert!(
        why.contains("from θ =") && why.contains("more than"),
        "{why}"
    );
}

/// A rotation that hangs on the pads' twist is refused for it after one state: the twist arm
/// is geometry over all the states, the same number the whole analysis finds.
#[test]
fn screening_refuses_a_rotation_on_the_twist_after_one_state() {
    // The chair side's candidate 1 hangs its weight 107.6 mm beyond the pinch (kept here).
    let (file, k, mesh) = kept_plan("chair_side", 1);
    let base = PhysicsSettings::default();
    let part = PartMass::resolve(file.object.mass, &mesh, None, base.density).unwrap();
    let whole = analyse_plan(&model(&file), k, &part, &base).unwrap();
    assert_eq!(whole.verdict, Verdict::LiftsOffSupport);
    assert!(whole.states.len() > 10);
    let screened = screen_plan(&model(&file), k, &part, &base).unwrap();
    assert_eq!(screened.states.len(), 1);
    assert_eq!(screened.verdict, Verdict::LiftsOffSupport);
    assert_eq!(screened.twist_arm, whole.twist_arm);
    assert_eq!(screened.rejection(), whole.rejection());
}

/// The report lists each closing with the force the plan gives it: `sup1` the pinch's recommended
/// force (equal to this check's with the same settings), the power grasps the 2F-85's largest
/// (the planner's carry check); a force the plan gives `mas1` is reported as given.
#[test]
fn the_report_gives_each_closings_grip_force() {
    let (mut file, mesh) = planned("chair_side");
    let r = check(&file, &mesh, &PhysicsSettings::default());
    let words: Vec<(String, Option<f64>)> = r
        .closings
        .iter()
        .map(|c| (c.segment.to_string(), c.grip_force))
        .collect();
    let rec = r.recommended.expect("the chair's pinch holds");
    assert_eq!(
        words,
        [
            ("sup1".to_string(), Some(rec)),
            ("mas1".to_string(), Some(235.0)),
            ("sup2".to_string(), Some(235.0))
        ]
    );
    let sup = model(&file).plans[0].roles.supportive;
    assert_eq!(r.closings[0].arm, sup);
    let mas1 = file.plans[0]
        .segments
        .iter_mut()
        .find(|s| s.name == SegmentName::Mas1)
        .unwrap();
    mas1.grip_force = Some(120.0);
    let r = check(&file, &mesh, &PhysicsSettings::default());
    assert_eq!(r.closings[1].grip_force, Some(120.0));
    let json = serde_json::to_value(&r).unwrap();
    assert_eq!(json["closings"][1]["segment"], "mas1");
    assert_eq!(json["closings"][1]["grip_force"], 120.0);
}
