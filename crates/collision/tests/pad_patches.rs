//! Where the pads bear on a bar after the real closing (`pad_patches`): on a pinch across a
//! 40 mm × 25 mm bar, each patch is the overlap of the pad's 22 mm × 37.5 mm contact face with
//! the bar's side, and its torsion radius that of the overlap rectangle under uniform pressure.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use pregrasp_collision::fixtures::box_mesh;
use pregrasp_collision::{close_on_part, pad_patches, ObjectGeometry};
use pregrasp_robot::{linkage, ClosingKind};

/// Mean distance from the centre of a `w × h` rectangle, uniform density (fine grid).
fn rectangle_torsion_radius(w: f64, h: f64) -> f64 {
    let n = 400;
    let mut sum = 0.0;
    for i in 0..n {
        for j in 0..n {
            let x = (i as f64 + 0.5) / n as f64 * w - w / 2.0;
            let y = (j as f64 + 0.5) / n as f64 * h - h / 2.0;
            sum += x.hypot(y);
        }
    }
    sum / (n * n) as f64
}

#[test]
fn a_pinch_bears_on_the_overlap_of_pad_and_bar() {
    // The bar along world x, 40 mm across (y), its top at z = 0.025; the gripper from above,
    // closing along world y, the precision point `depth` below the bar's top.
    let half = Vector3::new(0.2, 0.02, 0.0125);
    let part = ObjectGeometry::new(&box_mesh(Point3::new(0.0, 0.0, 0.0125), half, 2)).unwrap();
    let down =
        UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, std::f64::consts::FRAC_PI_2);
    for depth in [0.004, 0.010, 0.016] {
        let flange =
            Isometry3::from_parts(Translation3::new(0.0, 0.0, 0.025 - depth + 0.150), down);
        let grip = close_on_part(&part, &pregrasp_robot::Gripper::default(), &flange).unwrap();
        assert_eq!(grip.kinds, [ClosingKind::Pinch; 2], "depth {depth}");
        // The pads' meshes stand 0.3 mm proud of their nominal face plane on each side.
        assert!(
            (grip.width() - 0.040).abs() < 1e-3,
            "width {}",
            grip.width()
        );
        // The pad face spans pad centre ± 18.75 mm along G's z; the bar's side spans
        // G z from (flange z − 0.025) to (flange z).
        let pad_z = grip.fingers().configs()[0].pad_center(linkage()).y;
        let flange_z = flange.translation.z;
        let (bar_lo, bar_hi) = (flange_z - 0.025, flange_z);
        let overlap = (pad_z + 0.01875).min(bar_hi) - (pad_z - 0.01875).max(bar_lo);
        let patches = pad_patches(&part, &pregrasp_robot::Gripper::default(), &flange, &grip);
        for (k, patch) in patches.iter().enumerate() {
            let patch = patch.expect("the pad bears on the bar");
            let area = 0.022 * overlap;
            // Sampled every 2 mm: within one row of cells (2 mm × 22 mm), and half a cell of
            // contact depth at each end.
            assert!(
                (patch.area - area).abs() <= 0.022 * 0.003,
                "depth {depth} pad {k}: area {} vs {area}",
                patch.area
            );
            assert!(
                (patch.center.x.abs() - 0.020).abs() < 1e-3,
                "{:?}",
                patch.center
            );
            let mid = 0.5 * ((pad_z - 0.01875).max(bar_lo) + (pad_z + 0.01875).min(bar_hi));
            assert!(
                (patch.center.z - mid).abs() < 1.5e-3,
                "depth {depth}: {:?} vs {mid}",
                patch.center
            );
            let e = rectangle_torsion_radius(0.022, overlap);
            assert!(
                (patch.torsion_radius - e).abs() < 1e-3,
                "depth {depth}: e {} vs {e}",
                patch.torsion_radius
            );
        }
    }
}

/// The part remembers the 2F-85's patches by the pose with the fingers they were found for:
/// asked again, the same answer as a part that never saw them; asked at that pose with other
/// fingers (a wider closing's), the answer for those fingers, not the remembered one.
#[test]
fn remembered_patches_are_those_of_the_fingers_asked() {
    let half = Vector3::new(0.2, 0.02, 0.0125);
    let mesh = box_mesh(Point3::new(0.0, 0.0, 0.0125), half, 2);
    let (part, fresh) = (ObjectGeometry::new(&mesh).unwrap(), || {
        ObjectGeometry::new(&mesh).unwrap()
    });
    let gripper = pregrasp_robot::Gripper::default();
    let down =
        UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, std::f64::consts::FRAC_PI_2);
    let at = |depth: f64| {
        Isometry3::from_parts(Translation3::new(0.0, 0.0, 0.025 - depth + 0.150), down)
    };
    let (shallow, deep) = (at(0.004), at(0.016));
    let grip = close_on_part(&part, &gripper, &shallow).unwrap();
    // A closing on a wider bar: other fingers at the same pose.
    let wide = ObjectGeometry::new(&box_mesh(
        Point3::new(0.0, 0.0, 0.0125),
        Vector3::new(0.2, 0.03, 0.0125),
        2,
    ))
    .unwrap();
    let wider = close_on_part(&wide, &gripper, &shallow).unwrap();
    assert_ne!(grip.fingers().configs(), wider.fingers().configs());

    let first = pad_patches(&part, &gripper, &shallow, &grip);
    assert!(first.iter().all(Option::is_some));
    assert_eq!(pad_patches(&part, &gripper, &shallow, &grip), first);
    assert_eq!(pad_patches(&fresh(), &gripper, &shallow, &grip), first);
    let other = pad_patches(&part, &gripper, &shallow, &wider);
    assert_eq!(other, pad_patches(&fresh(), &gripper, &shallow, &wider));
    assert_ne!(other, first);
    // Another pose, its own answer.
    let deep_grip = close_on_part(&part, &gripper, &deep).unwrap();
    assert_eq!(
        pad_patches(&part, &gripper, &deep, &deep_grip),
        pad_patches(&fresh(), &gripper, &deep, &deep_grip)
    );
}
