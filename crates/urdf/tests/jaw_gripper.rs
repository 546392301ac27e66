//! `describe_gripper`: the Franka Hand of `fr3.urdf` as a parallel-jaw gripper. Its numbers
//! are franka_description's: `fr3_hand` turned −45° about the flange `z`, jaws sliding along
//! the hand's `y` (0 … 0.04 m each, the second a mimic), fingertip pads 18.5 mm tall whose
//! inner faces meet at the closed stroke, their middle, the TCP (`fr3_hand_tcp`) 0.1034 m out.

mod common;

use common::data;
use nalgebra::{Point3, Vector3};
use pregrasp_robot::{Gripper, GripperState};
use pregrasp_urdf::{
    describe_gripper, CacheDir, GeometryOptions, LazyGeometry, UrdfArm, UrdfError,
};

fn options() -> GeometryOptions {
    GeometryOptions {
        cache: CacheDir::Off,
        ..GeometryOptions::default()
    }
}

fn hand() -> pregrasp_robot::JawGripper {
    let arm = UrdfArm::load(data("fr3.urdf").as_ref(), None, Some("fr3_link8")).unwrap();
    describe_gripper(&arm, None, None, &LazyGeometry::new(options())).unwrap()
}

#[test]
fn the_franka_hand_opens_80_mm_and_closes_on_its_pads() {
    let h = hand();
    assert!((h.open_gap() - 0.08).abs() < 1e-3, "open {}", h.open_gap());
    assert!(h.closed_gap().abs() < 1e-3, "closed {}", h.closed_gap());
    // The hand, then one finger per jaw.
    let names: Vec<&str> = h.parts().map(|p| p.name).collect();
    assert_eq!(
        names,
        [
            "gripper_fr3_hand",
            "gripper_fr3_leftfinger",
            "gripper_fr3_rightfinger"
        ]
    );
    // Inner faces: the fingertip boxes, 17.5 mm wide and 18.5 mm tall about z = 0.0584 + 0.04525 m.
    for f in h.faces() {
        assert!(
            (f.z.0 - 0.0944).abs() < 1e-9 && (f.z.1 - 0.1129).abs() < 1e-9,
            "{f:?}"
        );
        assert!((f.y.1 - f.y.0 - 0.0175).abs() < 1e-4, "{f:?}");
    }
    // Tool points default to the faces' middle, 0.3 mm from franka_description's TCP.
    assert!((h.precision_point_z - 0.1034).abs() < 3e-4);
    assert_eq!(h.power_point_z, h.precision_point_z);
}

#[test]
fn the_closing_axis_is_the_hands_y() {
    let h = hand();
    // fr3_hand is link8 turned −45° about z; the left finger slides along the hand's +y.
    let x = h.closing_frame() * Vector3::x();
    let hand_y = Vector3::new(
        std::f64::consts::FRAC_1_SQRT_2,
        std::f64::consts::FRAC_1_SQRT_2,
        0.0,
    );
    assert!((x - hand_y).norm() < 1e-12, "{x}");
    assert_eq!(h.precision_point().rotation, h.closing_frame().rotation);
    // At a 30 mm gap each finger's inner face is 15 mm off the flange axis along x_C.
    let state = h.at_gap(0.03);
    let faces = h.faces_at(state);
    assert!((faces[0].x - 0.015).abs() < 1e-4 && (faces[1].x + 0.015).abs() < 1e-4);
    // The jaw frames moved by the same: a finger vertex at the face moves with its jaw.
    let [open, at] = [GripperState::Open, state].map(|s| h.jaw_frames(s));
    let p = Point3::origin();
    let moved = (open[0] * p - at[0] * p).norm() + (open[1] * p - at[1] * p).norm();
    assert!((moved - (h.open_gap() - 0.03)).abs() < 1e-9, "{moved}");
}

#[test]
fn shapes_hold_their_pieces_at_every_opening() {
    let g = Gripper::Jaws(std::sync::Arc::new(hand()));
    for state in g.sample_states() {
        let frames = g.shape_frames(state);
        let pieces = g.shape_pieces();
        g.for_each_shape(state, |k, name, prim| {
            let pieces = pieces[k].expect("every part has pieces");
            let pregrasp_robot::Primitive::Cuboid { pose, half_extents } = prim else {
                panic!("{name} is a box");
            };
            for v in pieces.pieces.iter().flatten() {
                let local = pose.inverse() * (frames[k] * v);
                let out = (local.coords.abs() - half_extents).max();
                assert!(out < 1e-9, "{name}: a vertex {out} m outside its box");
            }
        });
    }
}

#[test]
fn an_arm_without_a_hand_is_no_jaw_gripper() {
    let arm = UrdfArm::load(data("ur5e.urdf").as_ref(), None, Some("tool0")).unwrap();
    let geometry = LazyGeometry::new(options());
    let err = describe_gripper(&arm, None, None, &geometry).unwrap_err();
    assert!(matches!(err, UrdfError::NotAJawGripper { .. }), "{err}");
    assert!(err.to_string().contains("0 prismatic joints"), "{err}");
}
