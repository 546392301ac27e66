//! Helpers shared by the integration tests.
#![allow(dead_code)]

use nalgebra::Isometry3;
use pregrasp_robot::{wrap_angle, Joints, UrKinematics};

/// Position (m) and rotation (rad) error between two poses.
pub fn pose_error(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    let dp = (a.translation.vector - b.translation.vector).norm();
    let dr = 2.0 * (a.rotation.conjugate() * b.rotation).imag().norm();
    (dp, dr)
}

/// Largest joint difference modulo 2π.
pub fn angle_gap(a: &Joints, b: &Joints) -> f64 {
    a.iter()
        .zip(b.iter())
        .map(|(x, y)| wrap_angle(x - y).abs())
        .fold(0.0, f64::max)
}

/// Asserts every solution is finite and reproduces `target` to 1e-9.
pub fn assert_solutions_exact(kin: &UrKinematics, sols: &[Joints], target: &Isometry3<f64>) {
    for s in sols {
        assert!(s.iter().all(|v| v.is_finite()), "non-finite solution {s:?}");
        let (dp, dr) = pose_error(&kin.fk(s), target);
        assert!(
            dp < 1e-9 && dr < 1e-9,
            "solution {s:?}: residual {dp} m, {dr} rad"
        );
    }
}

use parry3d_f64::query::intersection_test;
use parry3d_f64::shape::{
    Capsule as PCapsule, Cuboid, Cylinder as PCylinder, RoundCylinder, Shape,
};
use pregrasp_robot::{LinkShape, Primitive};

/// A link shape placed in the base frame by its frame pose, as a parry shape.
pub fn placed(shape: &LinkShape, frame_pose: &Isometry3<f64>) -> (Isometry3<f64>, Box<dyn Shape>) {
    match shape.primitive {
        Primitive::Capsule(c) => (
            Isometry3::identity(),
            Box::new(PCapsule::new(frame_pose * c.a, frame_pose * c.b, c.radius)),
        ),
        Primitive::Cylinder(c) => {
            // The rounded cylinder as parry's `RoundCylinder`: the inset core plus the border.
            let (a, b, radius) = c.inset();
            let (a, b) = (frame_pose * a, frame_pose * b);
            let d = b - a;
            let rot = nalgebra::UnitQuaternion::rotation_between(&nalgebra::Vector3::y(), &d)
                .unwrap_or_else(|| {
                    nalgebra::UnitQuaternion::from_axis_angle(
                        &nalgebra::Vector3::x_axis(),
                        std::f64::consts::PI,
                    )
                });
            (
                Isometry3::from_parts(nalgebra::center(&a, &b).coords.into(), rot),
                Box::new(RoundCylinder {
                    inner_shape: PCylinder::new(0.5 * d.norm(), radius),
                    border_radius: c.border,
                }),
            )
        }
        Primitive::Cuboid { pose, half_extents } => {
            (frame_pose * pose, Box::new(Cuboid::new(half_extents)))
        }
    }
}

/// True when two placed shapes intersect.
pub fn intersects(
    a: &(Isometry3<f64>, Box<dyn Shape>),
    b: &(Isometry3<f64>, Box<dyn Shape>),
) -> bool {
    intersection_test(&a.0, a.1.as_ref(), &b.0, b.1.as_ref()).expect("supported shape pair")
}
