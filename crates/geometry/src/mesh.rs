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

/// The undirected edges of the triangles `triangles` not shared by exactly two of them (0 for
/// a closed surface). Every triangle's edges as `(low, high)` vertex pairs, sorted: an edge's
/// triangles are a run of equal pairs (no hashing; a shelf board's 596 triangles in a few
/// microseconds).
pub fn open_edges(triangles: &[[u32; 3]]) -> usize {
    let mut edges: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    edges.sort_unstable();
    edges
        .chunk_by(|a, b| a == b)
        .filter(|run| run.len() != 2)
        .count()
}
