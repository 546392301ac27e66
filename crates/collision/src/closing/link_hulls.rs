//! The convex hull of each link of the built-in 2F-85's `+x` finger, computed once and shared:
//! the closing's finger shapes ([`super::FingerShapes`]) and the gripper's lowest point
//! (`ArmModel::gripper_lowest`) hull the same points, and a hull is most of what either costs
//! the first time (parry's `try_convex_hull` over a link's piece vertices, in the link frame;
//! the built-in links' hulls are baked, [`crate::baked_hulls`]).
//! The `−x` finger's links are the mirror images `x → −x` of these (`FingerSolids` builds them
//! so, bit for bit): their hull is this one mirrored, with the same faces.

use std::sync::OnceLock;

use nalgebra::Point3;
use pregrasp_robot::{FingerSolids, LINKS_PER_FINGER, SIDES};

use crate::tight::Polytope;

/// A hull: its vertices and its faces (indices into them), as parry gives it.
pub(crate) type HullFaces = (Vec<Point3<f64>>, Vec<[u32; 3]>);

/// The hull of `points`, as parry gives it (the points themselves, with no faces, where parry
/// finds no hull).
pub(crate) fn hull_of(points: Vec<Point3<f64>>) -> HullFaces {
    crate::baked_hulls::convex_hull(&points).unwrap_or((points, Vec::new()))
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

/// The hull of the 2F-85's finger shape `j` (`0..FINGER_SHAPES`, in shape order: the `−x`
/// finger's links, then the `+x` finger's), in its link frame, from [`robotiq_link_hull`] (the
/// `−x` links mirrored `x → −x`, as `FingerSolids` mirrors their pieces): the hull
/// `Tight::lowest` would build of the same points, with the same extreme vertices, so the same
/// least heights.
pub(crate) fn robotiq_finger_hull(j: usize) -> Polytope {
    let (verts, faces) = robotiq_link_hull(j % LINKS_PER_FINGER);
    let side = SIDES[j / LINKS_PER_FINGER];
    let verts: Vec<Point3<f64>> = verts
        .iter()
        .map(|p| Point3::new(side * p.x, p.y, p.z))
        .collect();
    if faces.is_empty() {
        Polytope::new(verts)
    } else {
        Polytope::with_faces(verts, faces)
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Isometry3, Translation3, UnitQuaternion};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::tight::Tight;

    /// The climb on the shared hull of each 2F-85 finger shape, both fingers, gives what
    /// `Tight::lowest` gives on the hull of the shape's own pieces — the least height of every
    /// vertex, to the bit (`tight::tests::lowest_is_the_least_height_of_every_vertex`) — in
    /// random frames and in axis-aligned ones (where vertices tie).
    #[test]
    fn the_shared_finger_hulls_give_the_lowest_of_their_own() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let solids = FingerSolids::robotiq_2f85();
        let aligned = [
            UnitQuaternion::identity(),
            UnitQuaternion::from_euler_angles(std::f64::consts::PI, 0.0, 0.0),
            UnitQuaternion::from_euler_angles(0.0, std::f64::consts::FRAC_PI_2, 0.0),
        ];
        let random: Vec<_> = (0..200)
            .map(|_| {
                let mut angle = |r: f64| rng.random_range(-r..r);
                UnitQuaternion::from_euler_angles(angle(3.2), angle(1.6), angle(3.2))
            })
            .collect();
        for (j, link) in solids.links.iter().enumerate() {
            let own = Tight::new(&link.pieces).expect("finger pieces are solids");
            let shared = Tight::new(&link.pieces).expect("finger pieces are solids");
            for rotation in aligned.iter().chain(&random) {
                let frame = Isometry3::from_parts(Translation3::new(0.1, -0.2, 0.3), *rotation);
                let climbed = shared.lowest_on(&frame, || robotiq_finger_hull(j));
                assert_eq!(climbed, own.lowest(&frame), "shape {j} ({})", link.name);
            }
        }
    }
}
