//! The exact tier of the arm links: convex pieces inside each link cylinder.
//!
//! A link shape is tested in two steps. Its cylinder, grown by the pieces' `slack`
//! ([`pregrasp_robot::ConvexPieces`]), bounds its pieces: if the cylinder is clear of the other
//! solid by `margin + slack`, so are the pieces, and the test ends there (most pairs). Only
//! where the cylinder is that close are the pieces tested, each a convex polytope given by its
//! vertices in the link's DH frame, by GJK on parry's support maps stopping as soon as it knows
//! the answer at the margin ([`gjk::within`]), against the other solid's own pieces or
//! primitive. A piece needs no faces at run time: GJK only asks for its
//! support point `argmax_v d·v`, so loading a model builds no hulls. The pieces hug the real
//! link surface (a few millimetres at most, see `crates/robot/data/PROVENANCE.md`), so this is
//! where near-contact outcomes are decided. A pair GJK found apart remembers the separating
//! axis, and the next test of that pair (the next state of a motion) tries it first.

use std::cell::Cell;
use std::ops::ControlFlow;
use std::sync::OnceLock;

use nalgebra::Unit;
use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::query::details::distance_support_map_support_map;
use parry3d_f64::query::gjk::CSOPoint;
use parry3d_f64::shape::{SupportMap, Triangle};
use pregrasp_robot::ConvexPieces;

use crate::gjk;
use crate::shape::{with_primitive, Bounded, Placed};

type P = Point3<f64>;

mod mesh;
mod polytope;

pub(crate) use mesh::{
    any_piece_in, piece_near_triangle_bounded, piece_near_triangle_keyed, piece_triangle_distance,
};
pub(crate) use polytope::Climb;
pub use polytope::{Polytope, BUILD_AFTER};

/// One convex piece, ready for GJK: the polytope in its link frame, its box and a bounding
/// sphere.
#[derive(Clone, Debug)]
pub struct Piece {
    poly: Polytope,
    center: P,
    radius: f64,
    lo: P,
    hi: P,
}

/// The pieces of one link shape and how far they reach outside it.
#[derive(Clone, Debug)]
pub struct Tight {
    pieces: Vec<Piece>,
    /// The hull of all pieces (its vertices, with their graph), built when first asked (arm
    /// links never are): a linear function's least value over the pieces is its least value
    /// over these (the support-plane tests).
    hull: OnceLock<Polytope>,
    slack: f64,
}

impl Tight {
    /// Builds every piece's vertex graph now (see [`Polytope`]): for a world that will serve
    /// many queries. Answers do not change.
    pub fn prepare(&self) {
        for piece in &self.pieces {
            piece.poly.prepare();
        }
    }

    /// The pieces of `src`; `None` if a piece has fewer than four vertices.
    pub fn new(src: &ConvexPieces) -> Option<Tight> {
        let pieces = src
            .pieces
            .iter()
            .map(|pts| {
                if pts.len() < 4 {
                    return None;
                }
                let (lo, hi) = pts.iter().fold(
                    (P::from([f64::INFINITY; 3]), P::from([f64::NEG_INFINITY; 3])),
                    |(lo, hi), p| (lo.inf(p), hi.sup(p)),
                );
                let center = nalgebra::center(&lo, &hi);
                let radius = pts.iter().map(|p| (p - center).norm()).fold(0.0, f64::max);
                Some(Piece {
                    poly: Polytope::new(pts.clone()),
                    center,
                    radius,
                    lo,
                    hi,
                })
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Tight {
            pieces,
            hull: OnceLock::new(),
            slack: src.slack,
        })
    }

    /// One piece: the hull with the vertices `points` and the faces `triangles` (indices into
    /// `points`, as parry's hull gives them), its vertex graph built from the faces (see
    /// [`Polytope`]); `None` with fewer than four vertices.
    pub fn hull(points: Vec<P>, triangles: &[[u32; 3]]) -> Option<Tight> {
        let mut tight = Tight::new(&ConvexPieces {
            pieces: vec![points.clone()],
            slack: 0.0,
        })?;
        tight.pieces[0].poly = Polytope::with_faces(points, triangles);
        Some(tight)
    }

    /// How far the pieces reach outside the link shape (m).
    pub fn slack(&self) -> f64 {
        self.slack
    }

    /// Whether a piece, its frame at `frame` (in the triangle's frame), touches `tri` (GJK,
    /// distance 0, each piece's box tested first).
    /// `tri_key` names the triangle for as long as it lives (e.g. the address of its first
    /// vertex in the mesh): GJK tries first the axis that last separated this piece from it
    /// ([`near_keyed`]; the answer is GJK's either way).
    pub(crate) fn any_piece_touches(
        &self,
        frame: &Isometry3<f64>,
        tri: &Triangle,
        tri_key: usize,
    ) -> bool {
        let (lo, hi) = tri_box(tri);
        let m = frame.rotation.to_rotation_matrix().matrix().abs();
        self.pieces.iter().any(|piece| {
            let c = frame * nalgebra::center(&piece.lo, &piece.hi);
            let ext: Vector3<f64> = m * (0.5 * (piece.hi - piece.lo));
            let (plo, phi) = (c - ext, c + ext);
            let apart = (0..3).any(|i| plo[i] > hi[i] || phi[i] < lo[i]);
            if apart {
                return false;
            }
            let key = (piece as *const Piece as usize, tri_key);
            piece_near_triangle_keyed(key, frame, &Climb::new(&piece.poly), tri, 0.0)
        })
    }

    /// A lower bound of the distance from the pieces, their frame at `frame` (in the
    /// triangle's frame), to `tri`: the least of [`gjk::clearance`] over the pieces, each run
    /// started along the axis that last separated the piece from the triangle (`tri_key` names
    /// it as for [`Tight::any_piece_touches`]), and the axis it found remembered. A piece whose
    /// box lies farther from the triangle's box than the least bound so far is not asked (the
    /// boxes' distance bounds the piece's from below). Stops at the first piece whose bound is
    /// not above `floor`.
    pub(crate) fn clearance(
        &self,
        frame: &Isometry3<f64>,
        tri: &Triangle,
        tri_key: usize,
        floor: f64,
    ) -> f64 {
        let (lo, hi) = tri_box(tri);
        let m = frame.rotation.to_rotation_matrix().matrix().abs();
        let to_link = frame.inverse();
        let centroid = to_link * nalgebra::center(&tri.a, &nalgebra::center(&tri.b, &tri.c));
        let mut least = f64::INFINITY;
        for piece in &self.pieces {
            let c = frame * nalgebra::center(&piece.lo, &piece.hi);
            let ext: Vector3<f64> = m * (0.5 * (piece.hi - piece.lo));
            let boxes = Vector3::from_fn(|i, _| {
                (lo[i] - (c[i] + ext[i]))
                    .max((c[i] - ext[i]) - hi[i])
                    .max(0.0)
            });
            if boxes.norm() >= least {
                continue;
            }
            let key = (piece as *const Piece as usize, tri_key);
            let toward = centroid - piece.center;
            let poly = Climb::new(&piece.poly);
            least = least.min(clearance_keyed(key, &to_link, &poly, tri, &toward));
            if least <= floor {
                break;
            }
        }
        least
    }

    /// [`Tight::clearance`] of the first piece alone (a link's hull), warm-started from what
    /// `warm` remembers of the last run on this pair, which it then remembers; `upper` bounds
    /// the distance from above where the caller knows a bound (`∞` else). The lower bound and
    /// GJK's upper one.
    pub(crate) fn hull_clearance(
        &self,
        frame: &Isometry3<f64>,
        tri: &Triangle,
        warm: &mut Warm,
        upper: f64,
    ) -> (f64, f64) {
        let piece = &self.pieces[0];
        let to_link = frame.inverse();
        let dir = warm.axis.unwrap_or_else(|| {
            let centroid = to_link * nalgebra::center(&tri.a, &nalgebra::center(&tri.b, &tri.c));
            Unit::try_new(centroid - piece.center, f64::EPSILON).unwrap_or_else(Vector3::x_axis)
        });
        let poly = Climb::from(&piece.poly, warm.vertex);
        let (gap, axis, upper) = gjk::clearance(&to_link, &poly, tri, &dir, upper);
        warm.vertex = poly.at();
        if gap > 0.0 {
            warm.axis = Some(axis);
        }
        (gap, upper)
    }

    /// World `z` of the lowest vertex of the pieces with their frame at `frame`: the hull's
    /// support point along the world's `−z` (in the pieces' frame), by a climb over its vertex
    /// graph — the vertex a scan would find, so the same number as the least height over all.
    pub fn lowest(&self, frame: &Isometry3<f64>) -> f64 {
        self.lowest_on(frame, || {
            let all: Vec<P> = self
                .pieces
                .iter()
                .flat_map(|p| p.poly.points.iter())
                .copied()
                .collect();
            // The vertex graph from the faces of this one hull (as `Tight::hull` builds it):
            // `prepare` on the hull's vertices would hull them a second time, about as dear as
            // the first. The climb's answer is the scan's with either graph.
            match crate::baked_hulls::convex_hull(&all) {
                Some((verts, faces)) => Polytope::with_faces(verts, &faces),
                None => Polytope::new(all),
            }
        })
    }

    /// These pieces with the hull of all of them given now (instead of built when first asked):
    /// a hull of the same points from elsewhere, its vertices the pieces' extreme points bit for
    /// bit, so every least height is the same number. Given once, before any query, it is the
    /// one hull every query uses, whichever thread asks first.
    pub(crate) fn with_hull(self, hull: Polytope) -> Tight {
        let _ = self.hull.set(hull);
        self
    }

    /// [`Tight::lowest`] with the hull of all pieces built by `hull` where it is not yet built:
    /// a hull of the same points from elsewhere (its vertices the pieces' extreme points, bit
    /// for bit), so the least height is the same number.
    pub(crate) fn lowest_on(&self, frame: &Isometry3<f64>, hull: impl FnOnce() -> Polytope) -> f64 {
        let row = crate::distance::world_up_in(frame);
        let hull = self.hull.get_or_init(hull);
        // `(−row)·v` is `−(row·v)` to the bit: the farthest vertex along `−row` is the first
        // lowest one.
        let v = Climb::new(hull).local_support_point(&-row);
        row.dot(&v.coords) + frame.translation.vector.z
    }
}

/// What [`Tight::hull_clearance`] remembers of a pair between runs: the axis that last
/// separated it and the vertex where the last climb of support points ended.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Warm {
    axis: Option<Unit<Vector3<f64>>>,
    vertex: Option<u32>,
}

/// The axis-aligned box of a triangle.
fn tri_box(tri: &Triangle) -> (P, P) {
    (tri.a.inf(&tri.b).inf(&tri.c), tri.a.sup(&tri.b).sup(&tri.c))
}

/// A link's pieces placed by its DH frame (link → world).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Posed<'a> {
    pub tight: &'a Tight,
    pub frame: &'a Isometry3<f64>,
}

/// Where an arm shape's exact pieces are: the arm's table of pieces, its parts (for the DH
/// frame of shape `k`) and its posed frames.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lookup<'a> {
    pub tight: &'a [Option<Tight>],
    pub parts: &'a [(usize, pregrasp_robot::Primitive)],
    pub frames: &'a [Isometry3<f64>; 7],
    /// The gripper's pieces per gripper shape (index `k − parts.len()`) and their frames.
    pub gripper_tight: &'a [Option<Tight>],
    pub gripper_frames: &'a [Isometry3<f64>],
    pub k: usize,
}

/// One solid taking part in a pair test: a placed primitive with its bounding sphere and slack,
/// and where to find its pieces if it has them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Part<'a> {
    pub bounded: &'a Bounded,
    pub lookup: Option<Lookup<'a>>,
}

impl<'a> Part<'a> {
    /// A solid that is its primitive.
    #[inline]
    pub fn plain(bounded: &'a Bounded) -> Self {
        Part {
            bounded,
            lookup: None,
        }
    }

    /// The placed primitive (the bound of the pieces, grown by [`slack`](Self::slack)).
    #[inline]
    pub fn shape(&self) -> &'a Placed {
        &self.bounded.shape
    }

    /// How far the exact solid may reach outside [`shape`](Self::shape).
    #[inline]
    pub fn slack(&self) -> f64 {
        self.bounded.slack
    }

    /// The exact pieces placed by their link frame, if the solid has them.
    #[inline]
    pub fn tight(&self) -> Option<Posed<'a>> {
        let l = self.lookup?;
        match l.parts.get(l.k) {
            Some((frame, _)) => Some(Posed {
                tight: l.tight.get(l.k)?.as_ref()?,
                frame: &l.frames[*frame],
            }),
            None => {
                let j = l.k - l.parts.len();
                Some(Posed {
                    tight: l.gripper_tight.get(j)?.as_ref()?,
                    frame: l.gripper_frames.get(j)?,
                })
            }
        }
    }

    /// Calls `f(key, pose, convex, inflation)` for each convex part of the exact solid,
    /// stopping when it breaks: the pieces (inflation 0) whose bounding sphere comes within
    /// `reach` of the sphere `(c, r)`, or the primitive itself (capsule: its segment inflated by
    /// the radius; rounded cylinder: its core inflated by the border). `key` names the part for
    /// as long as it lives: its piece's address, or the primitive's.
    fn each_convex(
        &self,
        near: Option<(&P, f64)>,
        mut f: impl FnMut(usize, &Isometry3<f64>, &dyn SupportMap, f64) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        match self.tight() {
            Some(Posed { tight, frame }) => {
                for piece in &tight.pieces {
                    if let Some((c, reach)) = near {
                        let d = reach + piece.radius;
                        if (frame * piece.center - c).norm_squared() > d * d {
                            continue;
                        }
                    }
                    let key = piece as *const Piece as usize;
                    f(key, frame, &Climb::new(&piece.poly), 0.0)?;
                }
                ControlFlow::Continue(())
            }
            None => {
                let key = self.bounded as *const Bounded as usize;
                with_primitive(self.shape(), |pose, shape, inflation| {
                    f(key, pose, shape, inflation)
                })
            }
        }
    }

    /// Height of the exact solid's lowest point above the plane `z = height`.
    pub fn plane_distance(&self, height: f64) -> Option<f64> {
        let Posed { tight, frame } = self.tight()?;
        Some(tight.lowest(frame) - height)
    }
}

/// Whether two convex shapes at `p1`, `p2` come within `dist` of each other (GJK, stopping as
/// soon as it knows: [`gjk::within`]). The tests compare [`near_keyed`] with it.
#[cfg(test)]
#[inline]
fn near(
    p1: &Isometry3<f64>,
    g1: &dyn SupportMap,
    p2: &Isometry3<f64>,
    g2: &dyn SupportMap,
    dist: f64,
) -> bool {
    gjk::within(&p1.inv_mul(p2), g1, g2, dist, None).is_ok()
}

/// Whether two convex shapes at `p1`, `p2` come within `dist` of each other, by GJK
/// ([`gjk::within`]), for two convex bodies named `key`, trying first the axis that last separated
/// them on this thread ([`SEPARATORS`]): along a motion the pairs change little between
/// checks, and an axis that still shows them apart by more than `dist` settles the question
/// with one support point each — GJK's own test of an axis, so the answer is GJK's (a
/// remembered axis only speaks where the gap exceeds `dist` by [`gjk::GUARD`], well past
/// where GJK's bounds agree). Where it does not, GJK starts from that axis's support point
/// ([`gjk::within_from`], again only taken clear of `dist` by the guard), and from its usual
/// start where that leaves the answer open.
fn near_keyed(
    key: (usize, usize),
    p1: &Isometry3<f64>,
    g1: &dyn SupportMap,
    p2: &Isometry3<f64>,
    g2: &dyn SupportMap,
    dist: f64,
) -> bool {
    near_keyed_bounded(key, p1, g1, None, p2, g2, dist)
}

/// [`near_keyed`] with, if given, a box `(centre, half)` holding `g1` in its own frame. Along
/// the remembered axis `d` the box reaches `d·c + Σ|d_i| h_i`, no less than `g1`'s support
/// point does, so a gap it shows beyond `dist + GUARD` is one the support point shows too, and
/// the answer (apart) is the one the support point gives — without asking `g1` for it.
fn near_keyed_bounded(
    key: (usize, usize),
    p1: &Isometry3<f64>,
    g1: &dyn SupportMap,
    g1_box: Option<&(P, Vector3<f64>)>,
    p2: &Isometry3<f64>,
    g2: &dyn SupportMap,
    dist: f64,
) -> bool {
    let pos12 = p1.inv_mul(p2);
    let slot = separator_slot(key);
    let cached = SEPARATORS.with(|s| {
        let (k, dir) = s[slot].get();
        (k == key).then_some(dir)
    });
    let mut answer = None;
    if let Some(dir) = cached {
        if let Some((c, h)) = g1_box {
            let reach1 = dir.dot(&c.coords) + dir.abs().dot(h);
            let s2 = g2.support_point(&pos12, &-dir);
            if dir.dot(&s2.coords) - reach1 > dist + gjk::GUARD {
                return false;
            }
        }
        // GJK's own test of an axis: the shapes are farther apart along it than `dist` (the
        // remembered axis stays).
        let cso = CSOPoint::from_shapes(&pos12, g1, g2, &dir);
        if -dir.dot(&cso.point.coords) > dist + gjk::GUARD {
            return false;
        }
        // Not by enough: GJK from there, where its answer is sure.
        answer = gjk::within_from(&pos12, g1, g2, dist, cso);
    }
    match answer.unwrap_or_else(|| gjk::within(&pos12, g1, g2, dist, None)) {
        Ok(()) => true,
        Err(dir) => {
            SEPARATORS.with(|s| s[slot].set((key, dir)));
            false
        }
    }
}

/// [`gjk::clearance`] of the pair `key` (the second shape at `pos12` in the first's frame),
/// started along the axis that last separated the pair, else along `toward` (from the first
/// towards the second); a separating axis found is remembered for the pair.
fn clearance_keyed(
    key: (usize, usize),
    pos12: &Isometry3<f64>,
    g1: &dyn SupportMap,
    g2: &dyn SupportMap,
    toward: &Vector3<f64>,
) -> f64 {
    let slot = separator_slot(key);
    let dir = SEPARATORS
        .with(|s| {
            let (k, dir) = s[slot].get();
            (k == key).then_some(dir)
        })
        .or_else(|| Unit::try_new(*toward, f64::EPSILON))
        .unwrap_or_else(Vector3::x_axis);
    let (gap, axis, _) = gjk::clearance(pos12, g1, g2, &dir, f64::INFINITY);
    if gap > 0.0 {
        SEPARATORS.with(|s| s[slot].set((key, axis)));
    }
    gap
}

/// A pair of convex bodies (their keys) and the axis that last separated them.
type Separator = ((usize, usize), Unit<Vector3<f64>>);

/// Slots of [`SEPARATORS`] (pairs hashed into them).
const SEPARATOR_SLOTS: usize = 1024;

thread_local! {
    /// Per pair of convex bodies (by address: a piece, or a primitive in the posed buffers or
    /// the world), the axis GJK last separated them along, in the first one's frame. A slot
    /// holds one pair; a stale or foreign axis costs one support point each and decides
    /// nothing.
    static SEPARATORS: [Cell<Separator>; SEPARATOR_SLOTS] =
        std::array::from_fn(|_| Cell::new(((0, 0), Vector3::x_axis())));
}

/// The slot of a pair of keys.
fn separator_slot((a, b): (usize, usize)) -> usize {
    let h = (a as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (b as u64).rotate_left(29);
    (h.wrapping_mul(0xBF58_476D_1CE4_E5B9) >> 54) as usize % SEPARATOR_SLOTS
}

/// Whether the exact solids of `s1` and `s2` come within `margin` of each other.
pub(crate) fn within(s1: &Part, s2: &Part, margin: f64) -> bool {
    let (b1, b2) = (s1.bounded, s2.bounded);
    s1.each_convex(Some((&b2.center, b2.radius + margin)), |k1, p1, g1, e1| {
        s2.each_convex(Some((&b1.center, b1.radius + margin)), |k2, p2, g2, e2| {
            if near_keyed((k1, k2), p1, g1, p2, g2, margin + e1 + e2) {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
    })
    .is_break()
}

/// Distance between the exact solids of `s1` and `s2` (`0` in contact).
pub(crate) fn distance(s1: &Part, s2: &Part) -> f64 {
    let mut best = f64::INFINITY;
    let _ = s1.each_convex(None, |_, p1, g1, e1| {
        s2.each_convex(None, |_, p2, g2, e2| {
            let d = distance_support_map_support_map(&p1.inv_mul(p2), g1, g2) - e1 - e2;
            best = best.min(d.max(0.0));
            ControlFlow::Continue(())
        })
    });
    best
}

#[cfg(test)]
mod tests;
