//! The convex hull of each link of the built-in 2F-85's `+x` finger, computed once and shared:
//! the closing's finger shapes ([`super::FingerShapes`]) and the gripper's lowest point
//! (`ArmModel::gripper_lowest`) hull the same points, and a hull is most of what either costs
//! the first time (parry's `try_convex_hull` over a link's piece vertices, in the link frame).
//! The `−x` finger's links are the mirror images `x → −x` of these (`FingerSolids` builds them
//! so, bit for bit): their hull is this one mirrored, with the same faces.

use std::sync::OnceLock;

use nalgebra::Point3;
use pregrasp_robot::{FingerSolids, LINKS_PER_FINGER};

/// A hull: its vertices and its faces (indices into them), as parry gives it.
pub(crate) type HullFaces = (Vec<Point3<f64>>, Vec<[u32; 3]>);

/// The hull of `points`, as parry gives it (the points themselves, with no faces, where parry
/// finds no hull).
pub(crate) fn hull_of(points: Vec<Point3<f64>>) -> HullFaces {
    parry3d_f64::transformation::try_convex_hull(&points).unwrap_or((points, Vec::new()))
}

/// The hull of the built-in 2F-85's link `link` ([`pregrasp_robot::FINGER_LINKS`] order) of the
/// `+x` finger, in its link frame: of its pieces' vertices in the order the pieces list them.
pub(crate) fn robotiq_link_hull(link: usize) -> &'static HullFaces {
    static HULLS: [OnceLock<HullFaces>; LINKS_PER_FINGER] = [const { OnceLock::new() }; 5];
    HULLS[link].get_or_init(|| {
        let solid = &FingerSolids::robotiq_2f85().links[LINKS_PER_FINGER + link];
        hull_of(solid.pieces.pieces.iter().flatten().copied().collect())
    })
}
