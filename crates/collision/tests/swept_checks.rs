//! Swept checks stand for every state they cover: the range-wise answers equal checking the
//! states one by one, and a certified box holds no state in contact.

use std::f64::consts::FRAC_PI_2;

use nalgebra::{Isometry3, Vector3};
use pregrasp_collision::fixtures::{two_arm_cell, SAMPLE_RANGES};
use pregrasp_collision::{joint_space, ArmValidity, CollisionWorld, ObjectPlacement, WorldState};
use pregrasp_motion::{MotionValidator, State, StateValidator};
use pregrasp_robot::{group_sweep_radii, Gripper2F85, GripperState, Joints, UrModel};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The part's pose: lying 0.5 m in front of the arms, turned by `theta` about its long edge.
fn part_pose(theta: f64) -> Isometry3<f64> {
    Isometry3::translation(0.55, -0.25, 0.001) * Isometry3::rotation(Vector3::new(0.0, -theta, 0.0))
}

/// A random reachable-looking configuration: shoulder up, elbow bent, wrist anywhere.
fn random_q(rng: &mut ChaCha8Rng) -> Joints {
    SAMPLE_RANGES.map(|(lo, hi)| rng.random_range(lo..hi))
}

/// A random state of arm 0 holding a closed gripper, arm 1 anywhere with an open one, the part
/// lying (or, three times in ten, held 0.2 m out of arm 0's flange), arm 0 grasping or not.
fn random_state(rng: &mut ChaCha8Rng) -> WorldState {
    let other = random_q(rng);
    let q = random_q(rng);
    let attached = rng.random_bool(0.3);
    WorldState {
        q: [q, other],
        gripper: [GripperState::at_gap(0.02), GripperState::Open],
        object: if attached {
            ObjectPlacement::Attached {
                arm: 0,
                flange_to_object: Isometry3::translation(0.0, 0.0, 0.2),
            }
        } else {
            ObjectPlacement::Fixed(part_pose(0.2))
        },
        grasping: [rng.random_bool(0.5), false],
    }
}

/// A random motion of arm 0 (a few straight joint-space legs cut into steps of `step` rad at
/// most), arm 1 still, the part turning by up to 20° along it, grasp flags and grippers
/// changing at a few places.
fn random_motion(rng: &mut ChaCha8Rng, step: f64) -> Vec<WorldState> {
    let other = random_q(rng);
    let mut q = random_q(rng);
    let mut states = Vec::new();
    let legs = rng.random_range(1..4);
    let turn = rng.random_range(0.0..0.35);
    let mut grasping = [rng.random_bool(0.5), false];
    let mut gripper = [GripperState::Open; 2];
    for _ in 0..legs {
        let to: Joints = std::array::from_fn(|j| q[j] + rng.random_range(-0.6..0.6));
        let longest = (0..6).map(|j| (to[j] - q[j]).abs()).fold(0.0, f64::max);
        let n = ((longest / step).ceil() as usize).max(1);
        if rng.random_bool(0.3) {
            grasping[0] = !grasping[0];
            gripper[0] = if grasping[0] {
                GripperState::at_gap(0.02)
            } else {
                GripperState::Open
            };
        }
        for k in 0..n {
            let f = k as f64 / n as f64;
            let qk: Joints = std::array::from_fn(|j| q[j] + f * (to[j] - q[j]));
            let theta = turn * states.len() as f64 / 600.0;
            states.push(WorldState {
                q: [qk, other],
                gripper,
                object: ObjectPlacement::Fixed(part_pose(theta)),
                grasping,
            });
        }
        q = to;
    }
    states
}

#[test]
fn a_motion_checked_by_ranges_finds_the_state_checking_one_by_one_finds() {
    let world = two_arm_cell();
    let mut rng = ChaCha8Rng::seed_from_u64(20);
    let (mut collided, mut clear, mut certified) = (0, 0, 0);
    for _ in 0..300 {
        let step = [0.002, 0.005, 0.01][rng.random_range(0..3)];
        let states = random_motion(&mut rng, step);
        for only in [None, Some(0)] {
            let one_by_one = states.iter().position(|s| match only {
                None => world.check(s).is_err(),
                Some(a) => world.check_arm(a, s).is_err(),
            });
            let by_ranges = world.first_contact_in(only, &states);
            assert_eq!(
                by_ranges,
                one_by_one,
                "{} states, only {only:?}",
                states.len()
            );
            // The one-pass check of a segment finds the same state, and the same closest
            // grasping gripper as the minimum over the states.
            let both = world.check_states(only, &states);
            assert_eq!(both.first_contact, one_by_one);
            for arm in 0..2 {
                let brute = states
                    .iter()
                    .filter(|s| s.grasping[arm])
                    .map(|s| world.gripper_support_distance(arm, s))
                    .reduce(f64::min);
                assert_eq!(both.closest_grasp[arm], brute, "arm {arm}");
            }
            match one_by_one {
                Some(k) if k > 20 => collided += 1,
                Some(_) => {}
                None => clear += 1,
            }
            certified += usize::from(by_ranges.is_none_or(|k| k > 20));
        }
    }
    // The property must have been exercised on both kinds of motion.
    assert!(
        collided > 20 && clear > 20,
        "{collided} collided, {clear} clear"
    );
    assert!(certified > 40);
}

#[test]
fn a_motion_with_wide_steps_is_checked_state_by_state_and_gives_the_same_answer() {
    // Steps far wider than any swept check would take (0.3–1 rad): every state is checked
    // on its own, and the answer is still the first state in contact.
    let world = two_arm_cell();
    let mut rng = ChaCha8Rng::seed_from_u64(24);
    for _ in 0..40 {
        let step = rng.random_range(0.3..1.0);
        let states = random_motion(&mut rng, step);
        let one_by_one = states.iter().position(|s| world.check(s).is_err());
        assert_eq!(world.first_contact_in(None, &states), one_by_one);
    }
}

#[test]
fn the_closest_grasp_to_the_support_is_the_minimum_over_the_states() {
    let world = two_arm_cell();
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    let mut seen = 0;
    for _ in 0..200 {
        let states = random_motion(&mut rng, 0.005);
        let brute = states
            .iter()
            .filter(|s| s.grasping[0])
            .map(|s| world.gripper_support_distance(0, s))
            .fold(None, |m: Option<f64>, d| Some(m.map_or(d, |m| m.min(d))));
        let found = world.closest_grasp_to_support(0, &states);
        assert_eq!(found, brute);
        seen += usize::from(brute.is_some());
    }
    assert!(seen > 50);
}

#[test]
fn a_certified_joint_box_holds_no_state_in_contact() {
    // The widest certified box along a random direction is as tight as the bounds allow: some
    // pair nearly uses up its room there. No state of it, corners included, may be in contact.
    let world = two_arm_cell();
    let mut rng = ChaCha8Rng::seed_from_u64(22);
    let mut certified = 0;
    for _ in 0..150 {
        let state = random_state(&mut rng);
        let q = state.q[0];
        if world.check_arm(0, &state).is_err() {
            continue;
        }
        // Some joints only, so that self-collision pairs decide too.
        let dir: Joints = std::array::from_fn(|_| {
            if rng.random_bool(0.6) {
                rng.random_range(0.1..1.0)
            } else {
                0.0
            }
        });
        let boxed = |r: f64| -> Joints { std::array::from_fn(|j| r * dir[j]) };
        let (mut lo, mut hi) = (0.0, 1.0);
        if world.is_arm_free_within(0, &state, &boxed(hi)) {
            continue;
        }
        for _ in 0..16 {
            let mid = 0.5 * (lo + hi);
            if world.is_arm_free_within(0, &state, &boxed(mid)) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        if lo == 0.0 {
            continue;
        }
        certified += 1;
        let reach = boxed(lo);
        let corner = |bits: u32| -> Joints {
            std::array::from_fn(|j| {
                q[j] + if bits >> j & 1 == 1 {
                    reach[j]
                } else {
                    -reach[j]
                }
            })
        };
        let samples = (0..64u32).map(corner).chain(
            (0..200)
                .map(|_| std::array::from_fn(|j| q[j] + reach[j] * rng.random_range(-1.0..1.0))),
        );
        for x in samples {
            let mut s = state;
            s.q[0] = x;
            assert!(world.check_arm(0, &s).is_ok(), "{s:?} in a certified box");
        }
    }
    assert!(certified > 60, "{certified} boxes");
}

#[test]
fn a_box_names_every_pair_that_may_fail_in_it() {
    // Where a box is not free, the pairs it names are the only ones to ask about at any of its
    // states (and the boxes within it name fewer): checking a state among them gives the full
    // check's answer.
    let world = two_arm_cell();
    let mut rng = ChaCha8Rng::seed_from_u64(24);
    let (mut named, mut free, mut too_many, mut failing) = (0, 0, 0, 0);
    for _ in 0..200 {
        let state = random_state(&mut rng);
        let q = state.q[0];
        let reach: Joints = std::array::from_fn(|_| rng.random_range(0.0..0.08));
        let Some(doubts) = world.is_arm_doubted_within(0, &state, &reach, None) else {
            too_many += 1;
            continue;
        };
        if doubts.is_empty() {
            free += 1;
            assert!(world.is_arm_free_within(0, &state, &reach));
            continue;
        }
        named += 1;
        // A box within it, about another centre, asked about its doubts only.
        let half: Joints = std::array::from_fn(|j| 0.5 * reach[j]);
        let mut inner = state;
        inner.q[0] = std::array::from_fn(|j| q[j] + half[j] * rng.random_range(-1.0..1.0));
        let fewer = world.is_arm_doubted_within(0, &inner, &half, Some(&doubts));
        let fewer = fewer.expect("never more than it was asked about");
        assert!(fewer.as_slice().iter().all(|c| doubts.contains(*c)));
        for _ in 0..40 {
            let mut s = state;
            s.q[0] = std::array::from_fn(|j| q[j] + reach[j] * rng.random_range(-1.0..1.0));
            let full = world.check_arm(0, &s).is_ok();
            failing += usize::from(!full);
            assert_eq!(world.is_free_among(&s, &doubts), full, "{s:?}");
            let mut t = inner;
            t.q[0] = std::array::from_fn(|j| inner.q[0][j] + half[j] * rng.random_range(-1.0..1.0));
            let full = world.check_arm(0, &t).is_ok();
            assert_eq!(world.is_free_among(&t, &fewer), full, "{t:?}");
        }
    }
    assert!(
        named > 60 && free > 20 && failing > 300,
        "{named} named, {free} free, {too_many} too many, {failing} failing states"
    );
}

#[test]
fn edges_checked_by_boxes_agree_with_edges_checked_state_by_state() {
    let world = two_arm_cell();
    let space = joint_space(&world.arms()[0]);
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let (mut valid, mut invalid) = (0, 0);
    for _ in 0..300 {
        let base = WorldState {
            q: [[0.0; 6], random_q(&mut rng)],
            gripper: [GripperState::Open; 2],
            object: ObjectPlacement::Fixed(part_pose(0.0)),
            grasping: [false; 2],
        };
        let boxes = ArmValidity::new(&world, 0, base);
        // The same states without the box certificate: checked one by one.
        let states = |q: &State<6>| boxes.is_valid(q);
        let a = random_q(&mut rng);
        if !boxes.is_valid(&a) {
            continue;
        }
        let b: Joints = std::array::from_fn(|j| a[j] + rng.random_range(-0.8..0.8));
        for resolution in [0.005, 0.01] {
            let by_boxes = MotionValidator::new(&space, &boxes, resolution).check_edge(&a, &b);
            let one_by_one = MotionValidator::new(&space, &states, resolution).check_edge(&a, &b);
            assert_eq!(by_boxes, one_by_one, "{a:?} → {b:?} at {resolution}");
            if by_boxes {
                valid += 1;
            } else {
                invalid += 1;
            }
        }
    }
    assert!(
        valid > 50 && invalid > 50,
        "{valid} valid, {invalid} invalid"
    );
}

#[test]
fn a_base_joint_turn_is_not_vertical_motion() {
    // One arm over the bare table, its gripper pointing down a few centimetres above it:
    // turning the base about the vertical brings nothing nearer the support, so a box in the
    // base joint whose gripper sweep exceeds that height is still certified; the same sweep
    // from the shoulder joint is not.
    let arm = two_arm_cell().arms()[0].clone();
    let world = CollisionWorld::single_arm(Some(0.0), None, arm)
        .unwrap()
        .with_margin(0.008);
    let mut q: Joints = [0.0, -1.2, 2.0, -2.37, -FRAC_PI_2, 0.0];
    let height = |q: &Joints| world.gripper_support_distance(0, &WorldState::new([*q, *q]));
    while height(&q) > 0.04 {
        q[1] += 0.002;
    }
    while height(&q) < 0.025 {
        q[1] -= 0.002;
    }
    let h = height(&q);
    let state = WorldState::new([q, q]);
    assert!(world.check(&state).is_ok());
    let radii = group_sweep_radii(UrModel::Ur5e, &Gripper2F85::default().into());
    let pan = 0.06;
    let sweep = radii[0][7] * pan;
    assert!(
        sweep > h,
        "the gripper may sweep {sweep} m, more than its height {h} m"
    );
    assert!(world.is_arm_free_within(0, &state, &[pan, 0.0, 0.0, 0.0, 0.0, 0.0]));
    let lift = sweep / radii[1][7];
    assert!(!world.is_arm_free_within(0, &state, &[0.0, lift, 0.0, 0.0, 0.0, 0.0]));
}
