mod common;

use common::*;
use pregrasp_motion::simplify::{
    greedy_shortcut, partial_shortcut, random_shortcut, remove_waypoints,
};
use pregrasp_motion::{
    rrt_connect, simplify, MotionValidator, PlanStatus, RrtConnectSettings, State,
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
        random_shortcut(&mv, &mut r, seed, 100);
        assert!(mv.check_path(&r) && space.path_length(&r) <= before + 1e-12);
        let mut p = raw.clone();
        partial_shortcut(&mv, &mut p, seed, 100);
        assert!(mv.check_path(&p) && space.path_length(&p) <= before + 1e-12);
        let mut w = raw.clone();
        remove_waypoints(&mv, &mut w);
        assert!(mv.check_path(&w) && space.path_length(&w) <= before + 1e-12);
    }
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
    partial_shortcut(&mv, &mut p, 5, 200);
    let before = space.path_length(&path);
    let after = space.path_length(&p);
    assert!(after < 0.75 * before, "{after} vs {before}");
    assert_eq!((p.first(), p.last()), (path.first(), path.last()));
}
