//! Bad input built in code — what a scene file's loader would refuse — is an error from the
//! planner, never a panic: a mesh that cannot be a collision body, an arm whose joint limits
//! cannot time a motion.

use std::path::Path;
use std::sync::Arc;

use nalgebra::Isometry3;
use pregrasp_io::scene::Scene;
use pregrasp_planner::pipeline::PlanOptions;
use pregrasp_planner::{plan_scene, PlanError};
use pregrasp_robot::{ArmKinematics, ChainSteps, Joints};

fn chair() -> (Scene, pregrasp_geometry::Mesh) {
    let ex = pregrasp_examples::by_name("chair_side").unwrap();
    let scene = Scene::from_str(&ex.scene_toml, Path::new("examples/chair_side.toml")).unwrap();
    (scene, ex.mesh)
}

fn plan(scene: &Scene, mesh: &pregrasp_geometry::Mesh) -> Result<(), PlanError> {
    plan_scene(scene, mesh, &PlanOptions::default(), &|_| {}, &|| {}).map(|_| ())
}

#[test]
fn a_mesh_with_a_non_finite_vertex_is_an_error_not_a_panic() {
    let (scene, mut mesh) = chair();
    mesh.vertices[3].y = f64::NAN;
    assert!(matches!(plan(&scene, &mesh), Err(PlanError::Mesh(_))));
    let (scene, mut mesh) = chair();
    mesh.triangles[0][1] = mesh.vertices.len() as u32 + 7;
    assert!(matches!(plan(&scene, &mesh), Err(PlanError::Mesh(_))));
    // The unchanged chair plans.
    let (scene, mesh) = chair();
    assert_eq!(plan(&scene, &mesh), Ok(()));
}

/// An arm's kinematics with one joint's speed limit replaced.
#[derive(Debug)]
struct Slowed {
    inner: Arc<dyn ArmKinematics>,
    joint: usize,
    speed: f64,
}

impl ArmKinematics for Slowed {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn fk(&self, q: &Joints) -> Isometry3<f64> {
        self.inner.fk(q)
    }
    fn fk_frames(&self, q: &Joints) -> [Isometry3<f64>; 7] {
        self.inner.fk_frames(q)
    }
    fn ik(&self, flange: &Isometry3<f64>, seed: &Joints) -> Vec<Joints> {
        self.inner.ik(flange, seed)
    }
    fn ik_nearest(&self, flange: &Isometry3<f64>, seed: &Joints) -> Option<Joints> {
        self.inner.ik_nearest(flange, seed)
    }
    fn joint_limits(&self) -> [(f64, f64); 6] {
        self.inner.joint_limits()
    }
    fn max_joint_speed(&self) -> Joints {
        let mut v = self.inner.max_joint_speed();
        v[self.joint] = self.speed;
        v
    }
    fn max_joint_accel(&self) -> Joints {
        self.inner.max_joint_accel()
    }
    fn frame_offsets(&self) -> [f64; 6] {
        self.inner.frame_offsets()
    }
    fn chain_steps(&self) -> ChainSteps {
        self.inner.chain_steps()
    }
}

#[test]
fn an_arm_whose_speed_limit_is_zero_or_not_finite_is_an_error_naming_it() {
    for speed in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let (mut scene, mesh) = chair();
        let arm = &mut scene.robots[1].arm;
        arm.kin = Arc::new(Slowed {
            inner: arm.kin.clone(),
            joint: 3,
            speed,
        });
        let err = plan(&scene, &mesh).unwrap_err();
        let name = scene.robots[1].name.clone();
        assert!(
            matches!(&err, PlanError::JointLimit { arm, joint: 4, what: "speed", .. } if *arm == name),
            "{err}"
        );
        assert!(
            err.to_string().contains("joint 4 has a speed limit"),
            "{err}"
        );
    }
}
