//! Indexed triangle meshes.

use crate::{Point, Pose};

/// An indexed triangle mesh in its own frame (metres, after any scale was applied).
///
/// Triangles are counter-clockwise seen from outside when the mesh is consistently oriented.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub vertices: Vec<Point>,
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    pub fn new(vertices: Vec<Point>, triangles: Vec<[u32; 3]>) -> Self {
        Self {
            vertices,
            triangles,
        }
    }

    /// The same mesh with every vertex mapped by `pose`.
    pub fn transformed(&self, pose: &Pose) -> Mesh {
        Mesh {
            vertices: self.vertices.iter().map(|v| pose * v).collect(),
            triangles: self.triangles.clone(),
        }
    }
}
