//! Algorithm 1 under rigid placements: moving a resting part about the vertical and across the
//! support (and the support up or down) moves its candidates with it and leaves every θ_max,
//! length and score unchanged; θ_max is where the part first touches the support.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use pregrasp_geometry::shapes::{cuboid, prism, union};
use pregrasp_geometry::Mesh;
use pregrasp_io::scene::PlannerParams;
use pregrasp_planner::axes::{rotation_axis_candidates, RotationAxisCandidate};
use proptest::prelude::*;

fn p(x: f64, y: f64, z: f64) -> Point3<f64> {
    Point3::new(x, y, z)
}

/// One of a few part families, sized by `dims` (each in [0.1, 1]).
fn part(kind: u8, dims: [f64; 3]) -> Mesh {
    let [a, b, c] = dims;
    match kind {
        0 => cuboid(p(-a / 2.0, 0.0, 0.0), p(a / 2.0, b, 0.05 * c)),
        1 => prism(&[[0.0, 0.0], [a, 0.0], [a * c, 0.5 * b]], 0.0, 0.8),
        _ => union(&[
            cuboid(p(0.0, 0.0, 0.0), p(a, 0.04, 0.03)),
            cuboid(p(0.0, b + 0.1, 0.0), p(a, b + 0.14, 0.03)),
            cuboid(
                p(0.5 * a * c, 0.05, 0.0),
                p(0.5 * a * c + 0.04, b + 0.09, 0.03),
            ),
        ]),
    }
}

/// The pose that rests `mesh`, turned by `r0`, on `z = 0`.
fn resting(mesh: &Mesh, r0: UnitQuaternion<f64>) -> Isometry3<f64> {
    let low = mesh
        .vertices
        .iter()
        .map(|v| (r0 * v).z)
        .fold(f64::INFINITY, f64::min);
    Isometry3::from_parts(Translation3::new(0.0, 0.0, -low), r0)
}

fn orientation(k: u8) -> UnitQuaternion<f64> {
    let (roll, pitch) = [
        (0.0, 0.0),
        (FRAC_PI_2, 0.0),
        (PI, 0.0),
        (-FRAC_PI_2, 0.0),
        (0.0, FRAC_PI_2),
        (0.0, -FRAC_PI_2),
    ][k as usize % 6];
    UnitQuaternion::from_euler_angles(roll, pitch, 0.0)
}

fn matches(a: &RotationAxisCandidate, b: &RotationAxisCandidate, g: &Isometry3<f64>) -> bool {
    let (a0, a1) = (g * a.axis[0], g * a.axis[1]);
    let close = |x: &Point3<f64>, y: &Point3<f64>| (x - y).norm() < 1e-9;
    let same_ends = (close(&a0, &b.axis[0]) && close(&a1, &b.axis[1]))
        || (close(&a0, &b.axis[1]) && close(&a1, &b.axis[0]));
    same_ends
        && (g.rotation * a.signed_axis().into_inner() - b.signed_axis().into_inner()).norm() < 1e-9
        && (a.theta_max - b.theta_max).abs() < 1e-9
        && (a.theta_max_stepped - b.theta_max_stepped).abs() < 1e-9
        && (a.length - b.length).abs() < 1e-12
        && (a.score - b.score).abs() < 1e-9
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn candidates_move_with_the_part(
        kind in 0u8..3,
        dims in prop::array::uniform3(0.1..1.0f64),
        face in 0u8..6,
        yaw in -PI..PI,
        x in -1.0..1.0f64,
        y in -1.0..1.0f64,
        s in -0.5..1.0f64,
    ) {
        let mesh = part(kind, dims);
        let base = resting(&mesh, orientation(face));
        let params = PlannerParams::default();
        let reference = rotation_axis_candidates(&mesh, &base, 0.0, &params);
        let g = Isometry3::from_parts(Translation3::new(x, y, s), UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw));
        let placed = rotation_axis_candidates(&mesh, &(g * base), s, &params);
        prop_assert_eq!(reference.candidates.len(), placed.candidates.len());
        prop_assert!(!reference.candidates.is_empty());
        for a in &reference.candidates {
            let n = placed.candidates.iter().filter(|b| matches(a, b, &g)).count();
            prop_assert_eq!(n, 1, "candidate {:?} has {} images", a, n);
        }
        // Best scores agree in order.
        for (a, b) in reference.candidates.iter().zip(&placed.candidates) {
            prop_assert!((a.score - b.score).abs() < 1e-9);
        }
    }

    #[test]
    fn theta_max_is_first_contact(
        kind in 0u8..3,
        dims in prop::array::uniform3(0.1..1.0f64),
        face in 0u8..6,
        lift in 0.0001..0.01f64,
    ) {
        let mesh = part(kind, dims);
        let base = resting(&mesh, orientation(face));
        let params = PlannerParams { lift, max_angle: 3.0, ..PlannerParams::default() };
        let r = rotation_axis_candidates(&mesh, &base, 0.0, &params);
        let lowest = |pose: &Isometry3<f64>| r.hull.vertices.iter().map(|v| (pose * v).z).fold(f64::INFINITY, f64::min);
        for c in &r.candidates {
            prop_assert!(c.theta_max > 0.0 && c.theta_max <= params.max_angle);
            if c.theta_max < params.max_angle {
                prop_assert!(lowest(&c.rotated_pose(&r.p_init, c.theta_max)).abs() < 1e-9);
                prop_assert!(lowest(&c.rotated_pose(&r.p_init, c.theta_max + 1e-4)) < 0.0);
            }
            for k in 0..=50 {
                prop_assert!(lowest(&c.rotated_pose(&r.p_init, c.theta_max * k as f64 / 50.0)) >= -1e-9);
            }
        }
    }
}
