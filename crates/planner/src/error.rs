//! Why a scene cannot be planned at all: bad input the scene file's loader would have refused
//! (a [`pregrasp_io::scene::Scene`] or a mesh built in code), never a rejected candidate (a
//! scene without a plan is a plan file with `status = "no_plan"`: [`crate::rejection`]).

use pregrasp_collision::CollisionError;

/// Why [`crate::plan_scene`] (or any planning entry) cannot plan a scene.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PlanError {
    /// An arm and its gripper have more shapes than the collision model holds (a scene loaded
    /// by `pregrasp_io` never has: loading refuses such a robot).
    #[error("{0}")]
    Arm(CollisionError),
    /// The part's mesh cannot be a collision body (no triangles, an index past its vertices, a
    /// non-finite vertex).
    #[error("{0}")]
    Mesh(CollisionError),
    /// An arm's joint speed or acceleration limit is not a positive finite number (a robot
    /// description read by `pregrasp_urdf` never has one: it refuses such a joint).
    #[error(
        "arm {arm:?}: joint {joint} has a {what} limit of {value} (it must be positive and finite)"
    )]
    JointLimit {
        arm: String,
        joint: usize,
        what: &'static str,
        value: f64,
    },
}

/// [`PlanError::Mesh`] unless `mesh` can be the part: the checks of
/// [`pregrasp_collision::ObjectGeometry::new`], before any stage reads the mesh.
pub fn check_mesh(mesh: &pregrasp_geometry::Mesh) -> Result<(), PlanError> {
    pregrasp_collision::check_mesh(mesh).map_err(PlanError::Mesh)
}
