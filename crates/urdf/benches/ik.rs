//! IK speed and success on the shipped arms (FR3, xArm6, UR5e).
//!
//! Before the timings, for each arm: the success rate over 1000 random reachable poses (random
//! q within the limits → FK) solved from unrelated random seeds, and the median wall time of
//! one call, for the first solution (`max_solutions = 1`) and for all solutions (32 starts).
//! Criterion then times FK, the first solution, all solutions and one 1° `ik_nearest` step
//! over a fixed set of 64 poses per iteration (divide by 64).

use std::hint::black_box;
use std::time::Instant;

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Isometry3, UnitQuaternion, Vector3};
use pregrasp_urdf::{recognise_ur, IkOptions, SerialChain, UrdfModel};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn chain(file: &str, base: &str, tip: &str) -> SerialChain {
    let path = format!("{}/../../data/robots/{file}", env!("CARGO_MANIFEST_DIR"));
    UrdfModel::from_file(path)
        .unwrap()
        .chain(base, tip)
        .unwrap()
}

fn random_q(c: &SerialChain, r: &mut ChaCha8Rng) -> Vec<f64> {
    c.limits()
        .iter()
        .map(|l| r.random_range(l.lower..l.upper))
        .collect()
}

/// (target, seed) pairs.
fn problems(c: &SerialChain, n: usize) -> Vec<(Isometry3<f64>, Vec<f64>)> {
    let mut r = ChaCha8Rng::seed_from_u64(7);
    (0..n)
        .map(|_| {
            let q = random_q(c, &mut r);
            (c.fk(&q), random_q(c, &mut r))
        })
        .collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn report(name: &str, c: &SerialChain) {
    let first = IkOptions {
        max_solutions: 1,
        ..IkOptions::default()
    };
    let (mut ok_first, mut ok_all, mut t_first, mut t_all, mut count) = (0, 0, vec![], vec![], 0);
    for (target, seed) in problems(c, 1000) {
        let t0 = Instant::now();
        ok_first += usize::from(!c.ik_with(&target, &seed, &first).is_empty());
        t_first.push(t0.elapsed().as_secs_f64() * 1e6);
        let t0 = Instant::now();
        let all = c.ik(&target, &seed);
        t_all.push(t0.elapsed().as_secs_f64() * 1e6);
        ok_all += usize::from(!all.is_empty());
        count += all.len();
    }
    eprintln!(
        "{name}: first solution {ok_first}/1000 solved, median {:.0} µs; all solutions \
         {ok_all}/1000 solved, {:.1} per pose, median {:.0} µs",
        median(t_first),
        count as f64 / 1000.0,
        median(t_all)
    );
}

fn ik(cr: &mut Criterion) {
    let arms = [
        ("fr3", chain("fr3.urdf", "fr3_link0", "fr3_link8")),
        ("xarm6", chain("xarm6.urdf", "link_base", "link_eef")),
        ("ur5e", chain("ur5e.urdf", "base_link", "tool0")),
    ];
    for (name, c) in &arms {
        report(name, c);
    }
    let first = IkOptions {
        max_solutions: 1,
        ..IkOptions::default()
    };
    for (name, c) in &arms {
        let set = problems(c, 64);
        let q0 = vec![0.1; c.dof()];
        cr.bench_function(&format!("fk_{name}"), |b| b.iter(|| c.fk(black_box(&q0))));
        cr.bench_function(&format!("ik_first_x64_{name}"), |b| {
            b.iter(|| {
                for (t, s) in &set {
                    black_box(c.ik_with(t, s, &first));
                }
            })
        });
        cr.bench_function(&format!("ik_all_x64_{name}"), |b| {
            b.iter(|| {
                for (t, s) in &set {
                    black_box(c.ik(t, s));
                }
            })
        });
        // One 1° step: the target turned by 1° about its own z axis, tracked from the pose's q.
        let mut r = ChaCha8Rng::seed_from_u64(8);
        let steps: Vec<(Isometry3<f64>, Vec<f64>)> = (0..64)
            .map(|_| {
                let q = random_q(c, &mut r);
                let t = c.fk(&q);
                let turn = UnitQuaternion::from_axis_angle(
                    &(t.rotation * Vector3::z_axis()),
                    1f64.to_radians(),
                );
                (Isometry3::from_parts(t.translation, turn * t.rotation), q)
            })
            .collect();
        cr.bench_function(&format!("ik_nearest_1deg_x64_{name}"), |b| {
            b.iter(|| {
                for (t, q) in &steps {
                    black_box(c.ik_nearest(t, q));
                }
            })
        });
    }
    let ur = &arms[2].1;
    let m = recognise_ur(ur).unwrap();
    let set = problems(ur, 64);
    cr.bench_function("ik_analytic_via_urdf_x64_ur5e", |b| {
        b.iter(|| {
            for (t, s) in &set {
                black_box(m.ik(t, &s.clone().try_into().unwrap()));
            }
        })
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = ik
}
criterion_main!(benches);
