//! RRT-Connect on a 6-D narrow-passage toy problem (slab with a small hole), plus the
//! easy case the product hits most (straight connection valid) and simplification.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use pregrasp_motion::{rrt_connect, JointSpace, MotionValidator, RrtConnectSettings, State};

const START: State<6> = [-0.8, -0.5, 0.5, 0.3, -0.2, 0.1];
const GOAL: State<6> = [0.8, -0.4, 0.6, -0.3, 0.4, -0.6];

fn narrow_passage(q: &State<6>) -> bool {
    let in_slab = q[0].abs() < 0.1;
    let in_hole = (q[1] - 0.3).abs() < 0.12 && (q[2] + 0.2).abs() < 0.12;
    !in_slab || in_hole
}

fn bench(c: &mut Criterion) {
    let space = JointSpace::new([-1.0; 6], [1.0; 6], [0.2; 6]).unwrap();
    let v = narrow_passage;
    let mv = MotionValidator::new(&space, &v, 0.01);
    let base = RrtConnectSettings {
        max_iterations: 20_000,
        max_time: None,
        range: 0.3,
        seed: 0,
        simplify: false,
    };

    // Seeds cycle so the median spans many different searches.
    let mut seed = 0u64;
    c.bench_function("rrt_connect_6d_narrow_passage", |b| {
        b.iter(|| {
            seed = seed.wrapping_add(1);
            let r = rrt_connect(
                &space,
                &mv,
                &START,
                &GOAL,
                &RrtConnectSettings {
                    seed,
                    ..base.clone()
                },
            );
            black_box(r.path.len())
        })
    });
    let mut seed = 0u64;
    c.bench_function("rrt_connect_6d_narrow_passage_simplified", |b| {
        b.iter(|| {
            seed = seed.wrapping_add(1);
            let r = rrt_connect(
                &space,
                &mv,
                &START,
                &GOAL,
                &RrtConnectSettings {
                    seed,
                    simplify: true,
                    ..base.clone()
                },
            );
            black_box(r.path.len())
        })
    });
    let free_goal: State<6> = [-0.3, -0.4, 0.6, -0.3, 0.4, -0.6];
    c.bench_function("rrt_connect_6d_straight_line", |b| {
        b.iter(|| {
            black_box(
                rrt_connect(&space, &mv, &START, black_box(&free_goal), &base)
                    .path
                    .len(),
            )
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
