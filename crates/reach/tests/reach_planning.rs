//! One UR5e among a table and boxes: seeded random start/goal pairs are planned with
//! RRT-Connect + simplification; every path is re-checked at 4× finer resolution.

use pregrasp_collision::ArmValidity;
use pregrasp_collision::WorldState;
use pregrasp_motion::{MotionValidator, PlanStatus};
use pregrasp_reach::{
    table_boxes_obstacles, ReachPlanner, ReachProblemSet, ReachQuery, ReachSettings,
};
use pregrasp_robot::UrModel;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn planner() -> ReachPlanner {
    let set = ReachProblemSet {
        model: UrModel::Ur5e,
        obstacles: table_boxes_obstacles(),
        queries: Vec::new(),
    };
    ReachPlanner::new(&set, ReachSettings::default())
}

/// `n` start/goal pairs, each state drawn uniformly in `[−π, π]⁶` until valid.
fn valid_pairs(p: &ReachPlanner, seed: u64, n: usize) -> Vec<ReachQuery> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| ReachQuery {
            start: p.sample_valid(&mut rng),
            goal: p.sample_valid(&mut rng),
        })
        .collect()
}

#[test]
fn five_hundred_random_queries_succeed_and_stay_valid_at_finer_resolution() {
    let p = planner();
    // Re-check without the planning margin: the paths must be free of any contact.
    let exact = p.world.clone().with_margin(0.0);
    let validity = ArmValidity::new(&exact, 0, WorldState::new([[0.0; 6]; 2]));
    let fine = MotionValidator::new(&p.space, &validity, p.settings.resolution / 4.0);
    let queries = valid_pairs(&p, 42, 500);
    let mut solved = 0;
    for (k, q) in queries.iter().enumerate() {
        let r = p.plan(q, k as u64);
        assert_ne!(r.status, PlanStatus::InvalidStart);
        assert_ne!(r.status, PlanStatus::InvalidGoal);
        if !r.is_solved() {
            continue;
        }
        solved += 1;
        assert_eq!(r.path.first(), Some(&q.start));
        assert_eq!(r.path.last(), Some(&q.goal));
        assert!(
            r.path.iter().all(|s| p.space.contains(s)),
            "query {k}: path leaves the joint limits"
        );
        assert!(
            fine.check_path(&r.path),
            "query {k}: path invalid at 4x finer resolution"
        );
    }
    let rate = solved as f64 / queries.len() as f64;
    eprintln!("solved {solved} of {}", queries.len());
    // 0.968 measured (seed 42): the unsolved pairs start or end with the upper arm hanging
    // past the table edge (shoulder lift near ±π, the elbow 1–2 cm from the table), narrow
    // pockets that the exact link pieces made valid and that 100 000 iterations do not leave
    // either; with the link cylinders alone those states were invalid and the rate was higher.
    assert!(rate >= 0.96, "success rate {rate}");
}

#[test]
fn same_seed_same_path_bit_for_bit() {
    let p = planner();
    for (k, q) in valid_pairs(&p, 7, 5).iter().enumerate() {
        let a = p.plan(q, 1000 + k as u64);
        let b = p.plan(q, 1000 + k as u64);
        assert_eq!(a.status, b.status);
        let bits = |path: &[[f64; 6]]| {
            path.iter()
                .flat_map(|s| s.map(f64::to_bits))
                .collect::<Vec<u64>>()
        };
        assert_eq!(bits(&a.path), bits(&b.path), "query {k}");
    }
}

#[test]
fn invalid_start_is_reported_not_planned() {
    let p = planner();
    let good = valid_pairs(&p, 3, 1)[0];
    // Shoulder lift down: the arm goes through the table.
    let bad = [0.0, std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0, 0.0];
    assert!(!p.is_valid(&bad));
    assert_eq!(
        p.plan(
            &ReachQuery {
                start: bad,
                goal: good.goal
            },
            0
        )
        .status,
        PlanStatus::InvalidStart
    );
    assert_eq!(
        p.plan(
            &ReachQuery {
                start: good.start,
                goal: bad
            },
            0
        )
        .status,
        PlanStatus::InvalidGoal
    );
}
