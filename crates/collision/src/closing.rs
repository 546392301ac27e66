//! The 2F-85 closing on the part's real mesh, with the support under it: the
//! [`pregrasp_robot::ClosingWorld`] of a grasp, for [`pregrasp_robot::close_fingers`].
//!
//! A finger link is a set of convex pieces in its link frame ([`FingerShapes`]); it touches the
//! part when a piece meets a triangle of the part's mesh (parry's convex-vs-mesh test through the
//! BVH), and the support when any piece vertex lies below the support plane. Frames: the
//! pieces are placed in the gripper frame G by the linkage, G in the object frame by the
//! grasp (`flange_in_object`); the support plane is given in the object frame as `(n, d)`: the
//! points `p` with `n · p > d` are below it (inside the table).

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::query;
use parry3d_f64::shape::ConvexPolyhedron;
use pregrasp_robot::{ClosingWorld, PlanarPose, Touch, FINGER_LINKS};

use crate::object::ObjectGeometry;

/// One convex piece of a finger link: its hull, and its vertices (for the support test).
#[derive(Clone, Debug)]
struct Piece {
    hull: ConvexPolyhedron,
    vertices: Vec<Point3<f64>>,
}

/// The finger links' convex pieces in their link frames, for the `+x` finger and its mirror.
#[derive(Clone, Debug)]
pub struct FingerShapes {
    /// `[side][link][piece]`, side 0 the `+x` finger, links in [`FINGER_LINKS`] order.
    pieces: [Vec<Vec<Piece>>; 2],
}

impl FingerShapes {
    /// From each link's pieces ([`FINGER_LINKS`] order) as point sets in the link frame of the
    /// `+x` finger; the other finger's are their mirror images `x → −x`. `None` if a link is
    /// missing or a piece has no volume.
    pub fn new(links: &[Vec<Vec<Point3<f64>>>]) -> Option<FingerShapes> {
        if links.len() != FINGER_LINKS.len() {
            return None;
        }
        let side = |sign: f64| -> Option<Vec<Vec<Piece>>> {
            links
                .iter()
                .map(|pieces| {
                    pieces
                        .iter()
                        .map(|pts| {
                            let vertices: Vec<Point3<f64>> = pts
                                .iter()
                                .map(|p| Point3::new(sign * p.x, p.y, p.z))
                                .collect();
                            let hull = ConvexPolyhedron::from_convex_hull(&vertices)?;
                            Some(Piece { hull, vertices })
                        })
                        .collect()
                })
                .collect()
        };
        Some(FingerShapes {
            pieces: [side(1.0)?, side(-1.0)?],
        })
    }
}

/// The part and the support at one grasp (see the module documentation).
pub struct PartClosing<'a> {
    pub object: &'a ObjectGeometry,
    pub shapes: &'a FingerShapes,
    /// The gripper frame G (the flange) in the object frame.
    pub flange_in_object: Isometry3<f64>,
    /// The support plane in the object frame: `n · p > d` is below it. `None`: no support.
    pub support: Option<(Vector3<f64>, f64)>,
}

impl ClosingWorld for PartClosing<'_> {
    fn touch(&self, side: f64, link: usize, pose: &PlanarPose) -> Touch {
        let in_object = self.flange_in_object * pose.to_isometry(side);
        let pieces = &self.shapes.pieces[usize::from(side < 0.0)][link];
        if let Some((n, d)) = self.support {
            let below = pieces
                .iter()
                .flat_map(|p| p.vertices.iter())
                .any(|v| n.dot(&(in_object * v).coords) > d);
            if below {
                return Touch::Support;
            }
        }
        let mesh = self.object.trimesh();
        for piece in pieces {
            if query::intersection_test(&in_object, &piece.hull, &Isometry3::identity(), mesh)
                .unwrap_or(false)
            {
                return Touch::Part;
            }
        }
        Touch::Nothing
    }
}
