//! Straight tool lines on an analytic toy "arm": the tool translation is (q0, q1, q2)
//! and its rotation the roll–pitch–yaw angles (q3, q4, q5).

use std::f64::consts::PI;

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pregrasp_motion::{
    interpolate_pose, straight_line, CartesianError, CartesianSettings, JointSpace,
    MotionValidator, State,
};

fn fk(q: &State<6>) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(q[0], q[1], q[2]),
        UnitQuaternion::from_euler_angles(q[3], q[4], q[5]),
    )
}

/// Both roll–pitch–yaw branches with 2π shifts; the one nearest to `seed`.
fn ik_nearest(pose: &Isometry3<f64>, seed: &State<6>) -> Option<State<6>> {
    let t = pose.translation.vector;
    let (r, p, y) = pose.rotation.euler_angles();
    let wrap = |a: f64, s: f64| a + 2.0 * PI * ((s - a) / (2.0 * PI)).round();
    [(r, p, y), (r + PI, PI - p, y + PI)]
        .into_iter()
        .map(|(r, p, y)| {
            [
                t.x,
                t.y,
                t.z,
                wrap(r, seed[3]),
                wrap(p, seed[4]),
                wrap(y, seed[5]),
            ]
        })
        .min_by(|a, b| dist(a, seed).total_cmp(&dist(b, seed)))
}

fn dist(a: &State<6>, b: &State<6>) -> f64 {
    (0..6).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
}

fn space() -> JointSpace<6> {
    JointSpace::new(
        [-2.0, -2.0, -2.0, -4.0, -4.0, -4.0],
        [2.0, 2.0, 2.0, 4.0, 4.0, 4.0],
        [1.0, 1.0, 1.0, 0.2, 0.2, 0.2],
    )
    .unwrap()
}

const START: State<6> = [0.1, 0.2, 0.3, 0.1, -0.2, 0.3];

fn goal() -> Isometry3<f64> {
    let g = fk(&START);
    let shift = Translation3::new(0.12, -0.05, 0.02);
    let turn = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.35);
    Isometry3::from_parts(shift * g.translation, turn * g.rotation)
}

#[test]
fn free_line_is_followed_within_tolerance() {
    let space = space();
    let v = |_: &State<6>| true;
    let mv = MotionValidator::new(&space, &v, 0.005);
    let settings = CartesianSettings::default();
    let (a, b) = (fk(&START), goal());
    let qs = straight_line(fk, ik_nearest, &mv, &START, &b, &settings).unwrap();
    assert_eq!(qs[0], START);
    let dir = (b.translation.vector - a.translation.vector).normalize();
    for w in qs.windows(2) {
        let (p0, p1) = (fk(&w[0]), fk(&w[1]));
        assert!(
            (p1.translation.vector - p0.translation.vector).norm()
                <= settings.max_translation_step + 1e-12
        );
        assert!(p0.rotation.angle_to(&p1.rotation) <= settings.max_rotation_step + 1e-9);
        assert!(dist(&w[0], &w[1]) <= settings.max_joint_jump);
    }
    for q in &qs {
        // On the line: no component of (p − a) orthogonal to the direction.
        let d = fk(q).translation.vector - a.translation.vector;
        assert!((d - dir * d.dot(&dir)).norm() < 1e-9);
        // On the rotation geodesic: the rotation axis of R_a⁻¹ R is the goal's.
        let rel = (a.rotation.inverse() * fk(q).rotation).scaled_axis();
        let goal_axis = (a.rotation.inverse() * b.rotation)
            .scaled_axis()
            .normalize();
        assert!(rel.cross(&goal_axis).norm() < 1e-9);
    }
    let end = fk(qs.last().unwrap());
    assert!((end.translation.vector - b.translation.vector).norm() < 1e-12);
    assert!(end.rotation.angle_to(&b.rotation) < 1e-9);
}

#[test]
fn blocked_line_fails_with_collision_fraction() {
    let space = space();
    // A wall across the line at x ∈ (0.16, 0.17): fraction ≈ (0.16 − 0.1) / 0.12 = 0.5.
    let v = |q: &State<6>| !(q[0] > 0.16 && q[0] < 0.17);
    let mv = MotionValidator::new(&space, &v, 0.002);
    match straight_line(
        fk,
        ik_nearest,
        &mv,
        &START,
        &goal(),
        &CartesianSettings::default(),
    ) {
        Err(CartesianError::Collision { fraction }) => {
            assert!((fraction - 0.5).abs() < 0.05, "{fraction}")
        }
        other => panic!("expected a collision, got {other:?}"),
    }
}

#[test]
fn ik_failure_reports_unreachable_fraction() {
    let space = space();
    let v = |_: &State<6>| true;
    let mv = MotionValidator::new(&space, &v, 0.005);
    // Workspace ends at x = 0.19: fraction (0.19 − 0.1) / 0.12 = 0.75.
    let ik = |p: &Isometry3<f64>, s: &State<6>| {
        if p.translation.x > 0.19 {
            None
        } else {
            ik_nearest(p, s)
        }
    };
    match straight_line(fk, ik, &mv, &START, &goal(), &CartesianSettings::default()) {
        Err(CartesianError::Unreachable { fraction }) => {
            assert!((fraction - 0.75).abs() < 0.05, "{fraction}")
        }
        other => panic!("expected unreachable, got {other:?}"),
    }
}

#[test]
fn branch_flip_is_detected() {
    let space = space();
    let v = |_: &State<6>| true;
    let mv = MotionValidator::new(&space, &v, 0.005);
    // An IK that switches to the other Euler branch past x = 0.15.
    let ik = |p: &Isometry3<f64>, s: &State<6>| {
        let q = ik_nearest(p, s)?;
        if p.translation.x > 0.15 {
            let flipped = [q[0], q[1], q[2], q[3] + PI, PI - q[4], q[5] + PI];
            assert!(
                fk(&flipped).rotation.angle_to(&p.rotation) < 1e-9,
                "same pose, other branch"
            );
            Some(flipped)
        } else {
            Some(q)
        }
    };
    match straight_line(fk, ik, &mv, &START, &goal(), &CartesianSettings::default()) {
        Err(CartesianError::BranchJump { fraction, jump }) => {
            assert!(fraction > 0.35 && fraction < 0.5, "{fraction}");
            assert!(jump > 2.0);
        }
        other => panic!("expected a branch jump, got {other:?}"),
    }
}

#[test]
fn joint_limits_and_invalid_start_fail_cleanly() {
    let tight = JointSpace::new(
        [-2.0, -2.0, -2.0, -4.0, -4.0, -4.0],
        [0.15, 2.0, 2.0, 4.0, 4.0, 4.0],
        [1.0; 6],
    )
    .unwrap();
    let v = |_: &State<6>| true;
    let mv = MotionValidator::new(&tight, &v, 0.005);
    assert!(matches!(
        straight_line(
            fk,
            ik_nearest,
            &mv,
            &START,
            &goal(),
            &CartesianSettings::default()
        ),
        Err(CartesianError::JointLimit { .. })
    ));
    let space = space();
    let never = |_: &State<6>| false;
    let mv = MotionValidator::new(&space, &never, 0.005);
    assert_eq!(
        straight_line(
            fk,
            ik_nearest,
            &mv,
            &START,
            &goal(),
            &CartesianSettings::default()
        ),
        Err(CartesianError::Collision { fraction: 0.0 })
    );
    let bad = CartesianSettings {
        max_translation_step: 0.0,
        ..CartesianSettings::default()
    };
    assert!(matches!(
        straight_line(
            fk,
            ik_nearest,
            &MotionValidator::new(&space, &v, 0.005),
            &START,
            &goal(),
            &bad
        ),
        Err(CartesianError::InvalidSettings(_))
    ));
}

#[test]
fn half_turn_interpolation_is_total_and_uniform() {
    let a = Isometry3::identity();
    let b = Isometry3::rotation(Vector3::new(0.0, 0.0, PI));
    let m = interpolate_pose(&a, &b, 0.5);
    assert!((m.rotation.angle() - PI / 2.0).abs() < 1e-12);
    assert!((interpolate_pose(&a, &b, 1.0).rotation.angle_to(&b.rotation)).abs() < 1e-12);
}
