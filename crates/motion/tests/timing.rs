use pregrasp_motion::{time_parameterize, try_time_parameterize, State, TimedPath, TimingError};
use proptest::prelude::*;

/// Checks the plan-file rules and the profile's acceleration bound on `tp`.
fn check_limits<const D: usize>(tp: &TimedPath<D>, vmax: &[f64; D], amax: &[f64; D]) {
    check_speed(tp, vmax);
    check_acceleration(tp, amax);
}

/// The plan checker's rule: t starts at 0, strictly increases, chord speeds ≤ vmax.
fn check_speed<const D: usize>(tp: &TimedPath<D>, vmax: &[f64; D]) {
    assert_eq!(tp.t.len(), tp.q.len());
    assert_eq!(tp.t[0], 0.0);
    for k in 1..tp.t.len() {
        let dt = tp.t[k] - tp.t[k - 1];
        assert!(dt > 0.0, "t strictly increasing at {k}");
        for (i, &v) in vmax.iter().enumerate() {
            let dq = (tp.q[k][i] - tp.q[k - 1][i]).abs();
            assert!(dq / dt <= v, "speed at {k}, joint {i}: {} > {v}", dq / dt);
        }
    }
}

/// Finite-difference acceleration of the chord speeds ≤ amax.
fn check_acceleration<const D: usize>(tp: &TimedPath<D>, amax: &[f64; D]) {
    for k in 1..tp.t.len().saturating_sub(1) {
        let (dt0, dt1) = (tp.t[k] - tp.t[k - 1], tp.t[k + 1] - tp.t[k]);
        for (i, &a) in amax.iter().enumerate() {
            let v0 = (tp.q[k][i] - tp.q[k - 1][i]) / dt0;
            let v1 = (tp.q[k + 1][i] - tp.q[k][i]) / dt1;
            let acc = (v1 - v0).abs() / (0.5 * (dt0 + dt1));
            assert!(
                acc <= a * (1.0 + 1e-6) + 1e-9,
                "accel at {k}, joint {i}: {acc} > {a}"
            );
        }
    }
}

/// Every waypoint of `path` (minus consecutive duplicates) appears in order.
fn visits_waypoints<const D: usize>(tp: &TimedPath<D>, path: &[State<D>]) -> bool {
    let mut it = tp.q.iter();
    path.iter().all(|w| it.any(|q| q == w))
}

#[test]
fn triangular_profile_matches_the_analytic_duration() {
    // 1 rad at v = 1, a = 1: v²/a = 1 ≥ 1, so the peak is never reached; T = 2 √(1/a) = 2 s.
    let tp = time_parameterize(&[[0.0], [1.0]], &[1.0], &[1.0]);
    assert!((tp.duration() - 2.0).abs() < 1e-12);
    assert_eq!(tp.q.last(), Some(&[1.0]));
}

#[test]
fn trapezoidal_profile_matches_the_analytic_duration() {
    // 4 rad at v = 1, a = 1: 1 s ramps (0.5 rad each) and 3 s cruise: T = 5 s.
    let tp = time_parameterize(&[[0.0], [4.0]], &[1.0], &[1.0]);
    assert!((tp.duration() - 5.0).abs() < 1e-12);
    // The cruise segment moves 3 rad in 3 s: exactly at the limit.
    let k =
        tp.t.iter()
            .position(|&t| (t - 1.0).abs() < 1e-12)
            .expect("ramp end sampled");
    assert!((tp.q[k + 1][0] - tp.q[k][0] - 3.0).abs() < 1e-12);
}

#[test]
fn slowest_joint_sets_the_pace_and_joints_arrive_together() {
    let tp = time_parameterize(&[[0.0, 0.0], [4.0, 1.0]], &[1.0, 10.0], &[1.0, 10.0]);
    assert!((tp.duration() - 5.0).abs() < 1e-12);
    for q in &tp.q {
        assert!(
            (q[1] - q[0] / 4.0).abs() < 1e-12,
            "joints stay on the straight line"
        );
    }
}

#[test]
fn duplicates_are_merged_and_degenerate_paths_handled() {
    assert!(time_parameterize::<2>(&[], &[1.0; 2], &[1.0; 2]).is_empty());
    let one = time_parameterize(&[[0.3, 0.1]], &[1.0; 2], &[1.0; 2]);
    assert_eq!((one.t, one.q), (vec![0.0], vec![[0.3, 0.1]]));
    let tp = time_parameterize(&[[0.0], [0.0], [1.0], [1.0]], &[1.0], &[1.0]);
    check_limits(&tp, &[1.0], &[1.0]);
    assert!((tp.duration() - 2.0).abs() < 1e-12);
}

#[test]
fn invalid_limits_are_typed_errors() {
    assert_eq!(
        try_time_parameterize(&[[0.0, 0.0]], &[1.0, 0.0], &[1.0; 2]),
        Err(TimingError::InvalidSpeedLimit {
            joint: 1,
            value: 0.0
        })
    );
    assert!(matches!(
        try_time_parameterize(&[[0.0]], &[1.0], &[f64::NAN]),
        Err(TimingError::InvalidAccelerationLimit { joint: 0, .. })
    ));
    assert_eq!(
        try_time_parameterize(&[[0.0], [f64::INFINITY]], &[1.0], &[1.0]),
        Err(TimingError::NonFiniteState { index: 1 })
    );
}

fn state6() -> impl Strategy<Value = State<6>> {
    prop::array::uniform6(-3.0..3.0f64)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn random_paths_respect_speed_and_acceleration_limits(
        path in prop::collection::vec(state6(), 1..8),
        vmax in prop::array::uniform6(0.05..4.0f64),
        amax in prop::array::uniform6(0.05..20.0f64),
    ) {
        let tp = time_parameterize(&path, &vmax, &amax);
        check_limits(&tp, &vmax, &amax);
        prop_assert_eq!(tp.q.first(), path.first());
        prop_assert_eq!(tp.q.last(), path.last());
        prop_assert!(visits_waypoints(&tp, &path));
    }

    #[test]
    fn tiny_steps_late_in_long_paths_keep_the_speed_rule(
        start in 1e3..1e4f64,
        step in 1e-9..1e-6f64,
    ) {
        // Large times and tiny motions stress the floating-point repair of Δt (finite-
        // difference accelerations are too noisy here to check).
        let path = [[0.0], [start], [start + step], [start + 2.0 * step]];
        let tp = time_parameterize(&path, &[0.7], &[0.3]);
        check_speed(&tp, &[0.7]);
    }
}
