//! Geometry for pregrasp, in nalgebra `f64` throughout (parry3d-f64 0.25 speaks the same types).
//!
//! Frames: world is right-handed with `z` up; the support surface is the plane
//! `z = support_height`. A [`Pose`] maps a child frame into its parent (`p_parent = pose * p_child`).

pub mod bits_hash;
pub mod hull;
pub mod mesh;
pub mod rotation;
pub mod shapes;

pub use bits_hash::{BitsBuildHasher, BitsHasher};
pub use hull::{ConvexHull, HullError, HullFace};
pub use mesh::Mesh;

/// A rigid transform (rotation + translation), `p_parent = pose * p_child`.
pub type Pose = nalgebra::Isometry3<f64>;
/// A point in some frame, in metres.
pub type Point = nalgebra::Point3<f64>;
/// A vector in some frame, in metres.
pub type Vector = nalgebra::Vector3<f64>;
