use pregrasp_collision::reach::*;
use pregrasp_collision::{ArmValidity, WorldState, CollisionWorld};
use pregrasp_motion::{MotionValidator, StateValidator};
use pregrasp_robot::UrModel;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
fn main() {
    let mode = std::env::args().nth(1).unwrap_or_default();
    let set = ReachProblemSet { model: UrModel::Ur5e, obstacles: if mode.contains("empty") { vec![] } else { table_boxes_obstacles() }, queries: Vec::new() };
    let mut p = ReachPlanner::new(&set, ReachSettings::default());
    if mode.contains("range") { p.settings.rrt.range = 2.0; }
    if mode.contains("narrow") { p.space = p.query_space(); }
    if mode.contains("big") { p.settings.rrt.max_iterations = 200_000; p.settings.rrt.max_time = None; }
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let mut draw = || p.sample_valid(&mut rng);
    // fraction valid
    let mut r2 = ChaCha8Rng::seed_from_u64(1); let mut v=0; for _ in 0..10000 { if p.is_valid(&p.space.sample(&mut r2)) { v+=1; } }
    println!("valid fraction {}", v as f64/1e4);
    // self collision only
    let w = CollisionWorld::single_arm(None, None, set.arm()).unwrap();
    let val = ArmValidity::new(&w, 0, WorldState::new([[0.0;6];2]));
    let mut r2 = ChaCha8Rng::seed_from_u64(1); let mut v=0; for _ in 0..10000 { let q=p.space.sample(&mut r2); if val.is_valid(&q) { v+=1; } else if v < 3 { println!("{:?}", w.check_arm(0, &val.state_at(&q))); } }
    println!("self-valid fraction {}", v as f64/1e4);
    let mut hist = std::collections::BTreeMap::new();
    let mut r3 = ChaCha8Rng::seed_from_u64(5);
    let qs = p.query_space();
    for _ in 0..10000 { let q = qs.sample(&mut r3); let st = WorldState::new([q, [0.0;6]]); if let Err(c) = p.world.check_arm(0, &st) { *hist.entry(format!("{}|{}", c.a, c.b)).or_insert(0) += 1; } }
    println!("{hist:?}");
    let home = [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0];
    for k in 0..10 {
        let q = if mode.contains("home") { ReachQuery { start: home, goal: draw() } } else { ReachQuery { start: draw(), goal: draw() } };
        if k < 3 { println!("{:?}", q); }
        let r = p.plan(&q, k);
        println!("{k}: {:?} {:.2}ms it {} states {} edges {} tree {} wp {}", r.status, r.stats.time.as_secs_f64()*1e3, r.stats.iterations, r.stats.states_checked, r.stats.edges_checked, r.stats.tree_states, r.path.len());
    }
    let _ = MotionValidator::new(&p.space, &val, 0.01);
}
