//! A link's pieces against the triangles of a mesh (the part): each piece placed in the mesh's
//! frame with its box there ([`any_piece_in`]), and GJK of a piece against one triangle, a
//! remembered separating axis tried first ([`piece_near_triangle_keyed`]).

use nalgebra::{Isometry3, Vector3};
use parry3d_f64::query::details::distance_support_map_support_map;
use parry3d_f64::shape::Triangle;

use super::{near_keyed, near_keyed_bounded, Climb, Piece, Posed, P};

/// One piece of a link placed in a mesh's frame, as [`any_piece_in`] hands it out.
pub(crate) struct PieceInMesh<'a> {
    /// The piece's link frame in the mesh frame.
    pub rel: &'a Isometry3<f64>,
    pub poly: Climb<'a>,
    /// The piece's box (link frame) bounded by a box of the mesh frame: `(lo, hi)`.
    pub aabb: (P, P),
    /// Names the piece for as long as it lives (its address), for
    /// [`piece_near_triangle_keyed`].
    pub key: usize,
    /// The piece's box in its link frame: centre and half extents.
    pub local_box: (P, Vector3<f64>),
}

/// Calls `f` for each piece of `t` placed in the frame of a mesh at `mesh_pose`
/// ([`PieceInMesh`]), until it returns `true`.
pub(crate) fn any_piece_in(
    t: &Posed,
    mesh_pose: &Isometry3<f64>,
    mut f: impl FnMut(&PieceInMesh) -> bool,
) -> bool {
    let rel = mesh_pose.inv_mul(t.frame);
    let m = rel.rotation.to_rotation_matrix().matrix().abs();
    t.tight.pieces.iter().any(|piece| {
        let local = nalgebra::center(&piece.lo, &piece.hi);
        let half = 0.5 * (piece.hi - piece.lo);
        let c = rel * local;
        let ext: Vector3<f64> = m * half;
        f(&PieceInMesh {
            rel: &rel,
            poly: Climb::new(&piece.poly),
            aabb: (c - ext, c + ext),
            key: piece as *const Piece as usize,
            local_box: (local, half),
        })
    })
}

/// Whether the polytope at `pose` comes within `margin` of the triangle (both in one frame),
/// trying first the axis that last separated the pair `key` (piece key, triangle key:
/// [`near_keyed`]; the answer is GJK's either way).
#[inline]
pub(crate) fn piece_near_triangle_keyed(
    key: (usize, usize),
    pose: &Isometry3<f64>,
    poly: &Climb,
    tri: &Triangle,
    margin: f64,
) -> bool {
    near_keyed(key, pose, poly, &Isometry3::identity(), tri, margin)
}

/// [`piece_near_triangle_keyed`] for a piece whose box in its own frame is `bounds` (centre,
/// half extents): a remembered axis is tried at the price of the triangle's support point
/// alone ([`near_keyed_bounded`]); the answer is the same.
#[inline]
pub(crate) fn piece_near_triangle_bounded(
    key: (usize, usize),
    pose: &Isometry3<f64>,
    poly: &Climb,
    bounds: &(P, Vector3<f64>),
    tri: &Triangle,
    margin: f64,
) -> bool {
    near_keyed_bounded(
        key,
        pose,
        poly,
        Some(bounds),
        &Isometry3::identity(),
        tri,
        margin,
    )
}

/// Distance from the polytope at `pose` to the triangle (both in one frame; `0` in contact).
#[inline]
pub(crate) fn piece_triangle_distance(pose: &Isometry3<f64>, poly: &Climb, tri: &Triangle) -> f64 {
    distance_support_map_support_map(&pose.inverse(), poly, tri).max(0.0)
}
