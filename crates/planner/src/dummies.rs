//! Gripper dummies (paper §V-A, Fig. 5b): free-floating copies of the gripper placed at the
//! power grasps, rotated with the part, and tested against the support plane.

use nalgebra::Isometry3;
use pregrasp_robot::{LinkShape, Primitive};

/// Lowest world `z` of a set of shapes whose owning frame is at `frame_pose` (world).
///
/// Exact for capsules (`min(a_z, b_z) − r`), cylinders (lowest rim point) and cuboids (lowest
/// of the eight corners).
pub fn lowest_point(shapes: &[LinkShape], frame_pose: &Isometry3<f64>) -> f64 {
    shapes
        .iter()
        .map(|shape| match &shape.primitive {
            Primitive::Capsule(c) => {
                let a = frame_pose * c.a;
                let b = frame_pose * c.b;
                a.z.min(b.z) - c.radius
            }
            Primitive::Cylinder(c) => {
                // The inset core's lowest rim point, lowered by the rounded rim's radius.
                let (a, b, radius) = c.inset();
                let (a, b) = (frame_pose * a, frame_pose * b);
                let d = (b - a).normalize();
                a.z.min(b.z) - radius * (1.0 - d.z * d.z).max(0.0).sqrt() - c.border
            }
            Primitive::Cuboid { pose, half_extents } => {
                let world = frame_pose * pose;
                // The lowest corner: for each local axis pick the sign that lowers z.
                let r = world.rotation.to_rotation_matrix();
                let m = r.matrix();
                let spread = (0..3)
                    .map(|k| m[(2, k)].abs() * half_extents[k])
                    .sum::<f64>();
                world.translation.vector.z - spread
            }
        })
        .fold(f64::INFINITY, f64::min)
}
