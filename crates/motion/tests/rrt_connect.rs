mod common;

use common::*;
use pregrasp_motion::{
    rrt_connect, rrt_connect_until, MotionValidator, PlanStatus, RrtConnectSettings, State,
};

fn settings(seed: u64) -> RrtConnectSettings {
    RrtConnectSettings {
        max_iterations: 20_000,
        max_time: None,
        range: 0.3,
        seed,
        simplify: true,
    }
}

#[test]
fn same_seed_same_path_bit_for_bit() {
    let space = cube6();
    let v = narrow_passage6;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let a = rrt_connect(&space, &mv, &START6, &GOAL6, &settings(11));
    let b = rrt_connect(&space, &mv, &START6, &GOAL6, &settings(11));
    assert_eq!(a.status, PlanStatus::Solved);
    let bits = |p: &[State<6>]| {
        p.iter()
            .flat_map(|q| q.map(f64::to_bits))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&a.path), bits(&b.path));
    assert_eq!(a.stats.iterations, b.stats.iterations);
    assert_eq!(a.stats.states_checked, b.stats.states_checked);
    // Different seeds explore differently (not required to, but they do here).
    let c = rrt_connect(
        &space,
        &mv,
        &START6,
        &GOAL6,
        &RrtConnectSettings {
            simplify: false,
            ..settings(12)
        },
    );
    let d = rrt_connect(
        &space,
        &mv,
        &START6,
        &GOAL6,
        &RrtConnectSettings {
            simplify: false,
            ..settings(13)
        },
    );
    assert_eq!(c.status, PlanStatus::Solved);
    assert_ne!(bits(&c.path), bits(&d.path));
}

/// A stop condition that never holds changes nothing; one that holds after `k` iterations ends
/// the search there with `Stopped`, not a path.
#[test]
fn a_search_stops_where_its_caller_says() {
    let space = cube6();
    let v = narrow_passage6;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let plain = rrt_connect(&space, &mv, &START6, &GOAL6, &settings(11));
    let never = rrt_connect_until(&space, &mv, &START6, &GOAL6, &settings(11), &|| false);
    assert_eq!(plain.status, PlanStatus::Solved);
    assert!(plain.stats.iterations > 3, "the passage needs a search");
    assert_eq!((never.status, never.path), (plain.status, plain.path));
    assert_eq!(never.stats.iterations, plain.stats.iterations);

    let asked = std::cell::Cell::new(0);
    let stop = || {
        asked.set(asked.get() + 1);
        asked.get() > 3
    };
    let stopped = rrt_connect_until(&space, &mv, &START6, &GOAL6, &settings(11), &stop);
    assert_eq!(stopped.status, PlanStatus::Stopped);
    assert!(stopped.path.is_empty());
    assert_eq!(stopped.stats.iterations, 3);
}

const RES: f64 = 0.01;

#[test]
fn solved_paths_are_valid_at_four_times_finer_resolution() {
    let space = cube6();
    // Plan in the world padded by resolution / w; re-check in the true world.
    let padded = |q: &State<6>| narrow_passage6_padded(q, RES / 0.2);
    let mv = MotionValidator::new(&space, &padded, RES);
    let truth = narrow_passage6;
    let fine = MotionValidator::new(&space, &truth, RES / 4.0);
    for seed in 0..10 {
        for simplify in [false, true] {
            let r = rrt_connect(
                &space,
                &mv,
                &START6,
                &GOAL6,
                &RrtConnectSettings {
                    simplify,
                    ..settings(seed)
                },
            );
            assert_eq!(r.status, PlanStatus::Solved, "seed {seed}");
            assert_eq!(r.path.first(), Some(&START6));
            assert_eq!(r.path.last(), Some(&GOAL6));
            assert!(fine.check_path(&r.path), "seed {seed} simplify {simplify}");
            assert!(r.stats.edges_checked > 0 && r.stats.states_checked >= r.stats.edges_checked);
        }
    }
}

#[test]
fn two_d_gap_is_found_and_passes_through_it() {
    let space = plane();
    let padded = |q: &State<2>| wall_with_gap_padded(q, 0.005);
    let mv = MotionValidator::new(&space, &padded, 0.005);
    let (start, goal) = ([-0.8, -0.8], [0.8, -0.8]);
    let truth = wall_with_gap;
    let fine = MotionValidator::new(&space, &truth, 0.00125);
    for seed in 0..20 {
        let r = rrt_connect(&space, &mv, &start, &goal, &settings(seed));
        assert_eq!(r.status, PlanStatus::Solved);
        assert!(fine.check_path(&r.path));
        // The path must cross x = 0 inside the gap.
        let crossing = r
            .path
            .windows(2)
            .find(|w| w[0][0] < 0.0 && w[1][0] >= 0.0)
            .expect("crosses x = 0");
        let s = -crossing[0][0] / (crossing[1][0] - crossing[0][0]);
        let y = crossing[0][1] + s * (crossing[1][1] - crossing[0][1]);
        assert!(y > 0.5 && y < 0.6, "crossed at y = {y}");
    }
}

#[test]
fn straight_connection_is_tried_first() {
    let space = plane();
    let v = wall_with_gap;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let r = rrt_connect(&space, &mv, &[-0.8, 0.55], &[0.8, 0.55], &settings(0));
    assert_eq!(r.status, PlanStatus::Solved);
    assert_eq!(r.path, vec![[-0.8, 0.55], [0.8, 0.55]]);
    assert_eq!(r.stats.iterations, 0);
    assert_eq!(r.stats.edges_checked, 1);
}

#[test]
fn invalid_start_and_goal_are_reported() {
    let space = plane();
    let v = wall_with_gap;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let inside_wall = [0.0, 0.0];
    let r = rrt_connect(&space, &mv, &inside_wall, &[0.8, 0.0], &settings(0));
    assert_eq!(r.status, PlanStatus::InvalidStart);
    assert!(r.path.is_empty());
    let r = rrt_connect(&space, &mv, &[-0.8, 0.0], &inside_wall, &settings(0));
    assert_eq!(r.status, PlanStatus::InvalidGoal);
    let out_of_bounds = [1.5, 0.0];
    let r = rrt_connect(&space, &mv, &[-0.8, 0.0], &out_of_bounds, &settings(0));
    assert_eq!(r.status, PlanStatus::InvalidGoal);
}

#[test]
fn unreachable_goal_hits_the_iteration_limit() {
    let space = plane();
    let v = closed_room;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let s = RrtConnectSettings {
        max_iterations: 500,
        ..settings(3)
    };
    let r = rrt_connect(&space, &mv, &[-0.8, 0.0], &[0.6, 0.0], &s);
    assert_eq!(r.status, PlanStatus::IterationLimit);
    assert_eq!(r.stats.iterations, 500);
    assert!(r.path.is_empty());
}

#[test]
fn zero_time_limit_times_out() {
    let space = plane();
    let v = closed_room;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let s = RrtConnectSettings {
        max_time: Some(std::time::Duration::ZERO),
        ..settings(3)
    };
    let r = rrt_connect(&space, &mv, &[-0.8, 0.0], &[0.6, 0.0], &s);
    assert_eq!(r.status, PlanStatus::Timeout);
}

#[test]
fn success_rate_and_path_length_over_many_seeds() {
    let space = cube6();
    let v = narrow_passage6;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let lower = narrow_passage6_lower_bound();
    let mut solved = 0;
    let mut total = 0.0;
    for seed in 100..140 {
        let r = rrt_connect(
            &space,
            &mv,
            &START6,
            &GOAL6,
            &RrtConnectSettings {
                max_iterations: 3000,
                ..settings(seed)
            },
        );
        if r.is_solved() {
            solved += 1;
            // Simplified paths through the hole stay close to the analytic bound.
            let len = space.path_length(&r.path);
            assert!(
                len >= lower - 1e-9 && len < 1.4 * lower,
                "seed {seed}: {len} vs {lower}"
            );
            total += len;
        }
    }
    assert!(solved >= 38, "solved {solved}/40");
    let mean = total / solved as f64;
    assert!(
        mean < 1.15 * lower,
        "mean length {mean} vs lower bound {lower}"
    );
}

#[test]
fn a_generous_time_limit_does_not_change_the_result() {
    let space = cube6();
    let v = narrow_passage6;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let none = rrt_connect(&space, &mv, &START6, &GOAL6, &settings(21));
    let limited = RrtConnectSettings {
        max_time: Some(std::time::Duration::from_secs(60)),
        ..settings(21)
    };
    let some = rrt_connect(&space, &mv, &START6, &GOAL6, &limited);
    assert_eq!(none.status, PlanStatus::Solved);
    assert_eq!(none.path, some.path);
    assert_eq!(none.stats.iterations, some.stats.iterations);
}
