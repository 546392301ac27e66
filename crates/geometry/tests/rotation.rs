//! Rotation about a line and the height sinusoid: Rodrigues vs nalgebra, closed-form crossings
//! vs analytic cases and dense sampling.

use nalgebra::{Point3, Unit, Vector3};
use pregrasp_geometry::rotation::{max_rotation_above, rotation_about_line, HeightSinusoid};
use proptest::prelude::*;

fn unit(x: f64, y: f64, z: f64) -> Unit<Vector3<f64>> {
    Unit::new_normalize(Vector3::new(x, y, z))
}

#[test]
fn rotation_about_line_fixes_the_line_and_turns_right_handed() {
    let c = Point3::new(1.0, 2.0, 3.0);
    let u = unit(0.0, 0.0, 1.0);
    let pose = rotation_about_line(&c, &u, std::f64::consts::FRAC_PI_2);
    assert!((pose * c - c).norm() < 1e-15);
    assert!((pose * (c + *u) - (c + *u)).norm() < 1e-15);
    // +x offset turns into +y offset under +90° about +z.
    let q = pose * Point3::new(2.0, 2.0, 3.0);
    assert!((q - Point3::new(1.0, 3.0, 3.0)).norm() < 1e-15);
}

#[test]
fn plate_edge_crossing_is_atan_of_lift_over_distance() {
    // Rotating (d, 0, h) about +y through the origin: z(θ) = h cos θ − d sin θ, zero at atan(h/d).
    for (d, h) in [(0.4, 0.001), (0.6, 0.001), (0.3, 0.0), (0.2, 0.05)] {
        let s = HeightSinusoid::of_point(
            &Point3::new(d, 0.0, h),
            &Point3::origin(),
            &unit(0.0, 1.0, 0.0),
        );
        let t = s.first_descent_below(0.0, 0.0).unwrap();
        assert!((t - (h / d).atan()).abs() < 1e-15, "d {d} h {h}: {t}");
    }
}

#[test]
fn point_rising_first_comes_down_after_half_a_turn_or_more() {
    // (d, 0, 0) about −y rises, and is back at z = 0 at θ = π.
    let s = HeightSinusoid::of_point(
        &Point3::new(0.5, 0.0, 0.0),
        &Point3::origin(),
        &unit(0.0, -1.0, 0.0),
    );
    assert_eq!(
        s.first_descent_below(0.0, 1e-12),
        Some(std::f64::consts::PI)
    );
    // A point circling about a line high above the level never reaches it.
    let s = HeightSinusoid::of_point(
        &Point3::new(0.5, 0.0, 1.0),
        &Point3::new(0.0, 0.0, 0.9),
        &unit(0.0, 1.0, 0.0),
    );
    assert_eq!(s.first_descent_below(0.0, 1e-12), None);
    // Starting below the level is an immediate crossing.
    let s = HeightSinusoid::of_point(
        &Point3::new(0.5, 0.0, -0.1),
        &Point3::origin(),
        &unit(0.0, 1.0, 0.0),
    );
    assert_eq!(s.first_descent_below(0.0, 1e-12), Some(0.0));
}

#[test]
fn max_rotation_is_capped_and_ignores_points_on_the_axis() {
    let axis = unit(0.0, 1.0, 0.0);
    let pts = [
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(0.0, 1.0, 0.0),
        Point3::new(-0.3, 0.0, 0.02),
    ];
    // Rotating about +y lifts the point at negative x... until it passes over the top.
    let t = max_rotation_above(&pts, &Point3::origin(), &axis, 0.0, 1.0, 1e-12);
    assert_eq!(t, 1.0);
    let t = max_rotation_above(&pts, &Point3::origin(), &(-axis), 0.0, 1.0, 1e-12);
    assert!((t - (0.02f64 / 0.3).atan()).abs() < 1e-15);
}

proptest! {
    #[test]
    fn sinusoid_matches_rotated_point(
        x in prop::array::uniform3(-1.0..1.0f64),
        c in prop::array::uniform3(-1.0..1.0f64),
        u in prop::array::uniform3(-1.0..1.0f64),
        theta in -7.0..7.0f64,
    ) {
        prop_assume!(Vector3::from(u).norm() > 0.1);
        let (x, c, u) = (Point3::from(x), Point3::from(c), unit(u[0], u[1], u[2]));
        let s = HeightSinusoid::of_point(&x, &c, &u);
        let rotated = rotation_about_line(&c, &u, theta) * x;
        prop_assert!((s.eval(theta) - rotated.z).abs() < 1e-12);
    }

    #[test]
    fn first_descent_agrees_with_dense_sampling(
        c in -1.0..1.0f64, a in -1.0..1.0f64, b in -1.0..1.0f64,
    ) {
        let s = HeightSinusoid { c, a, b };
        prop_assume!(s.eval(0.0) > 1e-3);
        let found = s.first_descent_below(0.0, 1e-12);
        let n = 200_000;
        let sampled = (1..=n)
            .map(|k| std::f64::consts::TAU * k as f64 / n as f64)
            .find(|&t| s.eval(t) < -1e-9);
        match (found, sampled) {
            (Some(t), Some(ts)) => {
                prop_assert!(t <= ts + 1e-12, "{t} after sampled {ts}");
                prop_assert!(ts - t < 1e-3, "{t} much before sampled {ts}");
                prop_assert!(s.eval(t).abs() < 1e-9);
                for k in 0..100 {
                    prop_assert!(s.eval(t * k as f64 / 100.0) >= -1e-12);
                }
            }
            (None, None) => {}
            // Near-tangential touches may be missed by one side only.
            (Some(t), None) => prop_assert!(s.amplitude() - (s.c).abs() < 1e-6, "{t}"),
            (None, Some(ts)) => prop_assert!(s.eval(ts) > -1e-6, "{ts}"),
        }
    }
}
