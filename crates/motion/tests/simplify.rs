mod common;

use common::*;
use pregrasp_motion::simplify::{
    greedy_shortcut, partial_shortcut, random_shortcut, remove_waypoints,
};
use pregrasp_motion::{
    rest_to_rest_duration, rrt_connect, simplify, simplify_by, time_parameterize, MotionValidator,
    PathCost, PlanStatus, RestToRest, RrtConnectSettings, State,
};

fn raw_path(seed: u64) -> Vec<State<6>> {
    let space = cube6();
    let v = narrow_passage6;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let s = RrtConnectSettings {
        max_iterations: 5000,
        max_time: None,
        range: 0.3,
        seed,
        simplify: false,
    };
    let r = rrt_connect(&space, &mv, &START6, &GOAL6, &s);
    assert_eq!(r.status, PlanStatus::Solved);
    r.path
}

#[test]
fn simplification_keeps_paths_valid_and_never_longer() {
    let space = cube6();
    let v = narrow_passage6;
    let mv = MotionValidator::new(&space, &v, 0.01);
    for seed in 0..25 {
        let raw = raw_path(seed);
        assert!(mv.check_path(&raw));
        let before = space.path_length(&raw);
        let out = simplify(&mv, &raw, seed ^ 0xABCD, 100);
        assert!(mv.check_path(&out), "seed {seed}");
        assert_eq!(out.first(), raw.first());
        assert_eq!(out.last(), raw.last());
        assert!(out.len() <= raw.len());
        assert!(space.path_length(&out) <= before + 1e-12, "seed {seed}");
        // Each stage on its own is monotone too.
        let g = greedy_shortcut(&mv, &raw);
        assert!(mv.check_path(&g) && space.path_length(&g) <= before + 1e-12);
        let mut r = raw.clone();
        random_shortcut(&mv, &mut r, seed, 100, &space);
        assert!(mv.check_path(&r) && space.path_length(&r) <= before + 1e-12);
        let mut p = raw.clone();
        partial_shortcut(&mv, &mut p, seed, 100, &space);
        assert!(mv.check_path(&p) && space.path_length(&p) <= before + 1e-12);
        let mut w = raw.clone();
        remove_waypoints(&mv, &mut w);
        assert!(mv.check_path(&w) && space.path_length(&w) <= before + 1e-12);
    }
}

/// Limits that make the joints differ: the slowest joint sets each edge's pace.
const LIMITS: RestToRest<6> = RestToRest {
    vmax: [1.0, 0.8, 1.2, 2.0, 2.0, 3.0],
    amax: [2.0, 1.5, 3.0, 4.0, 4.0, 6.0],
};

#[test]
fn rest_to_rest_cost_is_the_timed_duration() {
    let space = cube6();
    for seed in 0..5 {
        let raw = raw_path(seed);
        let timed = time_parameterize(&raw, &LIMITS.vmax, &LIMITS.amax);
        let summed = LIMITS.path(&raw);
        assert!(
            (timed.duration() - summed).abs() <= 1e-9 * summed,
            "seed {seed}"
        );
        for w in raw.windows(2) {
            // The triangle inequality the greedy pass and waypoint removal rely on.
            let mid = space.interpolate(&w[0], &w[1], 0.37);
            let through = LIMITS.edge(&w[0], &mid) + LIMITS.edge(&mid, &w[1]);
            assert!(LIMITS.edge(&w[0], &w[1]) <= through + 1e-12);
        }
    }
    assert_eq!(
        rest_to_rest_duration(&[0.0; 2], &[0.0; 2], &[1.0; 2], &[1.0; 2]),
        0.0
    );
}

#[test]
fn simplification_by_duration_keeps_paths_valid_and_never_slower() {
    let space = cube6();
    let v = narrow_passage6;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let mut faster = 0;
    for seed in 0..25 {
        let raw = raw_path(seed);
        let before = time_parameterize(&raw, &LIMITS.vmax, &LIMITS.amax).duration();
        let out = simplify_by(&mv, &raw, seed, 16, &LIMITS);
        assert!(mv.check_path(&out), "seed {seed}");
        assert_eq!((out.first(), out.last()), (raw.first(), raw.last()));
        let after = time_parameterize(&out, &LIMITS.vmax, &LIMITS.amax).duration();
        assert!(
            after <= before * (1.0 + 1e-9),
            "seed {seed}: {after} > {before}"
        );
        // The shortcut rounds themselves never slow it down either.
        let g = greedy_shortcut(&mv, &raw);
        let mut r = g.clone();
        random_shortcut(&mv, &mut r, seed, 16, &LIMITS);
        assert!(mv.check_path(&r) && LIMITS.path(&r) <= LIMITS.path(&g) * (1.0 + 1e-9));
        faster += usize::from(after < 0.9 * before);
    }
    assert!(
        faster >= 20,
        "only {faster} of 25 RRT paths got 10 % faster"
    );
}

#[test]
fn simplification_is_deterministic_for_a_seed() {
    let space = cube6();
    let v = narrow_passage6;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let raw = raw_path(4);
    assert_eq!(simplify(&mv, &raw, 9, 50), simplify(&mv, &raw, 9, 50));
}

#[test]
fn collinear_waypoints_in_free_space_collapse_to_one_edge() {
    let space = plane();
    let v = |_: &State<2>| true;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let path: Vec<State<2>> = (0..=10).map(|k| [-0.5 + 0.1 * k as f64, 0.2]).collect();
    assert_eq!(simplify(&mv, &path, 0, 10), vec![path[0], path[10]]);
    // A detour in free space becomes the straight edge.
    let detour = vec![[-0.5, -0.5], [0.9, 0.9], [0.5, 0.5]];
    assert_eq!(
        simplify(&mv, &detour, 0, 10),
        vec![[-0.5, -0.5], [0.5, 0.5]]
    );
}

#[test]
fn needed_corner_is_kept() {
    let space = plane();
    let v = wall_with_gap;
    let mv = MotionValidator::new(&space, &v, 0.005);
    let path = vec![[-0.8, 0.55], [0.2, 0.55], [0.8, -0.8]];
    assert!(mv.check_path(&path));
    let out = simplify(&mv, &path, 1, 50);
    assert!(out.len() >= 3, "the wall forces a corner: {out:?}");
    assert!(mv.check_path(&out));
    assert!(space.path_length(&out) <= space.path_length(&path));
}

#[test]
fn short_paths_are_returned_unchanged() {
    let space = plane();
    let v = |_: &State<2>| true;
    let mv = MotionValidator::new(&space, &v, 0.01);
    assert_eq!(
        simplify(&mv, &[[0.0, 0.0], [0.5, 0.5]], 0, 10),
        vec![[0.0, 0.0], [0.5, 0.5]]
    );
    assert!(simplify(&mv, &[], 0, 10).is_empty());
}

#[test]
fn partial_shortcut_straightens_a_wandering_joint() {
    // Joint 1 wiggles while joint 0 advances; only joint 1 can be straightened.
    let space = plane();
    let v = |_: &State<2>| true;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let path: Vec<State<2>> = (0..=8)
        .map(|k| [-0.8 + 0.2 * k as f64, if k % 2 == 0 { 0.0 } else { 0.3 }])
        .collect();
    let mut p = path.clone();
    partial_shortcut(&mv, &mut p, 5, 200, &space);
    let before = space.path_length(&path);
    let after = space.path_length(&p);
    assert!(after < 0.75 * before, "{after} vs {before}");
    assert_eq!((p.first(), p.last()), (path.first(), path.last()));
}
