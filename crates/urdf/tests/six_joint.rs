//! URDF arms as the planner drives them (`SixJointArm`): the FR3 with its elbow joint held,
//! the xArm6 as it is, the UR5e description against the built-in UR5e. The frames keep the
//! trait's promises, the flange is the chain's tool pose, inverse kinematics round-trips.

mod common;

use common::{dist, fr3, random_q, rng, ur5e, xarm6};
use pregrasp_robot::{ArmKinematics, Joints, UrKinematics, UrModel};
use pregrasp_urdf::{SerialChain, SixJointArm, UrdfError};

/// The FR3 with `fr3_joint3` (the elbow's twist, the usual redundancy joint) held at 0.
fn fr3_six() -> SixJointArm {
    SixJointArm::new("fr3", &fr3(), &[("fr3_joint3", 0.0)]).unwrap()
}

fn array(q: &[f64]) -> Joints {
    std::array::from_fn(|i| q[i])
}

/// Random six-joint vectors within the arm's limits (`margin` inside).
fn samples(arm: &SixJointArm, n: usize, seed: u64) -> Vec<Joints> {
    let mut r = rng(seed);
    (0..n)
        .map(|_| array(&random_q(arm.chain(), &mut r, 0.05)))
        .collect()
}

/// [`samples`] away from singularities: σ_min(J) ≥ 0.05 (where a small motion of the flange
/// needs a small motion of the joints, so a branch is followed without doubt).
fn regular_samples(arm: &SixJointArm, n: usize, seed: u64) -> Vec<Joints> {
    let mut r = rng(seed);
    let mut out = Vec::new();
    while out.len() < n {
        let q = random_q(arm.chain(), &mut r, 0.05);
        if arm
            .chain()
            .jacobian(&q)
            .svd(false, false)
            .singular_values
            .min()
            >= 0.05
        {
            out.push(array(&q));
        }
    }
    out
}

#[test]
fn held_joint_leaves_the_tool_pose_unchanged() {
    let full = fr3();
    let arm = fr3_six();
    assert_eq!(arm.chain().dof(), 6);
    for q in samples(&arm, 200, 1) {
        let q7 = arm.full_joints(&q);
        assert_eq!(q7.len(), 7);
        assert_eq!(q7[2], 0.0);
        let (dp, dr) = dist(&full.fk(&q7), &arm.fk(&q));
        assert!(dp < 1e-12 && dr < 1e-12, "{dp} {dr}");
        // The links too: every link frame of the full chain equals the held chain's.
        let a = full.link_frames(&q7);
        let b = arm.chain().link_frames(&q);
        for (x, y) in a.iter().zip(&b) {
            let (dp, dr) = dist(x, y);
            assert!(dp < 1e-12 && dr < 1e-12);
        }
    }
}

/// Frame 6 is the flange; frame i moves only with joints 1..=i; the origins of frames i and
/// i + 1 are `frame_offsets()[i]` apart at every joint vector.
fn frames_keep_their_promises(arm: &dyn ArmKinematics, qs: &[Joints]) {
    let offsets = arm.frame_offsets();
    for q in qs {
        let f = arm.fk_frames(q);
        let (dp, dr) = dist(&f[6], &arm.fk(q));
        assert!(dp < 1e-12 && dr < 1e-12);
        // The chain steps compose to the same frames.
        for (a, b) in f
            .iter()
            .zip(&pregrasp_robot::chain_frames(&arm.chain_steps(), q))
        {
            let (dp, dr) = dist(a, b);
            assert!(dp < 1e-12 && dr < 1e-12, "{}", arm.name());
        }
        for i in 0..6 {
            let d = (f[i + 1].translation.vector - f[i].translation.vector).norm();
            assert!((d - offsets[i]).abs() < 1e-12, "{}: joint {i}", arm.name());
            // Turning joints i+1.. leaves frame i where it is.
            let mut moved = *q;
            for v in moved.iter_mut().skip(i) {
                *v += 0.4;
            }
            let g = arm.fk_frames(&moved);
            let (dp, dr) = dist(&f[i], &g[i]);
            assert!(dp < 1e-12 && dr < 1e-12, "{}: frame {i} moved", arm.name());
            // Turning joint i+1 alone leaves frame i+1's origin on the sphere about frame
            // i's origin, and frame i's origin on joint i+1's axis: it does not move.
            let mut turned = *q;
            turned[i] += 0.7;
            let h = arm.fk_frames(&turned);
            assert!((h[i].translation.vector - f[i].translation.vector).norm() < 1e-12);
        }
    }
}

#[test]
fn fr3_and_xarm6_frames() {
    let arm = fr3_six();
    frames_keep_their_promises(&arm, &samples(&arm, 100, 2));
    let x = SixJointArm::new("xarm6", &xarm6(), &[]).unwrap();
    frames_keep_their_promises(&x, &samples(&x, 100, 3));
}

/// The UR5e description as a six-joint arm has the built-in UR5e's frame offsets and flange
/// (the description's base is turned half a turn about z from the controller's Base frame).
#[test]
fn ur5e_description_matches_the_built_in_arm() {
    let arm = SixJointArm::new("ur5e", &ur5e(), &[]).unwrap();
    let kin = UrKinematics::new(UrModel::Ur5e);
    for q in samples(&arm, 50, 4) {
        let base_turn =
            nalgebra::Isometry3::rotation(nalgebra::Vector3::z() * std::f64::consts::PI);
        let (dp, dr) = dist(&(base_turn * ArmKinematics::fk(&kin, &q)), &arm.fk(&q));
        assert!(dp < 1e-9 && dr < 1e-9, "{dp} {dr}");
    }
}

/// IK round trips: the flange pose of a random joint vector is solved back within 1e-6
/// (m and rad), the solution within the limits, and `ik_nearest` from a nearby seed returns
/// the same branch.
fn round_trips(arm: &SixJointArm, n: usize, seed: u64) {
    let limits = arm.joint_limits();
    let mut failures = 0;
    for q in regular_samples(arm, n, seed) {
        let target = arm.fk(&q);
        let seed_q: Joints = std::array::from_fn(|i| q[i] + 0.01);
        let sols = arm.ik(&target, &seed_q);
        let Some(first) = sols.first() else {
            failures += 1;
            continue;
        };
        for s in &sols {
            let (dp, dr) = dist(&arm.fk(s), &target);
            assert!(dp < 1e-6 && dr < 1e-6);
            assert!(s
                .iter()
                .zip(&limits)
                .all(|(v, (lo, hi))| *v >= *lo && *v <= *hi));
        }
        let Some(near) = arm.ik_nearest(&target, &seed_q) else {
            eprintln!("{}: ik_nearest failed at q = {q:?}", arm.name());
            failures += 1;
            continue;
        };
        let (dp, dr) = dist(&arm.fk(&near), &target);
        assert!(dp < 1e-6 && dr < 1e-6);
        let step = near
            .iter()
            .zip(&q)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        if step > 1e-6 {
            eprintln!(
                "{}: ik_nearest left the branch by {step} at q = {q:?} -> {near:?}",
                arm.name()
            );
            failures += 1;
        }
        let _ = first;
    }
    assert_eq!(
        failures,
        0,
        "{}: {failures} of {n} poses unsolved",
        arm.name()
    );
}

#[test]
fn fr3_held_elbow_ik_round_trips() {
    round_trips(&fr3_six(), 1000, 5);
}

#[test]
fn xarm6_ik_round_trips() {
    round_trips(&SixJointArm::new("xarm6", &xarm6(), &[]).unwrap(), 1000, 6);
}

#[test]
fn seven_joints_unheld_are_refused_with_a_hint() {
    let err = SixJointArm::new("fr3", &fr3(), &[]).unwrap_err();
    let msg = err.to_string();
    assert!(
        matches!(err, UrdfError::NotSixJoints { dof: 7, .. }),
        "{msg}"
    );
    assert!(
        msg.contains("fr3_joint1") && msg.contains("hold one joint"),
        "{msg}"
    );
    let err = SixJointArm::new("fr3", &fr3(), &[("fr3_joint9", 0.0)]).unwrap_err();
    assert!(err.to_string().contains("`fr3_joint9`"), "{err}");
    let err = SixJointArm::new("fr3", &fr3(), &[("fr3_joint4", 0.5)]).unwrap_err();
    assert!(err.to_string().contains("outside its limits"), "{err}");
}

/// Holding every joint but one of a chain leaves a one-joint chain whose tool pose is the
/// full chain's.
#[test]
fn holding_keeps_fk_for_any_subset() {
    let full: SerialChain = fr3();
    let names = full.joint_names();
    let mut r = rng(7);
    for k in 0..names.len() {
        let q = random_q(&full, &mut r, 0.05);
        let held: Vec<(&str, f64)> = (0..names.len())
            .filter(|&i| i != k)
            .map(|i| (names[i], q[i]))
            .collect();
        let one = full.with_held(&held).unwrap();
        assert_eq!(one.dof(), 1);
        let (dp, dr) = dist(&one.fk(&[q[k]]), &full.fk(&q));
        assert!(dp < 1e-12 && dr < 1e-12);
    }
}
