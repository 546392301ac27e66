//! The 2F-85 closing on the part's real mesh, with the support under it: the
//! [`pregrasp_robot::ClosingWorld`] of a grasp, for [`pregrasp_robot::close_fingers`].
//!
//! A finger link is a set of convex pieces in its link frame ([`FingerShapes`]); it touches the
//! part when a piece meets a triangle of the part's mesh (GJK on the link's hull, then on its
//! pieces, against the triangles near it), and the support when any piece vertex lies below the
//! support plane. Most poses of a closing are answered without a test: a link found clear of the
//! part (or a triangle) by some distance stays clear while it moves less than that, and one found
//! deep in a triangle stays in contact while it moves less than its depth (`near.rs`). Frames:
//! the pieces are placed in the gripper frame G by the linkage, G in the object frame by the
//! grasp (`flange_in_object`); the support plane is given in the object frame as `(n, d)`: the
//! points `p` with `n · p > d` are below it (inside the table).

use std::cell::RefCell;
use std::collections::HashMap;

use nalgebra::{Isometry3, Point3, Vector3};
use pregrasp_geometry::BitsBuildHasher;
use pregrasp_robot::{ClosingWorld, ConvexPieces, PlanarPose, Touch, FINGER_LINKS};

use crate::object::ObjectGeometry;
use crate::tight::Tight;

mod link_hulls;
mod near;

pub(crate) use link_hulls::{hull_of, robotiq_finger_hull, robotiq_link_hull, HullFaces};
use near::{Clearance, Link, Near, Solid};

/// One convex piece of a finger link: its vertices (for the support test and the boxes).
#[derive(Clone, Debug)]
struct Piece {
    vertices: Vec<Point3<f64>>,
}

/// The finger links' convex pieces in their link frames, for the `+x` finger and its mirror.
#[derive(Clone, Debug)]
pub struct FingerShapes {
    /// `[side][link][piece]`, side 0 the `+x` finger, links in [`FINGER_LINKS`] order.
    pieces: [Vec<Vec<Piece>>; 2],
    /// `[side][link]`: the box (centre in the link frame, half extents) holding the link's
    /// pieces — a link whose box misses the part misses it.
    boxes: [Vec<(Vector3<f64>, Vector3<f64>)>; 2],
    /// `[side][link]`: the pieces for the exact test (GJK on their support maps).
    tight: [Vec<Tight>; 2],
    /// `[side][link]`: the link's convex hull as one piece: a link whose hull misses the part
    /// misses it (one GJK per triangle rather than one per piece).
    hulls: [Vec<Tight>; 2],
    /// Per link, the vertices of its hull (the `+x` finger's, link frame).
    hull_points: Vec<Vec<Point3<f64>>>,
    /// `[side][link]`: the largest distance of a piece vertex from the link frame's origin.
    reach: [Vec<f64>; 2],
    /// `[side][link][piece]`: the pieces as solids bounded by planes (how deep a point lies).
    solids: [Vec<Vec<Solid>>; 2],
}

impl FingerShapes {
    /// From each link's pieces ([`FINGER_LINKS`] order) as point sets in the link frame of the
    /// `+x` finger; the other finger's are their mirror images `x → −x`. `None` if a link is
    /// missing or a piece has no volume.
    pub fn new(links: &[Vec<Vec<Point3<f64>>>]) -> Option<FingerShapes> {
        let hulls = links
            .iter()
            .map(|link| hull_of(link.iter().flatten().copied().collect()))
            .collect();
        FingerShapes::with_hulls(links, hulls)
    }

    /// [`FingerShapes::new`] with each link's hull given (`hull_faces`: as [`hull_of`] gives it
    /// for the link's piece vertices in order; the built-in 2F-85's are shared,
    /// [`robotiq_link_hull`]).
    pub(crate) fn with_hulls(
        links: &[Vec<Vec<Point3<f64>>>],
        hull_faces: Vec<HullFaces>,
    ) -> Option<FingerShapes> {
        if links.len() != FINGER_LINKS.len() || hull_faces.len() != links.len() {
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
                            // A piece is a solid: at least four points (`Tight::new` checks).
                            (vertices.len() >= 4).then_some(Piece { vertices })
                        })
                        .collect()
                })
                .collect()
        };
        let boxes = |pieces: &Vec<Vec<Piece>>| -> Vec<(Vector3<f64>, Vector3<f64>)> {
            pieces
                .iter()
                .map(|link| {
                    let mut lo = Vector3::repeat(f64::INFINITY);
                    let mut hi = Vector3::repeat(f64::NEG_INFINITY);
                    for v in link.iter().flat_map(|p| &p.vertices) {
                        lo = lo.inf(&v.coords);
                        hi = hi.sup(&v.coords);
                    }
                    ((lo + hi) * 0.5, (hi - lo) * 0.5)
                })
                .collect()
        };
        let pieces = [side(1.0)?, side(-1.0)?];
        let tight = |pieces: &Vec<Vec<Piece>>| -> Option<Vec<Tight>> {
            pieces
                .iter()
                .map(|link| {
                    Tight::new(&ConvexPieces {
                        pieces: link.iter().map(|p| p.vertices.clone()).collect(),
                        slack: 0.0,
                    })
                })
                .collect()
        };
        let reach = |pieces: &Vec<Vec<Piece>>| -> Vec<f64> {
            pieces
                .iter()
                .map(|link| {
                    link.iter()
                        .flat_map(|p| &p.vertices)
                        .map(|v| v.coords.norm())
                        .fold(0.0, f64::max)
                })
                .collect()
        };
        // Each link's hull once, for the `+x` finger (its vertices and faces, given); the
        // other finger's is its mirror image, with the same faces.
        let right: Vec<Tight> = hull_faces
            .iter()
            .map(|(pts, faces)| Tight::hull(pts.clone(), faces))
            .collect::<Option<_>>()?;
        let left: Vec<Tight> = right
            .iter()
            .map(Tight::mirrored_hull)
            .collect::<Option<_>>()?;
        let hull_points = hull_faces.iter().map(|(pts, _)| pts.clone()).collect();
        let hulls = [right, left];
        let tight = [tight(&pieces[0])?, tight(&pieces[1])?];
        let solids = |pieces: &Vec<Vec<Piece>>| -> Vec<Vec<Solid>> {
            pieces
                .iter()
                .map(|link| link.iter().map(|p| Solid::new(&p.vertices)).collect())
                .collect()
        };
        Some(FingerShapes {
            solids: [solids(&pieces[0]), solids(&pieces[1])],
            hull_points,
            hulls,
            reach: [reach(&pieces[0]), reach(&pieces[1])],
            boxes: [boxes(&pieces[0]), boxes(&pieces[1])],
            tight,
            pieces,
        })
    }
}

impl FingerShapes {
    /// The vertices of link `link`'s hull ([`FINGER_LINKS`] order), in the link frame of the
    /// `+x` finger.
    pub fn hull_points(&self, link: usize) -> &[Point3<f64>] {
        &self.hull_points[link]
    }
}

/// A link's pose as a memo key: (side, link, bits of the planar pose).
type PoseKey = (u8, u8, [u64; 3]);

/// The part and the support at one grasp (see the module documentation).
pub struct PartClosing<'a> {
    object: &'a ObjectGeometry,
    shapes: &'a FingerShapes,
    /// The gripper frame G (the flange) in the object frame.
    flange_in_object: Isometry3<f64>,
    /// The support plane in the object frame: `n · p > d` is below it. `None`: no support.
    support: Option<(Vector3<f64>, f64)>,
    /// The part test's answers by (side, link, pose bits): a closing asks the same pose of a
    /// link many times (the spring link turns about a pivot on the housing, so while it rests
    /// on the part its searches probe the same angles at every driver step).
    memo: RefCell<HashMap<PoseKey, bool, BitsBuildHasher>>,
    /// Per `[side][link]`, the link's last clearance from the part ([`near`]): it misses the
    /// part at every pose that moves none of its points that far.
    free: RefCell<[[Option<Clearance>; 5]; 2]>,
    /// Per `[side][link]`, the triangles near the link and its clearances from them.
    near: RefCell<[[Near; 5]; 2]>,
}

impl<'a> PartClosing<'a> {
    /// The closing world of the part `object` with the gripper at `flange_in_object` (G → object
    /// frame) and the support plane `support` (object frame, see the type).
    pub fn new(
        object: &'a ObjectGeometry,
        shapes: &'a FingerShapes,
        flange_in_object: Isometry3<f64>,
        support: Option<(Vector3<f64>, f64)>,
    ) -> Self {
        PartClosing {
            object,
            shapes,
            flange_in_object,
            support,
            memo: RefCell::new(HashMap::default()),
            free: RefCell::new([[None; 5]; 2]),
            near: RefCell::new(Default::default()),
        }
    }

    /// Whether link `link` of finger `s` is known to miss the part at `pose`: its last
    /// clearance is not used up there.
    fn known_free(&self, s: usize, link: usize, pose: &PlanarPose) -> bool {
        self.free.borrow()[s][link].is_some_and(|c| c.left(pose, self.shapes.reach[s][link]) > 0.0)
    }

    /// Whether link `link` of finger `s` (0: `+x`) touches the part at `pose` (its frame in
    /// the object frame `in_object`); a pose where it does not leaves its clearance.
    fn touches_part(
        &self,
        s: usize,
        link: usize,
        pose: &PlanarPose,
        in_object: &Isometry3<f64>,
    ) -> bool {
        if self.known_free(s, link, pose) {
            return false;
        }
        let (center, half) = &self.shapes.boxes[s][link];
        let tested = Link {
            hull: &self.shapes.hulls[s][link],
            pieces: &self.shapes.tight[s][link],
            solids: &self.shapes.solids[s][link],
            center,
            half,
            reach: self.shapes.reach[s][link],
            in_object,
        };
        let clear = self.near.borrow_mut()[s][link].touches(self.object, &tested, pose);
        match clear {
            None => true,
            Some(gap) => {
                if gap > 0.0 {
                    self.free.borrow_mut()[s][link] = Some(Clearance { at: *pose, gap });
                }
                false
            }
        }
    }
}

impl ClosingWorld for PartClosing<'_> {
    fn has_support(&self) -> bool {
        self.support.is_some()
    }

    fn touch(&self, side: f64, link: usize, pose: &PlanarPose) -> Touch {
        let s = usize::from(side < 0.0);
        if self.support.is_none() && self.known_free(s, link, pose) {
            return Touch::Nothing;
        }
        let key = (
            s as u8,
            link as u8,
            [pose.origin.x, pose.origin.y, pose.angle].map(f64::to_bits),
        );
        let remembered = || self.memo.borrow().get(&key).copied();
        let as_touch = |hit: bool| if hit { Touch::Part } else { Touch::Nothing };
        // Without a support the memo answers before the link is placed.
        if self.support.is_none() {
            if let Some(hit) = remembered() {
                return as_touch(hit);
            }
        }
        let in_object = self.flange_in_object * pose.to_isometry(side);
        if let Some((n, d)) = self.support {
            let below = self.shapes.pieces[s][link]
                .iter()
                .flat_map(|p| p.vertices.iter())
                .any(|v| n.dot(&(in_object * v).coords) > d);
            if below {
                return Touch::Support;
            }
            if let Some(hit) = remembered() {
                return as_touch(hit);
            }
        }
        let hit = self.touches_part(s, link, pose, &in_object);
        self.memo.borrow_mut().insert(key, hit);
        as_touch(hit)
    }
}
