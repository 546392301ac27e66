//! Errors of the collision world (bad input only; a collision is a query result, not an error).

use thiserror::Error;

/// Why a collision world or one of its parts could not be built.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CollisionError {
    /// The object mesh has no triangles.
    #[error("object mesh has no triangles")]
    EmptyMesh,
    /// A triangle indexes a vertex that does not exist.
    #[error("object mesh triangle {triangle} {indices:?} indexes past its {vertices} vertices")]
    BadTriangle {
        triangle: usize,
        indices: [u32; 3],
        vertices: usize,
    },
    /// A vertex has a NaN or infinite coordinate.
    #[error("object mesh has a non-finite vertex")]
    NonFiniteVertex,
    /// parry refused the mesh.
    #[error("object mesh rejected: {0}")]
    Mesh(parry3d_f64::shape::TriMeshBuilderError),
    /// An arm has more collision primitives than the fixed-size pose buffer holds.
    #[error("arm {arm:?} has {count} collision primitives, at most {max} are supported")]
    TooManyShapes {
        arm: String,
        count: usize,
        max: usize,
    },
}
