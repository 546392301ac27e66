//! Running a reach problem set: RRT-Connect + simplification per query, timed in process.

use std::time::{Duration, Instant};

use pregrasp_motion::{
    rrt_connect, JointSpace, MotionValidator, PlanResult, PlanStatus, RrtConnectSettings,
};
use pregrasp_robot::Joints;

use crate::problem::{ReachProblemSet, ReachQuery};
use pregrasp_collision::{joint_space, ArmValidity, CollisionWorld, WorldState};

/// Edge resolution (m of arm-point travel between checked states) used by the benchmark.
pub const DEFAULT_RESOLUTION: f64 = 0.01;

/// Safety margin (m) used by the benchmark: half the resolution, so every returned edge is
/// collision-free in continuous motion against the support, obstacles, the part and the
/// other arm (see [`pregrasp_collision::ArmValidity`]). Not the full resolution: the UR5e model keeps its
/// base box and upper-arm tube only ≈ 9 mm apart at some pan angles whatever the other
/// joints do, so a 10 mm margin would cut the pan joint's range into pieces.
pub const DEFAULT_MARGIN: f64 = 0.5 * DEFAULT_RESOLUTION;

/// How each query is planned.
#[derive(Clone, Debug, PartialEq)]
pub struct ReachSettings {
    /// Edge-check resolution (m), see [`pregrasp_collision::ArmValidity`].
    pub resolution: f64,
    /// Safety margin of every collision check (m).
    pub margin: f64,
    /// Planner settings; query `k` uses seed `rrt.seed + k` (so each query is reproducible
    /// on its own). Simplification is part of the measured time when enabled.
    pub rrt: RrtConnectSettings,
}

impl Default for ReachSettings {
    fn default() -> Self {
        ReachSettings {
            resolution: DEFAULT_RESOLUTION,
            margin: DEFAULT_MARGIN,
            rrt: RrtConnectSettings {
                max_iterations: 20_000,
                ..RrtConnectSettings::default()
            },
        }
    }
}

/// A world plus the space and validity of its arm 0, ready to plan queries.
pub struct ReachPlanner {
    pub world: CollisionWorld,
    pub space: JointSpace<6>,
    pub settings: ReachSettings,
}

impl ReachPlanner {
    /// The planner for a problem set's world.
    pub fn new(set: &ReachProblemSet, settings: ReachSettings) -> Self {
        Self::for_world(set.world(), settings)
    }

    /// The planner for arm 0 of any world (the other arm and part held as in a default state),
    /// its geometry prepared for many queries ([`CollisionWorld::prepare`]).
    pub fn for_world(world: CollisionWorld, settings: ReachSettings) -> Self {
        let world = world.with_margin(settings.margin);
        world.prepare();
        let space = joint_space(&world.arms()[0]);
        ReachPlanner {
            world,
            space,
            settings,
        }
    }

    /// Plans one query with seed `seed` for arm 0, everything else as in `base_state`.
    pub fn plan_in(&self, base_state: WorldState, query: &ReachQuery, seed: u64) -> PlanResult<6> {
        let validity = ArmValidity::new(&self.world, 0, base_state);
        let motion = MotionValidator::new(&self.space, &validity, self.settings.resolution);
        let rrt = RrtConnectSettings {
            seed,
            ..self.settings.rrt.clone()
        };
        rrt_connect(&self.space, &motion, &query.start, &query.goal, &rrt)
    }

    /// Plans one query (arm 1 at zero, open grippers, no part).
    pub fn plan(&self, query: &ReachQuery, seed: u64) -> PlanResult<6> {
        self.plan_in(WorldState::new([[0.0; 6]; 2]), query, seed)
    }

    /// The space queries are drawn from: the joint limits narrowed to one turn, `[−π, π]`
    /// per joint. With the full ±2π limits, the shoulder-lift angles that keep the upper arm
    /// above the table form two intervals a turn apart that no collision-free path joins,
    /// so uniformly drawn pairs would be infeasible half of the time.
    pub fn query_space(&self) -> JointSpace<6> {
        let mut s = self.space.clone();
        for i in 0..6 {
            s.lower[i] = s.lower[i].max(-std::f64::consts::PI);
            s.upper[i] = s.upper[i].min(std::f64::consts::PI);
        }
        s
    }

    /// A valid state of arm 0 drawn uniformly from [`query_space`](Self::query_space)
    /// (rejection sampling).
    pub fn sample_valid(&self, rng: &mut impl rand::Rng) -> Joints {
        let space = self.query_space();
        loop {
            let q = space.sample(rng);
            if self.is_valid(&q) {
                return q;
            }
        }
    }

    /// Whether `q` is a valid state of arm 0 (default state for the rest).
    pub fn is_valid(&self, q: &Joints) -> bool {
        use pregrasp_motion::StateValidator;
        ArmValidity::new(&self.world, 0, WorldState::new([[0.0; 6]; 2])).is_valid(q)
    }
}

/// Result of one query.
#[derive(Clone, Debug, PartialEq)]
pub struct QueryOutcome {
    pub status: PlanStatus,
    /// Wall-clock planning time including simplification.
    pub time: Duration,
    /// Waypoints of the returned path (0 unless solved).
    pub waypoints: usize,
    /// Path length in the space's metric (m of arm-point travel bound).
    pub length: f64,
    pub iterations: usize,
    pub states_checked: u64,
}

/// Summary of a problem-set run. Times are over all queries, solved or not.
#[derive(Clone, Debug, PartialEq)]
pub struct ReachReport {
    pub queries: usize,
    pub solved: usize,
    /// `solved / queries`.
    pub success_rate: f64,
    pub median_ms: f64,
    /// 95th percentile (nearest rank).
    pub p95_ms: f64,
    pub mean_ms: f64,
    pub max_ms: f64,
    pub outcomes: Vec<QueryOutcome>,
}

/// Plans every query of `set` in order, one at a time.
pub fn run_reach(set: &ReachProblemSet, settings: &ReachSettings) -> ReachReport {
    let planner = ReachPlanner::new(set, settings.clone());
    let outcomes: Vec<QueryOutcome> = set
        .queries
        .iter()
        .enumerate()
        .map(|(k, q)| {
            let t0 = Instant::now();
            let r = planner.plan(q, settings.rrt.seed.wrapping_add(k as u64));
            let time = t0.elapsed();
            QueryOutcome {
                status: r.status,
                time,
                waypoints: r.path.len(),
                length: planner.space.path_length(&r.path),
                iterations: r.stats.iterations,
                states_checked: r.stats.states_checked,
            }
        })
        .collect();
    summarize(outcomes)
}

/// Success rate and time statistics of a list of outcomes.
pub fn summarize(outcomes: Vec<QueryOutcome>) -> ReachReport {
    let n = outcomes.len();
    let solved = outcomes
        .iter()
        .filter(|o| o.status == PlanStatus::Solved)
        .count();
    let mut ms: Vec<f64> = outcomes
        .iter()
        .map(|o| o.time.as_secs_f64() * 1e3)
        .collect();
    ms.sort_by(f64::total_cmp);
    ReachReport {
        queries: n,
        solved,
        success_rate: if n == 0 {
            0.0
        } else {
            solved as f64 / n as f64
        },
        median_ms: percentile(&ms, 0.5),
        p95_ms: percentile(&ms, 0.95),
        mean_ms: if n == 0 {
            0.0
        } else {
            ms.iter().sum::<f64>() / n as f64
        },
        max_ms: ms.last().copied().unwrap_or(0.0),
        outcomes,
    }
}

/// Nearest-rank percentile of sorted values (`p ∈ (0, 1]`); 0 for no values. The median of
/// an even count is the mean of the two middle values.
pub fn percentile(sorted: &[f64], p: f64) -> f64 {
    let n = sorted.len();
    if n == 0 {
        return 0.0;
    }
    if p == 0.5 && n % 2 == 0 {
        return 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
    }
    let rank = ((p * n as f64).ceil() as usize).clamp(1, n);
    sorted[rank - 1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_by_nearest_rank() {
        let v: Vec<f64> = (1..=20).map(f64::from).collect();
        assert_eq!(percentile(&v, 0.95), 19.0);
        assert_eq!(percentile(&v, 0.5), 10.5);
        assert_eq!(percentile(&[3.0], 0.95), 3.0);
        assert_eq!(percentile(&[1.0, 2.0, 3.0], 0.5), 2.0);
        assert_eq!(percentile(&[], 0.5), 0.0);
    }
}
