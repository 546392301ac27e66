//! IK(FK(q)) round trips over many seeded random configurations, and the ordering and
//! limit rules of `ik`.

mod common;

use common::{angle_gap, assert_solutions_exact, pose_error};
use pregrasp_robot::{distinct_solutions, joint_distance, Joints, UrKinematics, UrModel};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_q(rng: &mut ChaCha8Rng, model: UrModel) -> Joints {
    let lim = model.joint_limits();
    std::array::from_fn(|j| rng.random_range(lim[j].0..=lim[j].1))
}

/// 100 000 configurations per model: every raw solution is exact, in (−π, π], distinct, and
/// one of them is q modulo 2π.
#[test]
fn ik_of_fk_contains_q_100k_per_model() {
    for (k, model) in UrModel::ALL.into_iter().enumerate() {
        let kin = UrKinematics::new(model);
        let mut rng = ChaCha8Rng::seed_from_u64(1000 + k as u64);
        let mut histogram = [0usize; 9];
        for _ in 0..100_000 {
            let q = random_q(&mut rng, model);
            let pose = kin.fk(&q);
            let sols = kin.ik_raw(&pose);
            histogram[sols.len()] += 1;
            assert_solutions_exact(&kin, sols.as_slice(), &pose);
            for s in &sols {
                assert!(s
                    .iter()
                    .all(|v| *v > -std::f64::consts::PI && *v <= std::f64::consts::PI));
            }
            let best = sols
                .iter()
                .map(|s| angle_gap(s, &q))
                .fold(f64::INFINITY, f64::min);
            assert!(
                best < 1e-7,
                "{model}: q={q:?} not among {:?}",
                sols.as_slice()
            );
            for (i, a) in sols.iter().enumerate() {
                for b in &sols.as_slice()[i + 1..] {
                    assert!(angle_gap(a, b) > 1e-9, "duplicate solutions {a:?}");
                }
            }
        }
        // Solutions come in pairs (elbow up/down, wrist flip) for generic poses.
        assert_eq!(histogram[0], 0, "{model}: {histogram:?}");
        assert!(
            histogram.iter().skip(1).step_by(2).all(|&n| n == 0),
            "{model}: {histogram:?}"
        );
        // Generic poses give 8: the clear majority of random configurations do.
        assert!(histogram[8] > 50_000, "{model}: {histogram:?}");
    }
}

/// Poses well inside the workspace (wrist near the shoulder height, moderate elbow bend)
/// give all 8 solutions.
#[test]
fn generic_poses_give_eight_solutions() {
    for model in UrModel::ALL {
        let kin = UrKinematics::new(model);
        for q in [
            [0.3, -1.2, 1.4, -0.9, 1.1, 0.4],
            [-2.0, -2.0, 1.2, 0.5, -1.3, 2.0],
            [1.0, -0.8, -1.5, 2.0, 0.7, -1.0],
        ] {
            let pose = kin.fk(&q);
            assert_eq!(kin.ik_raw(&pose).len(), 8, "{model} q={q:?}");
        }
    }
}

#[test]
fn ik_respects_limits_and_sorts_by_distance_to_seed() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for model in UrModel::ALL {
        let kin = UrKinematics::new(model);
        let lim = model.joint_limits();
        for _ in 0..300 {
            let q = random_q(&mut rng, model);
            let seed = random_q(&mut rng, model);
            let pose = kin.fk(&q);
            let all = kin.ik(&pose, &seed);
            // q itself (within limits) must be among the wrapped alternates.
            assert!(
                all.iter().any(|s| joint_distance(s, &q) < 1e-7),
                "{model} q={q:?}"
            );
            assert_solutions_exact(&kin, &all, &pose);
            for s in &all {
                for j in 0..6 {
                    assert!(s[j] >= lim[j].0 && s[j] <= lim[j].1);
                }
            }
            let d: Vec<f64> = all.iter().map(|s| joint_distance(s, &seed)).collect();
            assert!(d.windows(2).all(|w| w[0] <= w[1]));
            // Every raw solution appears with each allowed ±2π alternate: 2 choices per ±2π
            // joint (3 when exactly 0) and 1 for the ±π elbow.
            let raw = kin.ik_raw_with_q6_hint(&pose, seed[5]);
            let expected: usize = raw
                .iter()
                .map(|s| {
                    (0..6)
                        .map(|j| {
                            [
                                s[j] - std::f64::consts::TAU,
                                s[j],
                                s[j] + std::f64::consts::TAU,
                            ]
                            .iter()
                            .filter(|v| **v >= lim[j].0 && **v <= lim[j].1)
                            .count()
                        })
                        .product::<usize>()
                })
                .sum();
            assert_eq!(all.len(), expected);
            assert_eq!(all.len(), raw.len() * 32, "generic: 2^5 alternates each");
            let nearest = kin.ik_nearest(&pose, &seed).expect("reachable");
            assert_eq!(nearest, all[0]);
        }
    }
}

/// `ik_distinct` (each solution's nearest alternate, chosen per joint) is exactly the first
/// variant of each solution in `ik`'s full sorted list, bit for bit — on random seeds, on seeds
/// half a turn from a solution's joint (where two alternates tie), and at the wrist
/// singularity.
#[test]
fn ik_distinct_is_the_first_variant_of_each_solution() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut ties, mut solved) = (0, 0);
    for model in UrModel::ALL {
        let kin = UrKinematics::new(model);
        for i in 0..400 {
            let mut q = random_q(&mut rng, model);
            if i % 10 == 0 {
                q[4] = 0.0; // the wrist singularity
            }
            let pose = kin.fk(&q);
            let mut seed = random_q(&mut rng, model);
            if i % 4 == 1 {
                // Half a turn from a raw solution's joints: the alternates q ± 2π tie.
                let raw = kin.ik_raw_with_q6_hint(&pose, seed[5]);
                if let Some(s) = raw.iter().next() {
                    for j in 0..6 {
                        seed[j] = s[j] + std::f64::consts::PI;
                    }
                    ties += 1;
                }
            }
            let expected = distinct_solutions(kin.ik(&pose, &seed));
            let got = kin.ik_distinct(&pose, &seed);
            let bits =
                |v: &[Joints]| -> Vec<[u64; 6]> { v.iter().map(|q| q.map(f64::to_bits)).collect() };
            assert_eq!(bits(&got), bits(&expected), "{model} q={q:?} seed={seed:?}");
            assert!(got.len() <= 8);
            solved += usize::from(!got.is_empty());
        }
    }
    assert!(
        ties > 400 && solved > 1900,
        "{ties} ties, {solved} solved of 2000"
    );
}

#[test]
fn unreachable_poses_give_no_solution() {
    for model in UrModel::ALL {
        let kin = UrKinematics::new(model);
        let far = nalgebra::Isometry3::translation(3.0 * model.reach(), 0.0, 0.0);
        assert!(kin.ik_raw(&far).is_empty());
        assert!(kin.ik(&far, &[0.0; 6]).is_empty());
        assert!(kin.ik_nearest(&far, &[0.0; 6]).is_none());
        let nan = nalgebra::Isometry3::translation(f64::NAN, 0.0, 0.0);
        assert!(kin.ik_raw(&nan).is_empty());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    /// Randomised subset with shrinking: the seed continuation returns q itself.
    #[test]
    fn ik_nearest_with_seed_q_returns_q(
        q in prop::array::uniform6(-std::f64::consts::PI..std::f64::consts::PI),
        m in 0usize..5,
    ) {
        let model = UrModel::ALL[m];
        let kin = UrKinematics::new(model);
        let pose = kin.fk(&q);
        let got = kin.ik_nearest(&pose, &q).expect("FK pose is reachable");
        prop_assert!(joint_distance(&got, &q) < 1e-6, "got {:?}", got);
        let (dp, dr) = pose_error(&kin.fk(&got), &pose);
        prop_assert!(dp < 1e-9 && dr < 1e-9);
    }
}
