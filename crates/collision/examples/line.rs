use pregrasp_collision::reach::*;
use pregrasp_collision::*;
use pregrasp_robot::UrModel;
fn main() {
    let set = ReachProblemSet { model: UrModel::Ur5e, obstacles: table_boxes_obstacles(), queries: Vec::new() };
    let p = ReachPlanner::new(&set, ReachSettings::default());
    let a = [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0];
    let b = [-2.0421849392493314, -1.248539738216522, -0.08523383610310109, -1.6832135667570924, -1.1701050580828551, -0.6499688174029981];
    let mut last = String::new();
    for i in 0..=100 {
        let s = i as f64 / 100.0;
        let q: Vec<f64> = (0..6).map(|j| a[j] + s * (b[j] - a[j])).collect();
        let q: [f64; 6] = q.try_into().unwrap();
        let st = WorldState::new([q, [0.0; 6]]);
        let r = format!("{:?}", p.world.check_arm(0, &st));
        if r != last { println!("{s:.2}: {r} clearance {:?}", p.world.clearance_arm(0, &st)); last = r; }
    }
}
