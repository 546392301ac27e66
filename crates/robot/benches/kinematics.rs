//! Kinematics speed: FK of all link frames, FK of the flange, all analytic IK solutions (raw,
//! nearest, every ±2π alternate, one per distinct solution).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use pregrasp_robot::{UrKinematics, UrModel};

fn kinematics(c: &mut Criterion) {
    let kin = UrKinematics::new(UrModel::Ur5e);
    let q = [0.3, -1.2, 1.4, -0.9, 1.1, 0.4];
    let pose = kin.fk(&q);
    assert_eq!(kin.ik_raw(&pose).len(), 8);
    c.bench_function("fk_frames_ur5e", |b| {
        b.iter(|| kin.fk_frames(black_box(&q)))
    });
    c.bench_function("fk_flange_ur5e", |b| b.iter(|| kin.fk(black_box(&q))));
    c.bench_function("ik_raw_8_solutions_ur5e", |b| {
        b.iter(|| kin.ik_raw(black_box(&pose)))
    });
    c.bench_function("ik_nearest_ur5e", |b| {
        b.iter(|| kin.ik_nearest(black_box(&pose), black_box(&q)))
    });
    c.bench_function("ik_all_alternates_ur5e", |b| {
        b.iter(|| kin.ik(black_box(&pose), black_box(&q)))
    });
    c.bench_function("ik_distinct_ur5e", |b| {
        b.iter(|| kin.ik_distinct(black_box(&pose), black_box(&q)))
    });
}

criterion_group!(benches, kinematics);
criterion_main!(benches);
