//! Near-singular poses: the wrist singularity (q5 ≈ 0, joints 4 and 6 aligned), the
//! shoulder singularity (`o5 − d4·z1` on the base z axis, the two q1 branches merge) and the
//! stretched elbow (q3 ≈ 0). Solutions must be finite and exact, or absent.

mod common;

use common::{angle_gap, assert_solutions_exact};
use pregrasp_robot::{joint_distance, UrKinematics, UrModel};

#[test]
fn wrist_singularity_solutions_are_exact() {
    for model in UrModel::ALL {
        let kin = UrKinematics::new(model);
        for q5 in [
            0.0,
            1e-15,
            1e-12,
            1e-10,
            1e-9,
            1e-7,
            1e-5,
            1e-3,
            std::f64::consts::PI,
        ] {
            for sign in [1.0, -1.0] {
                let q = [0.4, -1.1, 1.3, -0.7, sign * q5, 0.9];
                let pose = kin.fk(&q);
                let raw = kin.ik_raw(&pose);
                assert!(!raw.is_empty(), "{model} q5={q5}");
                assert_solutions_exact(&kin, raw.as_slice(), &pose);
                // Seeded with q, the continuation keeps q6 and reproduces q.
                let near = kin.ik_nearest(&pose, &q).expect("reachable");
                assert_solutions_exact(&kin, &[near], &pose);
                if q5 > 1e-6 && q5 < 3.0 {
                    assert!(angle_gap(&near, &q) < 1e-6, "{model} q5={q5}: {near:?}");
                } else {
                    // Near the singularity only q4 ± q6 is determined (q4 + q6 at q5 ≈ 0,
                    // q4 − q6 at q5 ≈ π); the other joints are.
                    let s = if q5 < 1.0 { 1.0 } else { -1.0 };
                    let a = [
                        near[0],
                        near[1],
                        near[2],
                        near[3] + s * near[5],
                        near[4],
                        0.0,
                    ];
                    let b = [q[0], q[1], q[2], q[3] + s * q[5], q[4], 0.0];
                    assert!(angle_gap(&a, &b) < 1e-6, "{model} q5={q5}: {near:?}");
                }
                let all = kin.ik(&pose, &q);
                assert_eq!(all[0], near);
            }
        }
    }
}

#[test]
fn exactly_singular_wrist_uses_the_seed_q6() {
    let kin = UrKinematics::new(UrModel::Ur5e);
    let q = [0.4, -1.1, 1.3, -0.7, 0.0, 0.9];
    let pose = kin.fk(&q);
    for q6 in [-2.0, 0.0, 0.5, 2.5] {
        let seed = [0.4, -1.1, 1.3, -0.7, 0.0, q6];
        let near = kin.ik_nearest(&pose, &seed).expect("reachable");
        assert!((near[5] - q6).abs() < 1e-12, "q6 {q6} -> {near:?}");
        assert_solutions_exact(&kin, &[near], &pose);
    }
    // Without a seed, q6 = 0 and q4 absorbs the rotation (q4 + q6 is what matters).
    let raw = kin.ik_raw(&pose);
    assert!(raw.iter().all(|s| s[4].abs() > 1.0 || s[5] == 0.0));
}

/// Configurations with `o5` exactly on the circle of radius d4 about the base axis: the
/// planar x coordinate of o5 in frame 1, `a2 c2 + a3 c23 + d5 sin q234`, is zero.
#[test]
fn shoulder_singularity_solutions_are_exact_or_absent() {
    for model in UrModel::ALL {
        let kin = UrKinematics::new(model);
        let dh = model.dh();
        for (q2, q3) in [
            (-std::f64::consts::FRAC_PI_2, 0.0),
            (-1.3, -0.6),
            (-1.8, 0.5),
        ] {
            let x = dh.a2 * q2.cos() + dh.a3 * (q2 + q3).cos();
            let q234 = (-x / dh.d5).asin();
            for dq in [0.0, 1e-12, 1e-9, 1e-6] {
                let q = [0.7, q2, q3, q234 - q2 - q3 + dq, 1.2, -0.4];
                let pose = kin.fk(&q);
                let raw = kin.ik_raw(&pose);
                assert_solutions_exact(&kin, raw.as_slice(), &pose);
                // The defining configuration itself is always recovered (to the
                // conditioning of the double root, ~sqrt(eps)).
                let best = raw
                    .iter()
                    .map(|s| angle_gap(s, &q))
                    .fold(f64::INFINITY, f64::min);
                assert!(best < 1e-5, "{model} q={q:?}: best gap {best}");
            }
        }
    }
}

#[test]
fn stretched_elbow_solutions_are_exact() {
    for model in UrModel::ALL {
        let kin = UrKinematics::new(model);
        for q3 in [0.0, 1e-12, 1e-8, -1e-8] {
            let q = [-0.3, -0.9, q3, 0.8, -1.4, 2.2];
            let pose = kin.fk(&q);
            let raw = kin.ik_raw(&pose);
            assert_solutions_exact(&kin, raw.as_slice(), &pose);
            let near = kin.ik_nearest(&pose, &q).expect("reachable");
            assert!(
                joint_distance(&near, &q) < 1e-6,
                "{model} q3={q3}: {near:?}"
            );
        }
    }
}
