//! Clearances: what spares [`PartClosing`](super::PartClosing) most of its exact tests.
//!
//! A link found at least `g` from the part at pose `a` misses the part at every pose `b` that
//! moves none of its points `g` or farther. A point of the link at `r` from its frame's origin
//! moves at most `|Δorigin| + |Δangle| · r` from `a` to `b` (the turn about the origin carries
//! it along an arc no longer than that), so with `reach` the largest such `r` of the link,
//! `moved(a, b) = |Δorigin| + |Δangle| · reach` bounds every point's move ([`moved`]), and
//! `g − moved(a, b) > 0` is the link's certificate of being free at `b` ([`Clearance`]).
//!
//! Clearances come from two bounds:
//! - **far**: the triangles that meet the link's box grown by [`NEAR`] at `a` (the gathered
//!   ones, [`Near`]) are all the part has within [`NEAR`] of the link there;
//! - **near**: for each gathered triangle, GJK's lower bound of its distance from the link's
//!   hull, or where the hull meets it from each of the link's pieces ([`gjk::clearance`]: a
//!   support plane of the Minkowski difference, a true lower bound whatever GJK's tolerances).
//!
//! A gathered triangle is tested again only once the link has moved by its own clearance; a
//! closing stepping towards the part thus tests it about as often as the distance halves, not
//! at every step. Where no bound clears a triangle by more than [`gjk::GUARD`] (in contact, or
//! within GJK's tolerance of it), the exact test decides as it always did: the box's separating
//! axes, then GJK on the hull and the pieces at distance 0. A clearance is only taken where it
//! exceeds the guard, and only for poses that leave the link farther than the guard from the
//! triangle, where the exact test could not say *touch*: the answers are the exact test's.

use std::sync::OnceLock;

use nalgebra::{Isometry3, Point3, Translation3, Vector3};
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::Triangle;
use pregrasp_robot::PlanarPose;

use crate::distance::triangle_box_intersect;
use crate::gjk::GUARD;
use crate::object::ObjectGeometry;
use crate::tight::{Tight, Warm};

/// How far a link's box is grown to gather the triangles near it (m): a triangle that misses
/// the grown box is farther than this from every point of the link.
pub(super) const NEAR: f64 = 0.004;
/// How far the link may move from where its triangles were gathered before they are gathered
/// again (m): the ones not gathered stay at least `NEAR − REGATHER` away.
const REGATHER: f64 = 0.5 * NEAR;

/// The largest distance a point of a link (at most `reach` from its frame's origin) moves from
/// pose `a` to pose `b`, bounded from above (see the module documentation).
pub(super) fn moved(a: &PlanarPose, b: &PlanarPose, reach: f64) -> f64 {
    (b.origin - a.origin).norm() + (b.angle - a.angle).abs() * reach
}

/// A pose of a link at which it is at least `gap` from something (the part, or a triangle).
#[derive(Clone, Copy, Debug)]
pub(super) struct Clearance {
    pub at: PlanarPose,
    pub gap: f64,
}

impl Clearance {
    /// What is left of the clearance at `pose` (a link reaching `reach`): positive where the
    /// link is still clear.
    pub fn left(&self, pose: &PlanarPose, reach: f64) -> f64 {
        self.gap - moved(&self.at, pose, reach)
    }
}

/// A triangle of the part near a link, and the link's clearance from it when last tested.
#[derive(Clone, Debug)]
struct Candidate {
    tri: Triangle,
    /// The triangle's name for the separating-axis cache (the address of its first vertex).
    key: usize,
    /// The addresses of its three vertices: its name among the gathered triangles (vertices
    /// are shared, so the first alone does not name it).
    corners: [usize; 3],
    clear: Option<Clearance>,
    /// Whether the link touched it when last tested.
    touched: bool,
    /// A pose at which a piece of the link held a point of the triangle `gap` deep: the link
    /// touches the triangle at every pose that moves none of its points that far.
    contact: Option<Clearance>,
    /// A pose and an upper bound of the hull's distance from the triangle there (GJK's).
    upper: Option<Clearance>,
    /// Where GJK on the hull and the triangle starts next.
    warm: Warm,
}

/// The triangles of the part near one link (see the module documentation).
#[derive(Clone, Debug, Default)]
pub(super) struct Near {
    /// Where they were gathered.
    at: Option<PlanarPose>,
    tris: Vec<Candidate>,
}

/// One link as [`Near::touches`] tests it: its hull and pieces, its box (centre in the link
/// frame, half extents) and reach, and its frame in the object frame.
pub(super) struct Link<'a> {
    pub hull: &'a Tight,
    pub pieces: &'a Tight,
    pub solids: &'a [Solid],
    pub center: &'a Vector3<f64>,
    pub half: &'a Vector3<f64>,
    pub reach: f64,
    pub in_object: &'a Isometry3<f64>,
}

impl Near {
    /// Whether `link` at `pose` touches the part: `None` if it does, else a clearance of the
    /// link at `pose` (`≤ 0`: none worth keeping).
    pub fn touches(
        &mut self,
        object: &ObjectGeometry,
        link: &Link,
        pose: &PlanarPose,
    ) -> Option<f64> {
        let box_pose = link.in_object * Translation3::from(*link.center);
        let stale = self
            .at
            .is_none_or(|at| moved(&at, pose, link.reach) > REGATHER);
        if stale {
            self.gather(object, &box_pose, link.half, pose);
        }
        let gathered = self.at.as_ref().expect("gathered above");
        let mut clear = NEAR - moved(gathered, pose, link.reach);
        for k in 0..self.tris.len() {
            let cand = &mut self.tris[k];
            let inside = cand.contact.is_some_and(|c| c.left(pose, link.reach) > 0.0);
            let left = cand.clear.map_or(0.0, |c| c.left(pose, link.reach));
            if left > 0.0 {
                clear = clear.min(left);
                continue;
            }
            let tested = if inside {
                None
            } else {
                triangle_clearance(link, &box_pose, pose, cand)
            };
            let Some(gap) = tested else {
                // Asked first next time: a link in contact mostly stays so.
                self.tris.swap(0, k);
                return None;
            };
            cand.clear = (gap > 0.0).then_some(Clearance { at: *pose, gap });
            clear = clear.min(gap);
        }
        Some(clear)
    }

    /// Gathers the triangles that meet the link's box (`half` at `box_pose`) grown by [`NEAR`],
    /// the link at `pose`; a triangle gathered before keeps its clearance.
    fn gather(
        &mut self,
        object: &ObjectGeometry,
        box_pose: &Isometry3<f64>,
        half: &Vector3<f64>,
        pose: &PlanarPose,
    ) {
        let before = std::mem::take(&mut self.tris);
        let mut tris = Vec::with_capacity(before.len());
        object.any_triangle_in_box(box_pose, &(half + Vector3::repeat(NEAR)), |a, b, c| {
            let corners = [a, b, c].map(|p| p as *const _ as usize);
            let known = before.iter().find(|t| t.corners == corners);
            let clear = known.and_then(|t| t.clear);
            tris.push(Candidate {
                tri: Triangle::new(*a, *b, *c),
                key: corners[0],
                corners,
                clear,
                touched: known.is_some_and(|t| t.touched),
                contact: known.and_then(|t| t.contact),
                upper: known.and_then(|t| t.upper),
                warm: known.map_or_else(Warm::default, |t| t.warm),
            });
            false
        });
        self.tris = tris;
        self.at = Some(*pose);
    }
}

/// The clearance of `link` from one triangle, `None` where it touches it: GJK's lower bound for
/// the link's hull, else for its pieces, less [`GUARD`] ([`bound`]); where neither clears the
/// triangle by more than [`GUARD`], the exact test decides ([`exact`]), and a triangle it finds
/// apart is clear by 0 (nothing to skip). A triangle the link touched when last tested is put
/// to the exact test first.
fn triangle_clearance(
    link: &Link,
    box_pose: &Isometry3<f64>,
    pose: &PlanarPose,
    cand: &mut Candidate,
) -> Option<f64> {
    if cand.touched {
        if touching(link, box_pose, pose, cand) {
            return None;
        }
        cand.touched = false;
        return Some(bound(link, pose, cand).max(0.0));
    }
    let gap = bound(link, pose, cand);
    if gap > 0.0 {
        return Some(gap);
    }
    cand.touched = touching(link, box_pose, pose, cand);
    (!cand.touched).then_some(0.0)
}

/// Whether the link at `pose` touches the triangle: by a point of it deeper than [`GUARD`] in a
/// piece ([`depth`], which leaves the candidate its contact), else by the exact test.
fn touching(
    link: &Link,
    box_pose: &Isometry3<f64>,
    pose: &PlanarPose,
    cand: &mut Candidate,
) -> bool {
    let deep = depth(link, &cand.tri);
    if deep > GUARD {
        cand.contact = Some(Clearance {
            at: *pose,
            gap: deep - GUARD,
        });
        return true;
    }
    exact(link, box_pose, cand)
}

/// How deep a point of the triangle lies in a piece of the link, at least (`≤ 0`: none found):
/// per piece whose box meets the triangle's (link frame), the point of the triangle nearest the
/// piece's centre, and its depth there ([`Solid::depth`]). A point `x` of the triangle `p` deep
/// in a piece has the ball of radius `p` about it inside the piece; a move of the link that
/// carries no point of it `p` or farther carries that ball to one that still holds `x`.
fn depth(link: &Link, tri: &Triangle) -> f64 {
    let to_link = link.in_object.inverse();
    let tri = Triangle::new(to_link * tri.a, to_link * tri.b, to_link * tri.c);
    let (lo, hi) = (tri.a.inf(&tri.b).inf(&tri.c), tri.a.sup(&tri.b).sup(&tri.c));
    link.solids
        .iter()
        .filter(|s| (0..3).all(|i| s.lo[i] <= hi[i] && lo[i] <= s.hi[i]))
        .map(|s| s.depth(&tri.project_local_point(&s.center, true).point))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// GJK's lower bound of the distance from the link at `pose` to the triangle, for its hull,
/// else (where the hull is not clear of it by more than [`GUARD`]) for its pieces, less
/// [`GUARD`]. The hull's run starts where the last one on this triangle ended and stops sooner
/// for the upper bound that run left: the distance then, plus how far the link has moved.
fn bound(link: &Link, pose: &PlanarPose, cand: &mut Candidate) -> f64 {
    let known = cand
        .upper
        .map_or(f64::INFINITY, |u| u.gap + moved(&u.at, pose, link.reach));
    let (hull, upper) = link
        .hull
        .hull_clearance(link.in_object, &cand.tri, &mut cand.warm, known);
    cand.upper = Some(Clearance {
        at: *pose,
        gap: upper,
    });
    if hull > GUARD {
        return hull - GUARD;
    }
    link.pieces
        .clearance(link.in_object, &cand.tri, cand.key, GUARD)
        - GUARD
}

/// The exact test of the link against one triangle, as [`ObjectGeometry::any_triangle_in_box`]
/// makes it for the link's box: the box's separating axes (in the box's frame), then GJK at
/// distance 0 on the hull and on the pieces.
fn exact(link: &Link, box_pose: &Isometry3<f64>, cand: &Candidate) -> bool {
    let (tri, key) = (&cand.tri, cand.key);
    let rot = box_pose.rotation.to_rotation_matrix();
    let to_box = rot.matrix().transpose();
    let c = Point3::from(box_pose.translation.vector);
    let local = |p: &Point3<f64>| Point3::from(to_box * (p - c));
    triangle_box_intersect(&local(&tri.a), &local(&tri.b), &local(&tri.c), link.half)
        && link.hull.any_piece_touches(link.in_object, tri, key)
        && link.pieces.any_piece_touches(link.in_object, tri, key)
}

/// A convex piece as the planes that bound it (link frame), with its box and centre. The planes
/// are found when first asked for: most pieces never are.
#[derive(Clone, Debug)]
pub(super) struct Solid {
    vertices: Vec<Point3<f64>>,
    /// Outward unit normals `n` and offsets `d`: the piece is `{x : n · x ≤ d}` for all.
    planes: OnceLock<Vec<(Vector3<f64>, f64)>>,
    lo: Point3<f64>,
    hi: Point3<f64>,
    center: Point3<f64>,
}

impl Solid {
    /// The piece spanned by `vertices`.
    pub fn new(vertices: &[Point3<f64>]) -> Solid {
        let (lo, hi) = vertices.iter().fold(
            (
                Point3::from([f64::INFINITY; 3]),
                Point3::from([f64::NEG_INFINITY; 3]),
            ),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        );
        Solid {
            vertices: vertices.to_vec(),
            planes: OnceLock::new(),
            lo,
            hi,
            center: nalgebra::center(&lo, &hi),
        }
    }

    /// How deep `x` lies in the piece: its distance from the nearest bounding plane, negative
    /// outside.
    pub fn depth(&self, x: &Point3<f64>) -> f64 {
        self.planes
            .get_or_init(|| planes(&self.vertices))
            .iter()
            .map(|(n, d)| d - n.dot(&x.coords))
            .fold(f64::INFINITY, f64::min)
    }
}

/// The planes bounding the hull of `vertices`: one per face of the hull, facing away from the
/// vertices' centroid, through the face's farthest corner along it. Where the hull has a sliver
/// face (whose plane its corners fix poorly) or cannot be computed, one plane no point is inside
/// of: then no depth is ever positive.
fn planes(vertices: &[Point3<f64>]) -> Vec<(Vector3<f64>, f64)> {
    let faces: Vec<[Point3<f64>; 3]> = crate::baked_hulls::convex_hull(vertices)
        .map(|(pts, faces)| faces.iter().map(|f| f.map(|k| pts[k as usize])).collect())
        .unwrap_or_default();
    let sliver = |[a, b, c]: &[Point3<f64>; 3]| {
        let (u, v) = (b - a, c - a);
        u.cross(&v).norm() <= 1e-6 * u.norm() * v.norm()
    };
    if faces.len() < 4 || faces.iter().any(sliver) {
        return vec![(Vector3::x(), f64::NEG_INFINITY)];
    }
    let centroid = Point3::from(
        vertices.iter().map(|v| v.coords).sum::<Vector3<f64>>() / vertices.len() as f64,
    );
    faces
        .iter()
        .map(|[a, b, c]| {
            let n = (b - a).cross(&(c - a)).normalize();
            let n = if n.dot(&(a - centroid)) >= 0.0 { n } else { -n };
            let d = n.dot(&a.coords).max(n.dot(&b.coords)).max(n.dot(&c.coords));
            (n, d)
        })
        .collect()
}
