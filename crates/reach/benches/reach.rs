//! Reach-planner benchmarks.
//!
//! - `reach_query`: RRT-Connect + simplification from a start configuration to a stand-off
//!   above a part on a table (table cuboid and part mesh as obstacles).
//! - `reach_problem_set`: the queries of `data/reach-ur5-table-boxes.json`, one per iteration.
//!
//! Run: `cargo bench -p pregrasp-reach --bench reach -- --warm-up-time 1 --measurement-time 3`.

use std::f64::consts::{FRAC_PI_2, PI};
use std::hint::black_box;
use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::Isometry3;
use pregrasp_collision::fixtures::{plate_10k, stand_off, UP};
use pregrasp_collision::{ArmValidity, CollisionWorld, ObjectPlacement, WorldState};
use pregrasp_motion::StateValidator;
use pregrasp_reach::{ReachPlanner, ReachProblemSet, ReachQuery, ReachSettings};
use pregrasp_robot::UrModel;

fn reach_query(c: &mut Criterion) {
    let set = ReachProblemSet {
        model: UrModel::Ur5e,
        obstacles: vec![pregrasp_reach::table_boxes_obstacles()[0].clone()],
        queries: Vec::new(),
    };
    let plate = plate_10k();
    let arm = set.arm();
    let world = CollisionWorld::single_arm(None, Some(&plate), arm)
        .unwrap()
        .with_obstacle_cuboid(
            "table",
            set.obstacles[0].pose(),
            set.obstacles[0].half_extents,
        );
    let planner = ReachPlanner::for_world(world, ReachSettings::default());
    let mut base = WorldState::new([UP, UP]);
    base.object = ObjectPlacement::Fixed(Isometry3::translation(0.5, 0.0, -0.005));
    let kin = planner.world.arms()[0].kin.clone();
    let validity = ArmValidity::new(&planner.world, 0, base);
    let mut queries = Vec::new();
    for (i, pan) in [FRAC_PI_2, -FRAC_PI_2, 0.0, PI * 0.75].iter().enumerate() {
        let start = [*pan, UP[1], UP[2], UP[3], UP[4], UP[5]];
        for (j, (x, y)) in [(0.4, -0.1), (0.6, 0.12)].iter().enumerate() {
            let goal_pose = stand_off(*x, *y, 0.05, 0.4 * (i + j) as f64);
            // The IK solution nearest to the start that is collision-free at the stand-off.
            let goal = kin
                .ik(&goal_pose, &start)
                .into_iter()
                .find(|q| validity.is_valid(q))
                .expect("stand-off reachable");
            queries.push(ReachQuery { start, goal });
        }
    }
    for (k, q) in queries.iter().enumerate() {
        let r = planner.plan_in(base, q, k as u64);
        eprintln!(
            "reach_query {k}: {:?}, {:.3} ms, {} iterations, {} states checked, {} waypoints",
            r.status,
            r.stats.time.as_secs_f64() * 1e3,
            r.stats.iterations,
            r.stats.states_checked,
            r.path.len()
        );
    }
    let mut k = 0;
    c.bench_function("reach_query", |b| {
        b.iter(|| {
            k = (k + 1) % queries.len();
            black_box(planner.plan_in(base, &queries[k], k as u64))
        })
    });
}

fn reach_problem_set(c: &mut Criterion) {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/reach-ur5-table-boxes.json");
    let set = ReachProblemSet::load(&path).expect("shipped problem set");
    let planner = ReachPlanner::new(&set, ReachSettings::default());
    let mut k = 0;
    c.bench_function("reach_problem_set", |b| {
        b.iter(|| {
            k = (k + 1) % set.queries.len();
            black_box(planner.plan(&set.queries[k], k as u64))
        })
    });
}

criterion_group!(benches, reach_query, reach_problem_set);
criterion_main!(benches);
