//! A robot description (URDF text) through everything a scene does with it: parsing and the
//! tree's checks, the arm from its base to its tool link (the file's defaults), the six-joint
//! arm with its collision geometry (primitives; meshes resolve nowhere but a named device or
//! FIFO is refused), the jaw gripper below the tool link, the arm as the collision world
//! builds it with each gripper, and a motion timed by the arm's joint speeds.
#![no_main]

use libfuzzer_sys::fuzz_target;
use nalgebra::Isometry3;
use pregrasp_collision::ArmModel;
use pregrasp_robot::Gripper;
use pregrasp_urdf::{
    describe_arm_from, describe_gripper, CacheDir, GeometryOptions, LazyGeometry,
    SelfCollisionOptions, UrdfArm, UrdfModel,
};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(model) = UrdfModel::from_urdf_str(text, "<fuzz>") else {
        return;
    };
    let Ok(arm) = UrdfArm::from_model(model, None, None) else {
        return;
    };
    let geometry = LazyGeometry::new(GeometryOptions {
        cache: CacheDir::Off,
        self_collision: SelfCollisionOptions {
            samples: 32,
            ..SelfCollisionOptions::default()
        },
        ..GeometryOptions::default()
    });
    let Ok(description) = describe_arm_from(&arm, &[], &[], &geometry) else {
        return;
    };
    let kin = description.kin.clone();
    let mut grippers = vec![Gripper::default()];
    if let Ok(jaws) = describe_gripper(&arm, None, None, &geometry) {
        grippers.push(Gripper::Jaws(std::sync::Arc::new(jaws)));
    }
    for gripper in grippers {
        let _ = ArmModel::from_description("fuzz", description.clone(), Isometry3::identity(), gripper);
    }
    let limits = kin.joint_limits();
    let far: [f64; 6] = std::array::from_fn(|i| 0.5 * (limits[i].0 + limits[i].1));
    let path = [[0.0; 6], far];
    let _ = pregrasp_motion::try_time_parameterize(
        &path,
        &kin.max_joint_speed(),
        &kin.max_joint_accel(),
    );
    if let Some(q) = kin.ik(&kin.fk(&far), &far).first() {
        let _ = kin.fk(q);
    }
});
