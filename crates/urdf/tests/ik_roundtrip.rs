//! IK round trips at 1000 random reachable poses per arm: random q within the limits → FK →
//! IK from an unrelated random seed → FK back, within 1e-6 m and 1e-6 rad. Also: the
//! numerical solutions of the UR5e against the analytic ones, and determinism.

mod common;

use std::time::Instant;

use common::{dist, fr3, median, random_q, rng, ur5e, xarm6};
use pregrasp_urdf::{joint_distance, recognise_ur, IkOptions, SerialChain};

/// Solves 1000 poses; returns (solved, max position error, max rotation error, median µs).
fn round_trips(name: &str, chain: &SerialChain, seed: u64) -> (usize, f64, f64, f64) {
    let mut r = rng(seed);
    let opts = IkOptions::default();
    let (mut solved, mut wp, mut wr) = (0, 0.0_f64, 0.0_f64);
    let mut times = Vec::new();
    let mut solutions = 0;
    for _ in 0..1000 {
        let q = random_q(chain, &mut r, 0.0);
        let start = random_q(chain, &mut r, 0.0);
        let target = chain.fk(&q);
        let t0 = Instant::now();
        let sols = chain.ik_with(&target, &start, &opts);
        times.push(t0.elapsed().as_secs_f64() * 1e6);
        if !sols.is_empty() {
            solved += 1;
        }
        solutions += sols.len();
        for s in &sols {
            assert!(chain.limits().iter().zip(s).all(|(l, v)| l.contains(*v)));
            let (dp, dr) = dist(&chain.fk(s), &target);
            wp = wp.max(dp);
            wr = wr.max(dr);
        }
        for w in sols.windows(2) {
            assert!(joint_distance(&w[0], &start) <= joint_distance(&w[1], &start));
        }
    }
    let med = median(&mut times);
    eprintln!(
        "{name}: {solved}/1000 solved, {:.1} solutions per pose, max error {wp:.2e} m {wr:.2e} rad, \
         median {med:.0} µs per ik() call (32 starts, this build)",
        solutions as f64 / 1000.0
    );
    (solved, wp, wr, med)
}

#[test]
fn fr3_round_trips() {
    let (solved, wp, wr, _) = round_trips("FR3", &fr3(), 10);
    assert_eq!(solved, 1000);
    assert!(wp < 1e-6 && wr < 1e-6);
}

#[test]
fn xarm6_round_trips() {
    let (solved, wp, wr, _) = round_trips("xArm6", &xarm6(), 11);
    assert_eq!(solved, 1000);
    assert!(wp < 1e-6 && wr < 1e-6);
}

#[test]
fn ur5e_numerical_round_trips() {
    let (solved, wp, wr, _) = round_trips("UR5e numerical", &ur5e(), 12);
    assert_eq!(solved, 1000);
    assert!(wp < 1e-6 && wr < 1e-6);
}

/// Every numerical UR5e solution is one of the analytic ones (mod 2π), and most analytic
/// branches are found.
#[test]
fn ur5e_numerical_solutions_are_analytic_ones() {
    let chain = ur5e();
    let m = recognise_ur(&chain).unwrap();
    let mut r = rng(13);
    let (mut branches, mut found) = (0, 0);
    for _ in 0..200 {
        let q = random_q(&chain, &mut r, 0.0);
        let target = chain.fk(&q);
        let num = chain.ik(&target, &q);
        let raw = m.kinematics().ik_raw(&m.to_flange(&target));
        branches += raw.len();
        found += num.len();
        for n in &num {
            let near = raw.iter().any(|a| {
                a.iter().zip(n).all(|(x, y)| {
                    let d = x - y;
                    (d - std::f64::consts::TAU * (d / std::f64::consts::TAU).round()).abs() < 1e-4
                })
            });
            assert!(
                near,
                "numerical solution {n:?} is no analytic branch of {q:?}"
            );
        }
    }
    eprintln!(
        "UR5e: the numerical ik found {found} of the {branches} analytic branches (200 poses)"
    );
    assert!(found as f64 >= 0.85 * branches as f64, "{found}/{branches}");
}

#[test]
fn ik_is_deterministic_bit_for_bit() {
    for chain in [fr3(), xarm6()] {
        let mut r = rng(14);
        for _ in 0..20 {
            let target = chain.fk(&random_q(&chain, &mut r, 0.0));
            let seed = random_q(&chain, &mut r, 0.0);
            let a = chain.ik(&target, &seed);
            let b = chain.clone().ik(&target, &seed);
            let bits = |v: &Vec<Vec<f64>>| {
                v.iter()
                    .flatten()
                    .map(|x| x.to_bits())
                    .collect::<Vec<u64>>()
            };
            assert!(!a.is_empty());
            assert_eq!(bits(&a), bits(&b));
        }
    }
}

#[test]
fn unreachable_poses_give_no_solution() {
    let chain = xarm6();
    let mut far = chain.fk(&[0.0; 6]);
    far.translation.vector.x += 2.0;
    assert!(chain.ik(&far, &[0.0; 6]).is_empty());
    assert!(chain.ik_nearest(&far, &[0.0; 6]).is_none());
}
