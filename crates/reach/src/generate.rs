//! Deterministic generator of the shipped problem set `data/reach-ur5-table-boxes.json`.
//!
//! Scene: the arm base at the origin on a table whose top is 5 mm below the base plane,
//! with four boxes on it around the arm. Queries: start and goal drawn uniformly in the
//! joint limits narrowed to `[−π, π]` (seeded ChaCha8, see
//! [`ReachPlanner::query_space`]), kept when both are valid and a generous planning budget
//! connects them (so every shipped query is known feasible).

use nalgebra::{Point3, Vector3};
use pregrasp_robot::UrModel;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::problem::{CuboidSpec, ReachProblemSet, ReachQuery};
use crate::run::{ReachPlanner, ReachSettings};

/// Seed of the shipped problem set.
pub const GENERATOR_SEED: u64 = 20_261_123;

/// The table and four boxes (world frame, m).
pub fn table_boxes_obstacles() -> Vec<CuboidSpec> {
    let cub = |name: &str, c: [f64; 3], h: [f64; 3]| CuboidSpec {
        name: name.to_string(),
        center: Point3::from(c),
        half_extents: Vector3::from(h),
        rpy: [0.0; 3],
    };
    vec![
        cub("table", [0.3, 0.0, -0.03], [0.8, 1.0, 0.025]),
        cub("box_pillar", [0.45, 0.25, 0.2], [0.06, 0.06, 0.2]),
        cub("box_left", [-0.05, 0.5, 0.1], [0.1, 0.08, 0.1]),
        cub("box_back", [-0.45, -0.25, 0.15], [0.08, 0.12, 0.15]),
        cub("box_right", [0.35, -0.45, 0.06], [0.12, 0.1, 0.06]),
    ]
}

/// `n` feasible queries for `model` among [`table_boxes_obstacles`], drawn with `seed`.
///
/// Candidate `k` is kept when its start and goal are valid and RRT-Connect (seed `k`,
/// `check_iterations` iterations, no time limit) solves it.
pub fn generate_table_boxes(
    model: UrModel,
    seed: u64,
    n: usize,
    check_iterations: usize,
) -> ReachProblemSet {
    let mut set = ReachProblemSet {
        model,
        obstacles: table_boxes_obstacles(),
        queries: Vec::new(),
    };
    let mut settings = ReachSettings::default();
    settings.rrt.max_iterations = check_iterations;
    settings.rrt.max_time = None;
    settings.rrt.simplify = false;
    let planner = ReachPlanner::new(&set, settings);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut k = 0u64;
    while set.queries.len() < n {
        let query = ReachQuery {
            start: planner.sample_valid(&mut rng),
            goal: planner.sample_valid(&mut rng),
        };
        if planner.plan(&query, k).is_solved() {
            set.queries.push(query);
        }
        k += 1;
    }
    set
}
