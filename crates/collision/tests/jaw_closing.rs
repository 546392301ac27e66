//! How a parallel-jaw gripper closes on the part (`close_on_part` with a `JawGripper`): two
//! box jaws 80 mm apart when open, sliding along the flange `x` from a joint 0 … 0.04 m each
//! (the Franka Hand's stroke), closed on boxes whose answer is known by hand.

use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Translation3, Vector3};
use pregrasp_collision::fixtures::box_mesh;
use pregrasp_collision::{close_on_part, pad_patches, GripFailure, ObjectGeometry};
use pregrasp_robot::{ClosingKind, Gripper, GripperState, JawGripper, JawPart};

/// The corners of the box `lo`..`hi`.
fn corners(lo: [f64; 3], hi: [f64; 3]) -> Vec<Point3<f64>> {
    (0..8)
        .map(|i| {
            Point3::new(
                if i & 1 == 0 { lo[0] } else { hi[0] },
                if i & 2 == 0 { lo[1] } else { hi[1] },
                if i & 4 == 0 { lo[2] } else { hi[2] },
            )
        })
        .collect()
}

/// A hand box above z = 0.06 and two 10 mm thick jaws reaching from z = 0.06 to 0.12, their
/// inner faces at x = ±j (joint j), 20 mm wide in y.
fn jaws() -> Gripper {
    let part = |name: &str, lo, hi| JawPart::new(name, vec![corners(lo, hi)]).unwrap();
    let hand = part("hand", [-0.05, -0.03, 0.0], [0.05, 0.03, 0.06]);
    let plus = part("plus", [0.0, -0.01, 0.06], [0.01, 0.01, 0.12]);
    let minus = part("minus", [-0.01, -0.01, 0.06], [0.0, 0.01, 0.12]);
    let j = JawGripper::new(
        "test jaws".into(),
        vec![hand],
        [vec![plus], vec![minus]],
        [Isometry3::identity(); 2],
        [Vector3::x(), -Vector3::x()],
        (0.0, 0.04),
        0.1,
        0.1,
    )
    .unwrap();
    Gripper::Jaws(Arc::new(j))
}

/// A bar along y, `width` in x from `x0`, 20 mm tall about the flange's z = 0.1.
fn bar(x0: f64, width: f64) -> ObjectGeometry {
    let mesh = box_mesh(
        Point3::new(x0 + 0.5 * width, 0.0, 0.1),
        Vector3::new(0.5 * width, 0.1, 0.01),
        1,
    );
    ObjectGeometry::new(&mesh).unwrap()
}

#[test]
fn centred_jaws_stop_at_the_bars_width_and_both_bear_on_it() {
    let g = jaws();
    let part = bar(-0.015, 0.03);
    let grip = close_on_part(&part, &g, &Isometry3::identity()).unwrap();
    assert!((grip.width() - 0.03).abs() < 1e-9, "{}", grip.width());
    assert_eq!(grip.kinds, [ClosingKind::Pinch; 2]);
    assert!(matches!(grip.state(), GripperState::Jaws { .. }));
    // Each jaw face meets the bar over its 20 mm of width and the bar's 20 mm of height.
    let patches = pad_patches(&part, &g, &Isometry3::identity(), &grip);
    for p in patches {
        let p = p.expect("both jaws bear on the bar");
        assert!((p.area - 0.02 * 0.02).abs() < 1e-9, "{p:?}");
        assert!(
            (p.center.z - 0.1).abs() < 1e-9 && p.center.x.abs() > 0.0149,
            "{p:?}"
        );
    }
}

#[test]
fn an_off_centre_bar_stops_both_jaws_at_the_first_touch() {
    let g = jaws();
    // The bar spans x = −10 … 20 mm: the +x jaw meets it at a 40 mm gap, the −x jaw not.
    let grip = close_on_part(&bar(-0.01, 0.03), &g, &Isometry3::identity()).unwrap();
    assert!((grip.width() - 0.04).abs() < 1e-9, "{}", grip.width());
    assert_eq!(grip.kinds, [ClosingKind::Pinch, ClosingKind::Closed]);
}

#[test]
fn too_wide_or_nothing_between_is_refused() {
    let g = jaws();
    // Wider than the open jaws, which stand 10 mm inside it (their inner edges are 10 mm
    // from the bar's ends and faces): rule 2's open hand refuses it, naming the deepest jaw.
    let wide = close_on_part(&bar(-0.05, 0.1), &g, &Isometry3::identity());
    match wide.unwrap_err() {
        GripFailure::OpenInside { link, depth, back } => {
            assert!(link == "gripper_plus" || link == "gripper_minus", "{link}");
            assert!((depth - 0.01).abs() < 2e-4 && back == 0.0, "{depth} {back}");
        }
        other => panic!("{other:?}"),
    }
    // As wide as the open jaws: they touch it, and cannot close on it.
    let touching = close_on_part(&bar(-0.04, 0.08), &g, &Isometry3::identity());
    assert_eq!(touching.unwrap_err(), GripFailure::OpenTouches);
    let away = Isometry3::from(Translation3::new(0.0, 0.0, 0.5));
    let nothing = close_on_part(&bar(-0.015, 0.03), &g, &away);
    assert_eq!(nothing.unwrap_err(), GripFailure::ClosesOnNothing);
}

#[test]
fn the_lowest_point_is_the_jaw_tips_flange_down() {
    let g = jaws();
    let grip = close_on_part(&bar(-0.015, 0.03), &g, &Isometry3::identity()).unwrap();
    // Flange 0.3 m up, pointing down: the jaw tips (z = 0.12 in the flange) at 0.18, less the
    // 0.1 mm every closing sweep allows for (exact for sliding jaws, kept on the safe side).
    let down = Isometry3::from_parts(
        Translation3::new(0.0, 0.0, 0.3),
        nalgebra::UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI),
    );
    assert!(
        (grip.lowest(&down) - 0.1799).abs() < 1e-9,
        "{}",
        grip.lowest(&down)
    );
    assert!(grip.clears(&down, 0.1798) && !grip.clears(&down, 0.18));
}
