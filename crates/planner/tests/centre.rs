//! Power grasps moved across onto their bar's mid-plane (issue 48, closings that do not push):
//! the 2F-85's fingers close together, so a grasp off its bar's mid-plane meets the bar with
//! one pad first and shoves it. `seat::off_centre` reads the bar as the stretch of material
//! the grasp's closing line crosses (`seat::material_along`); the planner moves the grasp onto
//! its mid-plane and says so in `grasps.centred`.

mod common;

use common::scenes::generated_files;
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use pregrasp_collision::ObjectGeometry;
use pregrasp_examples::parts::families::Family;
use pregrasp_geometry::shapes::{cuboid, union};
use pregrasp_planner::pipeline::PlanOptions;
use pregrasp_planner::seat::{bar_mid_plane, material_along, off_centre, CENTRE_REACH};

/// A power grasp over a bar along the world `y`, the gripper pointing down (`z` into the
/// table), its fingers closing along the world `x`, its origin at `x`.
fn grasp_at(x: f64) -> Isometry3<f64> {
    let down = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI);
    Isometry3::from_parts(Translation3::new(x, 0.0, 0.01), down)
}

/// Bars 20 mm wide (`x ∈ [lo, lo + 0.02]`), 20 mm thick and 200 mm long along `y`.
fn bar(lo: f64) -> pregrasp_geometry::Mesh {
    cuboid(
        Point3::new(lo, -0.1, 0.0),
        Point3::new(lo + 0.02, 0.1, 0.02),
    )
}

#[test]
fn the_line_through_a_grasp_crosses_each_bar_once() {
    let part = ObjectGeometry::new(&union(&[bar(-0.08), bar(0.015)])).unwrap();
    let stretches = material_along(&part, &grasp_at(0.02));
    assert_eq!(stretches.len(), 2, "{stretches:?}");
    for ((low, high), want) in stretches.iter().zip([(-0.1, -0.08), (-0.005, 0.015)]) {
        assert!(
            (low - want.0).abs() < 1e-6 && (high - want.1).abs() < 1e-6,
            "{stretches:?}"
        );
    }
    // Along the bar (the grasp turned a quarter about its approach): one long stretch.
    let along = grasp_at(0.025)
        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2);
    let stretches = material_along(&part, &along);
    assert_eq!(stretches.len(), 1, "{stretches:?}");
    assert!((stretches[0].1 - stretches[0].0 - 0.2).abs() < 1e-5);
    // A bar longer than the stroke is no bar to centre on.
    assert_eq!(off_centre(&part, &along), None);
}

#[test]
fn a_grasp_off_a_bar_moves_onto_its_mid_plane() {
    let part = ObjectGeometry::new(&bar(-0.01)).unwrap();
    // The grasp's x runs along the world's x (turned about x, not z): a grasp at +x moves by
    // −x, as far as its origin lies outside the bar and beyond.
    for x in [0.0025, 0.008, -0.012, 0.02, -0.025] {
        let across = off_centre(&part, &grasp_at(x)).unwrap();
        assert!((across + x).abs() < 1e-6, "at {x}: {across}");
    }
    // Within the scene files' rounding it stays (the fingertip holds centre those).
    assert_eq!(off_centre(&part, &grasp_at(0.0015)), None);
    assert_eq!(off_centre(&part, &grasp_at(0.0)), None);
    // A bar whose near face lies within the open pads' reach (the open pad in it, as given),
    // and one beyond it.
    let across = off_centre(&part, &grasp_at(0.05)).unwrap();
    assert!((across + 0.05).abs() < 1e-6, "{across}");
    assert_eq!(off_centre(&part, &grasp_at(0.06)), None);
}

#[test]
fn a_grasp_between_two_bars_stays() {
    // Two 20 mm bars with 30 mm of air between them, the grasp's origin in the air: the pads
    // would meet the outer faces of two bars, which is no bar's mid-plane.
    let part = ObjectGeometry::new(&union(&[bar(-0.035), bar(0.015)])).unwrap();
    for x in [0.003, -0.004] {
        assert_eq!(off_centre(&part, &grasp_at(x)), None, "at {x}");
    }
    // Over one of two bars 30 mm apart: the other open pad would lie in the other bar.
    assert_eq!(off_centre(&part, &grasp_at(0.030)), None);
    // Bars 75 mm apart: the open pads fit between them.
    let part = ObjectGeometry::new(&union(&[bar(-0.08), bar(0.015)])).unwrap();
    let across = off_centre(&part, &grasp_at(0.030)).unwrap();
    assert!((across + 0.005).abs() < 1e-6, "{across}");
}

#[test]
fn a_grasp_a_user_moved_across_its_bar_is_planned_where_the_generator_put_it() {
    // Generated frame #1, its master grasp moved 12 mm across its bar (its own x): planned
    // as before, on the bar's mid-plane, the plan file saying how far it moved back.
    let (scene, mesh) = generated_files(Family::Frame, 1);
    let plan = |scene: &pregrasp_io::scene::Scene| {
        pregrasp_planner::plan_scene(scene, &mesh, &PlanOptions::default(), &|_| {}, &|| {})
            .unwrap()
            .file
    };
    let want = plan(&scene);
    assert!(!want.plans.is_empty());
    let part = ObjectGeometry::new(&mesh).unwrap();
    for k in 0..2 {
        let grasp = scene.grasps.power[k];
        assert!(bar_mid_plane(&part, &grasp).unwrap().abs() <= CENTRE_REACH);
        assert_eq!(off_centre(&part, &grasp), None, "power[{k}]");
    }
    let k = 1;
    let mut moved = scene.clone();
    moved.grasps.power[k] = scene.grasps.power[k] * Translation3::new(0.012, 0.0, 0.0);
    let got = plan(&moved);
    let centred = got.grasps.centred.unwrap();
    let before = want.grasps.centred.map_or(0.0, |c| c[k]);
    assert!((centred[k] - (before - 0.012)).abs() < 2e-6, "{centred:?}");
    let (a, b) = (want.grasps.power[k].xyz, got.grasps.power[k].xyz);
    let apart = (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
    assert!(apart < 2e-6, "{a:?} {b:?}");
    // The same plans, to the closings' widths.
    assert_eq!(got.plans.len(), want.plans.len());
    for (g, w) in got.plans.iter().zip(&want.plans) {
        for (s, t) in g.segments.iter().zip(&w.segments) {
            let (s, t) = (s.grip_width.unwrap_or(0.0), t.grip_width.unwrap_or(0.0));
            assert!((s - t).abs() < 1e-5, "{s} {t}");
        }
    }
}
