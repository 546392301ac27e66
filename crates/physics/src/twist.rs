//! Does the part hang on the pads' twist? The moment about the pinch that only a twist of the
//! pads can hold, per newton of the part's weight.
//!
//! While the supportive arm turns the part about its edge, the table bears the edge and the
//! pinch the rest. The table pushes only up, along the axis, so it holds no moment about the
//! axis: about the axis line, the weight `W` at the centre of mass (horizontal distance
//! `d_com` across the axis) is held by the pinch's lift `F` at `d_pinch` and a moment `m` of the
//! pinch about the axis direction `u`: `W d_com = F d_pinch + m`. With the table loaded
//! (`F ≤ W`), `m ≥ W (d_com − d_pinch)`: where the pinch lies nearer the axis than the centre
//! of mass, the part hangs from the pinch and the pads must hold that moment. Its part about
//! the pads' normal `x` (the closing axis), `m |u · x|`, only a twist of the pads holds — the
//! rest they hold by pressing harder on one edge of their faces. A pad's twist is its weakest
//! hold (the Menagerie's 2F-85 pads are two small boxes each, with no torsional friction); where
//! the rotation leans on it, the part turns in the pads and its edge lifts off the table.
//!
//! The measure is the **twist arm** `(d_com − d_pinch)⁺ · |u · x|` (m): the moment per newton
//! of weight the pads' twist must hold. A rotation is refused where it exceeds
//! [`MAX_TWIST_ARM`] in some state.

use nalgebra::{Point3, Vector3};

/// Largest twist arm (m) of a rotation whose edge stays on the table.
///
/// Whole-plan replay of the rotations planned without this rule (the examples and 30 generated
/// parts, seeds 1–5, `plan_replay_generated_twist_off_2f85.csv`; the five generated ladders
/// with their pinch moved onto the middle rung at 0.6–0.9 of the centre of mass' distance from
/// the axis, `plan_replay_pinch_probe_2f85.csv`; 30 generated parts of seeds 6–10, replayed after
/// the bound was set, `plan_replay_generated_seeds_6_10_twist_off_2f85.csv`; test
/// `crates/planner/tests/twist_truth.rs`): every rotation with a twist arm (18.7–107.6 mm, 27 of
/// 110) ended 0.58–9.90° short of the plan with its edge lifted 0.7–25.3 mm; every one without
/// (83) ended within 0.54°, among them the H-frames, whose pinch lies at 0.93 of the centre of
/// mass' distance with its pads facing across the axis. The bound allows for rounding and a
/// pinch a few millimetres off.
pub const MAX_TWIST_ARM: f64 = 0.005;

/// The twist arm (m) of one state: `axis` the rotation axis' two endpoints, `com` the centre of
/// mass, `pinch` where the pads bear on the part, `closing` the pads' normal (the gripper's
/// closing axis), all in the world frame (`z` up).
pub fn twist_arm(
    axis: [Point3<f64>; 2],
    com: Point3<f64>,
    pinch: Point3<f64>,
    closing: Vector3<f64>,
) -> f64 {
    let flat = |v: Vector3<f64>| Vector3::new(v.x, v.y, 0.0);
    let Some(u) = flat(axis[1] - axis[0]).try_normalize(1e-12) else {
        return 0.0; // a vertical axis: no rotation on a table
    };
    // Horizontal distance across the axis, along the centre of mass' side.
    let across = |p: Point3<f64>| {
        let d = flat(p - axis[0]);
        d - u * d.dot(&u)
    };
    let c = across(com);
    let Some(side) = c.try_normalize(1e-12) else {
        return 0.0; // the centre of mass above the axis: no moment to hold
    };
    let hang = c.norm() - across(pinch).dot(&side);
    let facing = closing
        .try_normalize(1e-12)
        .map_or(0.0, |x| u.dot(&x).abs());
    hang.max(0.0) * facing
}

#[cfg(test)]
mod tests {
    use super::twist_arm;
    use nalgebra::{Point3, Vector3};

    #[test]
    fn the_twist_arm_is_the_hang_times_how_much_the_pads_face_the_axis() {
        let axis = [Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0)];
        let com = Point3::new(0.3, 0.2, 0.05);
        let along = Vector3::x();
        // A pinch 0.1 m nearer the axis, pads facing along it: all of the hang.
        let near = Point3::new(0.5, 0.1, 0.3);
        assert!((twist_arm(axis, com, near, along) - 0.1).abs() < 1e-12);
        // The same pinch with its pads facing across the axis, or tilted 60° from it.
        assert_eq!(twist_arm(axis, com, near, Vector3::y()), 0.0);
        let tilted = Vector3::new(0.5, 3f64.sqrt() / 2.0, 0.0);
        assert!((twist_arm(axis, com, near, tilted) - 0.05).abs() < 1e-12);
        // A pinch beyond the centre of mass, or beyond the axis on its far side.
        assert_eq!(
            twist_arm(axis, com, Point3::new(0.1, 0.35, 0.0), along),
            0.0
        );
        assert!((twist_arm(axis, com, Point3::new(0.1, -0.1, 0.0), along) - 0.3).abs() < 1e-12);
        // The axis' ends swapped, the closing axis reversed: the same.
        let back = [axis[1], axis[0]];
        assert!((twist_arm(back, com, near, -along) - 0.1).abs() < 1e-12);
        // A centre of mass above the axis needs no hold.
        assert_eq!(
            twist_arm(axis, Point3::new(0.5, 0.0, 0.2), near, along),
            0.0
        );
    }
}
