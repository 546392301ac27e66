//! A box-shaped bar lying on the table and turned about its bottom edge.

#![allow(dead_code)]

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use pregrasp_geometry::Mesh;

pub const G: f64 = pregrasp_physics::GRAVITY;

/// A closed, outward-wound box mesh [0, l] × [0, w] × [0, h].
pub fn box_mesh(l: f64, w: f64, h: f64) -> Mesh {
    let v = |x: f64, y: f64, z: f64| Point3::new(x * l, y * w, z * h);
    let vertices = vec![
        v(0., 0., 0.),
        v(1., 0., 0.),
        v(1., 1., 0.),
        v(0., 1., 0.),
        v(0., 0., 1.),
        v(1., 0., 1.),
        v(1., 1., 1.),
        v(0., 1., 1.),
    ];
    let triangles = vec![
        [0, 2, 1],
        [0, 3, 2], // bottom (−z)
        [4, 5, 6],
        [4, 6, 7], // top (+z)
        [0, 1, 5],
        [0, 5, 4], // −y
        [2, 3, 7],
        [2, 7, 6], // +y
        [1, 2, 6],
        [1, 6, 5], // +x
        [0, 4, 7],
        [0, 7, 3], // −x
    ];
    Mesh::new(vertices, triangles)
}

/// The bar's pose after turning by `theta` about its bottom edge (the world `y` axis through
/// the origin), its far end (`+x`) going up.
pub fn turned(theta: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::identity(),
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -theta),
    )
}
