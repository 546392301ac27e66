use pregrasp_collision::*;
use pregrasp_robot::*;
fn main() {
    let arm = ArmModel::new("arm", UrModel::Ur5e, nalgebra::Isometry3::identity(), Gripper2F85::default());
    let w = CollisionWorld::single_arm(None, None, arm).unwrap().with_margin(0.01);
    for i in 0..=24 {
        let q5 = -6.2832 + i as f64 * 0.5236;
        let mut line = String::new();
        for j in 0..=48 {
            let q4 = -6.2832 + j as f64 * 0.2618;
            let q = [0.0, -1.5708, 1.5708, q4, q5, 0.0];
            line.push(if w.is_arm_free(0, &WorldState::new([q, q])) { '.' } else { '#' });
        }
        println!("q5={q5:+.2} {line}");
    }
}
