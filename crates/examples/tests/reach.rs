//! The arms can reach every grasp of every example: G_s for the supportive arm at P_init and
//! all along the tilt, each power grasp for its arm on the tilted part, with an IK solution
//! that keeps the arm above the table.

mod common;

use common::{committed_scene, tilted};
use nalgebra::{Isometry3, Translation3};
use pregrasp_examples::{all, Example};
use pregrasp_io::scene::{RobotSpec, Scene};
use pregrasp_robot::{Joints, UrKinematics, UrModel};

/// Every IK solution of `robot` bringing its gripper point (`point_z` along the flange `z`)
/// onto `target` (world), whose link frames all stay `clearance` above the table.
fn reachable(
    robot: &RobotSpec,
    point_z: f64,
    target: &Isometry3<f64>,
    clearance: f64,
) -> Vec<Joints> {
    let kin = UrKinematics::new(robot.arm.ur.expect("a built-in arm"));
    let flange = robot.base.inverse() * target * Translation3::new(0.0, 0.0, -point_z);
    kin.ik(&flange, &robot.start)
        .into_iter()
        .filter(|q| {
            kin.fk_frames(q)[2..]
                .iter()
                .all(|f| (robot.base * f).translation.z > clearance)
        })
        .collect()
}

/// Index of the supportive arm: the one whose power grasp is nearer the axis (paper §V-B).
fn supportive(example: &Example, scene: &Scene) -> usize {
    let d = |i: usize| {
        let t = scene.grasps.power[i].translation;
        example
            .design
            .distance_to_axis(&nalgebra::Point2::new(t.x, t.y))
    };
    if d(0) > d(1) {
        1
    } else {
        0
    }
}

#[test]
fn supportive_arm_reaches_the_support_grasp_while_tilting() {
    for example in all() {
        let scene = committed_scene(&example);
        let s = supportive(&example, &scene);
        let robot = &scene.robots[s];
        let p_init = scene.initial_object_pose();
        for deg in (0..=90).step_by(5) {
            let part = tilted(&example.design, &p_init, (deg as f64).to_radians());
            let sols = reachable(
                robot,
                robot.precision_point_z,
                &(part * scene.grasps.support),
                0.05,
            );
            assert!(
                !sols.is_empty(),
                "{}: {} cannot reach G_s at {deg} deg",
                example.name,
                robot.name
            );
        }
    }
}

/// The rotation path μ_rot exists in joint space: following the nearest IK solution in 1°
/// steps from P_init to 60°, no joint jumps by more than the default max joint step (10°).
#[test]
fn support_grasp_has_a_continuous_ik_branch_over_the_tilt() {
    for example in all() {
        let scene = committed_scene(&example);
        let robot = &scene.robots[supportive(&example, &scene)];
        let kin = UrKinematics::new(UrModel::Ur5e);
        let p_init = scene.initial_object_pose();
        let flange_at = |deg: f64| {
            let part = tilted(&example.design, &p_init, deg.to_radians());
            robot.base.inverse()
                * part
                * scene.grasps.support
                * Translation3::new(0.0, 0.0, -robot.precision_point_z)
        };
        let starts = reachable(
            robot,
            robot.precision_point_z,
            &(p_init * scene.grasps.support),
            0.05,
        );
        let continuous = starts.iter().any(|start| {
            let mut q = *start;
            (1..=60).all(|deg| match kin.ik_nearest(&flange_at(deg as f64), &q) {
                Some(next)
                    if next
                        .iter()
                        .zip(&q)
                        .all(|(a, b)| (a - b).abs() < 10f64.to_radians()) =>
                {
                    q = next;
                    true
                }
                _ => false,
            })
        });
        assert!(
            continuous,
            "{}: no continuous IK branch for G_s over 0..60 deg",
            example.name
        );
    }
}

#[test]
fn both_arms_reach_their_power_grasps_on_the_tilted_part() {
    for example in all() {
        let scene = committed_scene(&example);
        let p_init = scene.initial_object_pose();
        for deg in (10..=90).step_by(10) {
            let part = tilted(&example.design, &p_init, (deg as f64).to_radians());
            for (robot, grasp) in scene.robots.iter().zip(&scene.grasps.power) {
                let sols = reachable(robot, robot.power_point_z, &(part * grasp), 0.05);
                assert!(
                    !sols.is_empty(),
                    "{}: {} cannot power-grasp at {deg} deg",
                    example.name,
                    robot.name
                );
            }
        }
    }
}

#[test]
fn start_configurations_hold_the_gripper_above_the_part() {
    for example in all() {
        let scene = committed_scene(&example);
        for robot in &scene.robots {
            let kin = UrKinematics::new(UrModel::Ur5e);
            let frames = kin.fk_frames(&robot.start);
            let tip = robot.base * frames[6] * nalgebra::Point3::new(0.0, 0.0, 0.17);
            assert!(
                tip.z > 0.2,
                "{}: {} gripper tip at z {}",
                example.name,
                robot.name,
                tip.z
            );
            assert!(frames.iter().all(|f| (robot.base * f).translation.z >= 0.0));
        }
    }
}
