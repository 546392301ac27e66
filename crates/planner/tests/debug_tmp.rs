use std::path::Path;
use pregrasp_io::scene::Scene;
use pregrasp_planner::context::PlanningContext;
use pregrasp_planner::poses::*;
use pregrasp_planner::rotate::*;
use pregrasp_planner::timeline::Moment;
use pregrasp_robot::GripperState;
#[test]
fn debug() {
    let ex = pregrasp_examples::by_name("shelf_side").unwrap();
    let scene = Scene::from_str(&ex.scene_toml, Path::new("examples/x.toml")).unwrap();
    let axes = pregrasp_planner::rotation_axis_candidates(&ex.mesh, &scene.object.pose, scene.support_height, &scene.planner);
    let ctx = PlanningContext::new(&scene, &ex.mesh).unwrap();
    let c = &axes.candidates[0];
    let p = object_pose_for_power_grasp(&ctx, c).unwrap();
    for s in &p.support_ik {
        let Ok(rot) = rotation_path(&ctx, c, &p, s) else { continue };
        let mut m = Moment { q: ctx.starts(), gripper: [GripperState::Open; 2], object: ctx.p_init, contact_allowed: [false; 2] };
        m.q[p.supportive] = rot.q[0]; m.contact_allowed[p.supportive] = true;
        println!("open+contact: {:?}", ctx.check_arm(p.supportive, &m).err());
        m.gripper[p.supportive] = GripperState::Closed;
        println!("closed+contact: {:?}", ctx.check_arm(p.supportive, &m).err());
    }
}
