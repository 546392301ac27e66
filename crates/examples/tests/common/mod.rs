//! Shared helpers of the examples' integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use pregrasp_examples::{Example, PartDesign};
use pregrasp_io::scene::Scene;

/// The committed `examples/` directory of the repository.
pub fn committed_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// The example's scene as committed (parsed with the real loader).
pub fn committed_scene(example: &Example) -> Scene {
    let path = committed_dir().join(format!("{}.toml", example.name));
    Scene::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The intended axis in world at P_init: a point on it and the unit direction about which a
/// positive rotation lifts the part (the inward normal turns towards world `+z`).
pub fn world_axis(
    design: &PartDesign,
    p_init: &Isometry3<f64>,
) -> (Point3<f64>, Unit<Vector3<f64>>) {
    let a0 = p_init * Point3::new(design.axis[0].x, design.axis[0].y, 0.0);
    let n = design.axis_inward_normal();
    let n_world = p_init.rotation * Vector3::new(n.x, n.y, 0.0);
    (a0, Unit::new_normalize(n_world.cross(&Vector3::z())))
}

/// P_init rotated by `theta` (rad) about the intended axis, lifting the part.
pub fn tilted(design: &PartDesign, p_init: &Isometry3<f64>, theta: f64) -> Isometry3<f64> {
    let (a, u) = world_axis(design, p_init);
    let about_axis = Translation3::from(a.coords)
        * UnitQuaternion::from_axis_angle(&u, theta)
        * Translation3::from(-a.coords);
    about_axis * p_init
}
