//! Following a path: the target rotated 30° about a line in 1° steps, tracked with
//! `ik_nearest` (and `ik_follow` for the 7-DoF FR3). Every step must succeed with a small
//! joint change and stay on the starting branch.

mod common;

use common::{dist, fr3, random_q, rng, ur5e, xarm6};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pregrasp_robot::Joints;
use pregrasp_urdf::{joint_distance, recognise_ur, RedundancyOptions, SerialChain};
use rand_chacha::ChaCha8Rng;

/// Largest change of any joint between two consecutive 1° steps (rad). A step moves the
/// target by 1° (0.0175 rad) and at most 0.9 mm; away from singularities (σ_min(J) ≥ 0.05 at
/// the start) the joints move a few hundredths of a radian, a branch change moves some joint
/// by far more than 0.15 rad.
const MAX_STEP_CHANGE: f64 = 0.15;

/// The 31 targets: `fk(q0)` rotated by 0°, 1°, …, 30° about the line through the tool
/// origin shifted 5 cm along the tool x axis, parallel to the tool z axis.
fn path(start: &Isometry3<f64>) -> Vec<Isometry3<f64>> {
    let axis = start.rotation * Vector3::z_axis();
    let centre = start.translation.vector + start.rotation * Vector3::new(0.05, 0.0, 0.0);
    (0..=30)
        .map(|deg| {
            let r = UnitQuaternion::from_axis_angle(&axis, (deg as f64).to_radians());
            let about = Translation3::from(centre)
                * Isometry3::from_parts(Translation3::identity(), r)
                * Translation3::from(-centre);
            about * start
        })
        .collect()
}

/// A start `margin` inside the limits with σ_min(J) ≥ 0.05.
fn good_start(chain: &SerialChain, r: &mut ChaCha8Rng, margin: f64) -> Vec<f64> {
    loop {
        let q = random_q(chain, r, margin);
        let sv = chain.jacobian(&q).svd(false, false).singular_values;
        if sv.min() >= 0.05 {
            return q;
        }
    }
}

/// Tracks the path from `q0`; returns the configurations and the largest per-step change,
/// or `None` when a step fails.
fn follow(
    chain: &SerialChain,
    q0: &[f64],
    step: impl Fn(&Isometry3<f64>, &[f64]) -> Option<Vec<f64>>,
) -> Option<(Vec<Vec<f64>>, f64)> {
    let targets = path(&chain.fk(q0));
    let mut qs = vec![q0.to_vec()];
    let mut worst = 0.0_f64;
    for t in &targets[1..] {
        let prev = qs.last().unwrap();
        let q = step(t, prev)?;
        let (dp, dr) = dist(&chain.fk(&q), t);
        assert!(dp < 1e-6 && dr < 1e-6);
        worst = worst.max(
            q.iter()
                .zip(prev)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max),
        );
        qs.push(q);
    }
    Some((qs, worst))
}

fn check_arm(name: &str, chain: &SerialChain, seed: u64, margin: f64) -> usize {
    let mut r = rng(seed);
    let (mut done, mut worst) = (0, 0.0_f64);
    for _ in 0..20 {
        let q0 = good_start(chain, &mut r, margin);
        let Some((qs, w)) = follow(chain, &q0, |t, prev| chain.ik_nearest(t, prev)) else {
            continue;
        };
        done += 1;
        worst = worst.max(w);
        assert!(w < MAX_STEP_CHANGE, "{name}: a step changed a joint by {w}");
        // Same branch: each step is the solution nearest to the previous one among all the
        // multi-start solver finds.
        for (k, pair) in qs.windows(2).enumerate() {
            let t = chain.fk(&pair[1]);
            let nearest = &chain.ik(&t, &pair[0])[0];
            assert!(
                joint_distance(nearest, &pair[1]) < 1e-6,
                "{name}: step {k} left its branch"
            );
        }
    }
    eprintln!(
        "{name}: {done}/20 paths of 30 × 1° followed, largest joint change per step {worst:.4} rad"
    );
    done
}

#[test]
fn xarm6_follows_a_rotation_without_jumps() {
    assert!(check_arm("xArm6", &xarm6(), 20, 0.3) >= 18);
}

#[test]
fn fr3_follows_a_rotation_without_jumps() {
    assert!(check_arm("FR3", &fr3(), 21, 0.3) >= 18);
}

/// The UR5e tracked numerically stays on the analytic branch: every step equals
/// `UrKinematics::ik_nearest` from the previous step.
#[test]
fn ur5e_tracking_matches_the_analytic_branch() {
    let chain = ur5e();
    let m = recognise_ur(&chain).unwrap();
    let mut r = rng(22);
    let mut done = 0;
    for _ in 0..20 {
        let q0 = good_start(&chain, &mut r, 0.3);
        let Some((qs, w)) = follow(&chain, &q0, |t, prev| chain.ik_nearest(t, prev)) else {
            continue;
        };
        done += 1;
        assert!(w < MAX_STEP_CHANGE, "{w}");
        for pair in qs.windows(2) {
            let prev: Joints = pair[0].clone().try_into().unwrap();
            let analytic = m.ik_nearest(&chain.fk(&pair[1]), &prev).unwrap();
            assert!(joint_distance(&analytic, &pair[1]) < 1e-6);
        }
    }
    eprintln!("UR5e: {done}/20 paths followed on the analytic branch");
    assert!(done >= 18);
}

/// 7-DoF continuity with the redundancy joint (FR3 joint 3, index 2) held: it never moves,
/// the other joints change little per step.
#[test]
fn fr3_follow_holds_the_redundancy_joint() {
    let chain = fr3();
    let mut r = rng(23);
    let (mut done, mut worst) = (0, 0.0_f64);
    for _ in 0..20 {
        let q0 = good_start(&chain, &mut r, 0.3);
        let Some((qs, w)) = follow(&chain, &q0, |t, prev| chain.ik_follow(t, prev, 2)) else {
            continue;
        };
        done += 1;
        worst = worst.max(w);
        assert!(w < MAX_STEP_CHANGE, "{w}");
        assert!(qs.iter().all(|q| q[2] == q0[2]));
    }
    eprintln!("FR3 ik_follow (joint 3 held): {done}/20 paths, largest joint change per step {worst:.4} rad");
    assert!(done >= 15);
}

/// Branches across the self-motion: with joint 3 sampled over 16 values (plus the seed's),
/// the FR3 shows solutions at many values of joint 3 and, at some values, several branches;
/// the seed's own configuration comes first.
#[test]
fn fr3_redundancy_grid_finds_branches() {
    let chain = fr3();
    let mut r = rng(24);
    let opts = RedundancyOptions::new(2);
    let l = chain.limits()[2];
    let grid: Vec<f64> = (0..16)
        .map(|k| l.lower + (k as f64 + 0.5) * (l.upper - l.lower) / 16.0)
        .collect();
    let (mut total, mut values_total, mut multi_branch) = (0, 0, 0);
    for _ in 0..20 {
        let q = random_q(&chain, &mut r, 0.0);
        let target = chain.fk(&q);
        let sols = chain.ik_redundant(&target, &q, &opts);
        assert!(
            joint_distance(&sols[0], &q) < 1e-6,
            "the seed itself comes first"
        );
        for s in &sols {
            let (dp, dr) = dist(&chain.fk(s), &target);
            assert!(dp < 1e-6 && dr < 1e-6);
            assert!(
                s[2] == q[2] || grid.contains(&s[2]),
                "joint 3 held at a grid value"
            );
        }
        let mut values: Vec<f64> = sols.iter().map(|s| s[2]).collect();
        values.sort_by(f64::total_cmp);
        values.dedup();
        total += sols.len();
        values_total += values.len();
        if values.len() < sols.len() {
            multi_branch += 1;
        }
    }
    eprintln!(
        "FR3 ik_redundant: {:.1} solutions per pose at {:.1} of the 17 values of joint 3; \
         {multi_branch}/20 poses with several branches at one value",
        total as f64 / 20.0,
        values_total as f64 / 20.0
    );
    assert!(values_total >= 20 * 8, "{values_total}");
    assert!(multi_branch >= 5, "{multi_branch}");
}
