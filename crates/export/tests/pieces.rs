//! The small pieces every format relies on.

use pregrasp_export::float;
use pregrasp_export::ros2::sec_nanosec;
use pregrasp_export::urscript::{grip_pos, ticks, DT};
use pregrasp_model::timeline::sample_knots;

#[test]
fn floats_round_trip_and_always_have_a_point() {
    for x in [
        0.0,
        1.0,
        -2.0,
        0.1,
        1e-7,
        -2.123456789012345,
        123456.789,
        1e20,
    ] {
        let s = float(x);
        assert!(s.contains('.'), "{s}");
        assert!(!s.contains('e'), "{s}");
        assert_eq!(s.parse::<f64>().unwrap(), x);
    }
}

#[test]
fn ticks_cover_the_interval_with_at_most_one_extra_cycle() {
    for d in [1e-4, 0.002, 0.0021, 0.01, 0.1234567, 1.0, 3.333] {
        let n = ticks(d);
        assert!(n >= 1);
        assert!(n as f64 * DT >= d - 1e-12, "{d}");
        assert!((n as f64 - 1.0) * DT < d, "{d}");
    }
}

#[test]
fn seconds_and_nanoseconds_carry() {
    assert_eq!(sec_nanosec(0.0), (0, 0));
    assert_eq!(sec_nanosec(1.5), (1, 500_000_000));
    assert_eq!(sec_nanosec(1.9999999999), (2, 0));
    assert_eq!(sec_nanosec(2.000000001), (2, 1));
}

#[test]
fn knots_interpolate_linearly_and_hold_outside() {
    let knots = vec![(0.0, [0.0; 6]), (1.0, [1.0; 6]), (3.0, [-1.0; 6])];
    assert_eq!(sample_knots(&knots, -1.0), [0.0; 6]);
    assert_eq!(sample_knots(&knots, 0.5), [0.5; 6]);
    assert_eq!(sample_knots(&knots, 1.0), [1.0; 6]);
    assert_eq!(sample_knots(&knots, 2.0), [0.0; 6]);
    assert_eq!(sample_knots(&knots, 9.0), [-1.0; 6]);
}

#[test]
fn gripper_positions_are_monotone_in_the_gap() {
    let mut last = 255;
    for k in 0..=85 {
        let p = grip_pos(k as f64 * 0.001);
        assert!(p <= last);
        last = p;
    }
    assert_eq!(last, 0);
}
