use pregrasp_collision::*;
use pregrasp_robot::*;
fn main() {
    let arm = ArmModel::new("arm", UrModel::Ur5e, nalgebra::Isometry3::identity(), Gripper2F85::default());
    for q in [[0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0], [0.0, -0.3, 0.0, 0.0, 0.0, 0.0], [0.0,0.0,0.0,0.0,0.0,0.0]] {
        println!("q = {q:?}");
        for (n, s) in arm.placed_shapes(&q, GripperState::Open) {
            match s { Placed::Capsule{a,b,radius} => println!("  {n}: cap a=({:.3},{:.3},{:.3}) b=({:.3},{:.3},{:.3}) r={radius:.3}", a.x,a.y,a.z,b.x,b.y,b.z),
                      Placed::Cuboid{pose,half} => println!("  {n}: box c=({:.3},{:.3},{:.3}) h={:.3?}", pose.translation.x,pose.translation.y,pose.translation.z, half.as_slice()) }
        }
    }
}
