//! Power grasps held at the fingertips first (issue 48, `seat::SeatRule::PLANNER`): a 2F-85
//! power grasp whose pads pinch its bar at the fingertips is held there, on the bar's
//! mid-plane; where that pinch cannot carry the part, the plan is made with the wraps. The
//! scene's `[planner] power_hold` chooses otherwise. What the replay says of each hold is
//! `carry_truth.rs`'s.

mod common;

use std::path::Path;

use common::scenes::{example_files, generated_files};
use nalgebra::Translation3;
use pregrasp_collision::{close_on_part, ObjectGeometry};
use pregrasp_examples::parts::families::Family;
use pregrasp_io::scene::{PowerHold, Scene};
use pregrasp_planner::context::arm_models;
use pregrasp_planner::pipeline::PlanOptions;
use pregrasp_planner::seat::{
    bar_depth, bar_mid_plane, seat_power_grasps_by, SeatRule, CENTRE_REACH, FINGERTIP_STEP,
    FINGERTIP_TRIES,
};
use pregrasp_robot::ClosingKind;

fn plan(scene: &Scene, mesh: &pregrasp_geometry::Mesh) -> pregrasp_io::plan_file::PlanFile {
    pregrasp_planner::plan_scene(scene, mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file
}

/// How arm `k`'s fingers end when its power grasp is held at the fingertips (the precision
/// point) and moved `x` across its bar.
fn kinds_at_fingertips(
    scene: &Scene,
    part: &ObjectGeometry,
    arms: &[pregrasp_collision::ArmModel; 2],
    k: usize,
    x: f64,
) -> [ClosingKind; 2] {
    let gripper = &arms[k].gripper;
    let out = scene.robots[k].power_point_z - scene.robots[k].precision_point_z;
    let held = scene.grasps.power[k] * Translation3::new(x, 0.0, out);
    close_on_part(part, gripper, &(held * gripper.power_point().inverse()))
        .unwrap()
        .kinds
}

#[test]
fn bars_the_pads_pinch_are_held_at_the_fingertips_though_the_wrap_squeezes() {
    // The stool side's first grasp: the wrap squeezes its 25 mm leg 4 mm below the palm (the
    // wraps seat it); the planner holds it at the fingertips, where the pads pinch it.
    let (scene, mesh) = example_files("stool_side");
    let part = ObjectGeometry::new(&mesh).unwrap();
    let arms = arm_models(&scene).unwrap();
    let power = &scene.grasps.power;
    let wraps = seat_power_grasps_by(&part, &arms, power, [0.0; 2], SeatRule::WRAPS);
    let first = seat_power_grasps_by(&part, &arms, power, [0.0; 2], SeatRule::PLANNER);
    assert!(wraps.moved[0] > 0.0, "{:?}", wraps.moved);
    for (k, arm) in arms.iter().enumerate() {
        let point = arm.gripper.power_point();
        let to_tips = scene.robots[k].precision_point_z - scene.robots[k].power_point_z;
        let out = -first.moved[k];
        let nearest = to_tips - FINGERTIP_STEP * (FINGERTIP_TRIES - 1) as f64;
        assert!(
            out >= nearest - 1e-5 && out <= to_tips + 1e-9,
            "power[{k}] {out} m out"
        );
        let held = close_on_part(&part, &arm.gripper, &(first.power[k] * point.inverse()))
            .unwrap()
            .kinds;
        assert_eq!(held, [ClosingKind::Pinch; 2], "power[{k}]");
    }
    // The plan is made with them: both out, the first also moved across onto its leg's
    // mid-plane.
    let file = plan(&scene, &mesh);
    assert_eq!(file.grasps.seated, None);
    assert_eq!(file.grasps.fingertips, Some(first.moved.map(|m| -m)));
    let across = file.grasps.centred.unwrap();
    assert!(
        across[0] != 0.0 && across[0].abs() <= CENTRE_REACH,
        "{across:?}"
    );
}

#[test]
fn a_grasp_held_at_the_fingertips_lies_on_its_bars_mid_plane() {
    // Generated h_frame #1: the scene's master grasp lies 0.03 mm off its 24 mm bar's
    // mid-plane (the scene file's 0.1 mm rounding). At the fingertips the pad that meets the
    // bar first stops both fingers (their drivers turn together): off the mid-plane our closing
    // ends on one side, on it both pads pinch.
    let (scene, mesh) = generated_files(Family::HFrame, 1);
    let part = ObjectGeometry::new(&mesh).unwrap();
    let arms = arm_models(&scene).unwrap();
    let k = 1;
    let grasp = scene.grasps.power[k];
    let across = bar_mid_plane(&part, &grasp).unwrap();
    assert!(across.abs() > 1e-6 && across.abs() < 1e-4, "{across}");
    let kinds = |x: f64| kinds_at_fingertips(&scene, &part, &arms, k, x);
    assert!(
        kinds(0.0).contains(&ClosingKind::Closed),
        "{:?}",
        kinds(0.0)
    );
    assert_eq!(kinds(across), [ClosingKind::Pinch; 2]);
    // The plan file says how far each grasp moved across, to the micrometre.
    let file = plan(&scene, &mesh);
    let centred = file.grasps.centred.unwrap();
    assert!((centred[k] - across).abs() < 1e-6, "{centred:?} {across}");
}

#[test]
fn a_tapered_legs_mid_plane_is_where_both_pads_meet_it() {
    // Generated chamfered #11: the legs taper (the inner face slopes about 2° along the leg),
    // so a pad meets that face first at its edge. Centred between the faces at the grasp's
    // origin alone, the pad on the sloping face stops both fingers and the other closes on
    // nothing; centred between the faces each pad meets first over its width, both pinch.
    let (scene, mesh) = generated_files(Family::Chamfered, 11);
    let part = ObjectGeometry::new(&mesh).unwrap();
    let arms = arm_models(&scene).unwrap();
    for k in 0..2 {
        let grasp = scene.grasps.power[k];
        // The faces the rays through the origin meet, as bar_mid_plane read them before.
        let half = pregrasp_robot::FingerKinematics::robotiq_2f85().stroke() / 2.0;
        let face = |side: f64| {
            let start = grasp * nalgebra::Point3::new(side * half, 0.0, 0.0);
            let towards = grasp.rotation * nalgebra::Vector3::new(-side, 0.0, 0.0);
            let ray = parry3d_f64::query::Ray::new(start, towards);
            let hit =
                parry3d_f64::query::RayCast::cast_local_ray(part.trimesh(), &ray, half, false);
            side * (half - hit.unwrap())
        };
        let at_origin = 0.5 * (face(1.0) + face(-1.0));
        let across = bar_mid_plane(&part, &grasp).unwrap();
        assert!(
            (across - at_origin).abs() > 1e-4,
            "power[{k}] {across} {at_origin}"
        );
        assert!(across.abs() <= CENTRE_REACH, "power[{k}] {across}");
        let kinds = |x: f64| kinds_at_fingertips(&scene, &part, &arms, k, x);
        assert!(
            kinds(at_origin).contains(&ClosingKind::Closed),
            "power[{k}] {:?}",
            kinds(at_origin)
        );
        assert_eq!(kinds(across), [ClosingKind::Pinch; 2], "power[{k}]");
    }
}

#[test]
fn the_wraps_carry_where_the_pinch_at_the_fingertips_cannot() {
    // The chair side held at both fingertips: no grip force holds its weight's moment about the
    // line through the two pinches, and sliding them does not help; the planner makes the plan
    // with the wraps, which carry it.
    let (scene, mesh) = example_files("chair_side");
    let mut pinched = scene.clone();
    pinched.planner.power_hold = PowerHold::Fingertips;
    let file = plan(&pinched, &mesh);
    assert_eq!(file.planner.power_hold.as_deref(), Some("fingertips"));
    let warnings = file.plans[0].physics.as_ref().unwrap().warnings.clone();
    assert!(
        warnings
            .iter()
            .any(|w| w.starts_with("carry: no grip force")),
        "{warnings:?}"
    );
    let auto = plan(&scene, &mesh);
    assert_eq!(auto.planner.power_hold, None);
    assert!(auto.grasps.seated.is_some(), "{:?}", auto.grasps);
    assert!(auto
        .plans
        .iter()
        .all(|p| p.physics.as_ref().unwrap().warnings.is_empty()));
    // `"wraps"` asks for them from the start: the same grasps.
    let mut wrapped = scene.clone();
    wrapped.planner.power_hold = PowerHold::Wraps;
    let wraps = plan(&wrapped, &mesh);
    assert_eq!(wraps.grasps, auto.grasps);
    assert_eq!(wraps.planner.power_hold.as_deref(), Some("wraps"));
}

#[test]
fn an_unknown_power_hold_is_refused_by_name() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/stool_side.toml");
    let text = std::fs::read_to_string(root).unwrap();
    let text = text.replacen("[planner]", "[planner]\npower_hold = \"palm\"", 1);
    let err = Scene::from_str(&text, Path::new("stool_side.toml"))
        .unwrap_err()
        .to_string();
    assert!(err.contains("power_hold"), "{err}");
    assert!(
        err.contains("\"auto\", \"fingertips\" or \"wraps\""),
        "{err}"
    );
}

#[test]
fn where_the_wraps_get_no_path_the_pinch_slides_alone() {
    // Generated hand_hole #22 (36 mm stock): its pads' pinch at the fingertips needs 141 N by
    // the carry check (281 N with the safety factor, past the 2F-85's 235 N), so the planner
    // tries the wraps, which carry it but whose master's open hand touches the part on its
    // straight approach. Slid together the grasps leave a bar (one sits beside its hole's
    // end); slid one at a time the pinches carry the part: the plan is theirs, not flagged
    // (the whole-plan replay: rose 48.6 mm, tilted 1.0°; the pinch as given, flagged until
    // grasps slid one at a time, rose 47.6 mm, 1.7°).
    let (scene, mesh) = generated_files(Family::HandHole, 22);
    let file = plan(&scene, &mesh);
    assert!(!file.plans.is_empty(), "{:?}", file.reason);
    assert!(file.grasps.fingertips.is_some() && file.grasps.seated.is_none());
    let slid = file.grasps.slid.expect("slid one at a time");
    assert!(
        slid.iter().filter(|s| s.abs() < 1e-9).count() == 1,
        "{slid:?}"
    );
    let warnings = &file.plans[0].physics.as_ref().unwrap().warnings;
    assert!(warnings.is_empty(), "{warnings:?}");
    // The wraps alone get no plan, and said why.
    let mut wraps = scene.clone();
    wraps.planner.power_hold = PowerHold::Wraps;
    let file = plan(&wraps, &mesh);
    assert!(file.plans.is_empty());
    assert!(file.reason.unwrap().contains("μ_mas1: straight approach"));
}

#[test]
fn a_pinch_short_of_the_fingertips_with_the_palm_out_of_reach_moves_out_to_them() {
    // Generated frame #1 with each power point declared 6 mm short of the precision point (a
    // user's tool offset): the palm lies beyond the seating's reach and the pads pinch the
    // bar 6 mm nearer the palm than any fingertip depth, where the fingers curl (the replay
    // of u_frame_70__p272, its power point so: the master pushed the part 7.7 mm). The bar
    // moves out to the precision point.
    let (mut scene, mesh) = generated_files(Family::Frame, 1);
    for robot in &mut scene.robots {
        robot.power_point_z = robot.precision_point_z - 0.006;
    }
    let part = ObjectGeometry::new(&mesh).unwrap();
    let arms = arm_models(&scene).unwrap();
    // On their bars' mid-planes, where the closing at the scene's depth pinches with both pads
    // (0.01–0.06 mm off, it ends on one side, and is held at the fingertips for that).
    let power = scene.grasps.power.map(|g| {
        let across = bar_mid_plane(&part, &g).unwrap();
        g * Translation3::new(across, 0.0, 0.0)
    });
    for (k, arm) in arms.iter().enumerate() {
        let flange = power[k] * arm.gripper.power_point().inverse();
        let kinds = close_on_part(&part, &arm.gripper, &flange).unwrap().kinds;
        assert_eq!(
            kinds,
            [ClosingKind::Pinch; 2],
            "power[{k}] at the scene's depth"
        );
    }
    let held = seat_power_grasps_by(&part, &arms, &power, [0.0; 2], SeatRule::PLANNER);
    let nearest = -FINGERTIP_STEP * (FINGERTIP_TRIES - 1) as f64;
    for (k, robot) in scene.robots.iter().enumerate() {
        let depth = bar_depth(&part, &power[k]).unwrap();
        assert!(depth.abs() < 1e-4, "power[{k}] {depth}");
        assert!(held.moved[k] < -0.001, "power[{k}] {:?}", held.moved);
        let beyond = robot.power_point_z + bar_depth(&part, &held.power[k]).unwrap()
            - robot.precision_point_z;
        assert!(
            beyond <= 1e-4 && beyond >= nearest - 1e-4,
            "power[{k}] {beyond}"
        );
        let kinds = close_on_part(
            &part,
            &arms[k].gripper,
            &(held.power[k] * arms[k].gripper.power_point().inverse()),
        )
        .unwrap()
        .kinds;
        assert_eq!(kinds, [ClosingKind::Pinch; 2], "power[{k}]");
    }
}

#[test]
fn grasps_held_at_the_fingertips_stay_there_when_planned_again() {
    // The stool side's grasps held at the fingertips, given again as the scene's grasps (as
    // `replan` gives a plan file's): the palm is out of the seating's reach and the bar lies at
    // a fingertip depth, so neither moves again.
    let (scene, mesh) = example_files("stool_side");
    let part = ObjectGeometry::new(&mesh).unwrap();
    let arms = arm_models(&scene).unwrap();
    let first = seat_power_grasps_by(
        &part,
        &arms,
        &scene.grasps.power,
        [0.0; 2],
        SeatRule::PLANNER,
    );
    assert!(first.moved.iter().all(|&m| m < 0.0), "{:?}", first.moved);
    let again = seat_power_grasps_by(&part, &arms, &first.power, [0.0; 2], SeatRule::PLANNER);
    assert_eq!(again.moved, [0.0; 2]);
    assert_eq!(again.power, first.power);
}
