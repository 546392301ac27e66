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
use std::collections::HashMap;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicU32, Ordering};
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

/// A convex polytope as the convex hull of its vertices (link frame); its support point in a
/// direction is the vertex farthest along it, the first in order where several are.
///
/// The pieces have 37–410 vertices, and GJK asks for a support point a few times per query, so
/// a scan over all of them is most of a near-contact test. A polytope asked often enough
/// ([`BUILD_AFTER`] scans) builds its hull's vertex graph (`Graph`) and from then on climbs it;
/// the answer is the scan's, vertex for vertex, so when the graph is built does not show.
#[derive(Debug)]
pub struct Polytope {
    points: Vec<P>,
    scans: AtomicU32,
    graph: OnceLock<Option<Graph>>,
}

/// Scans of a polytope before it builds its vertex graph: building costs about what a few
/// hundred scans of its vertices cost, so a part asked a few times never pays for it and one
/// asked often pays at most twice what it would with the graph from the start.
pub const BUILD_AFTER: u32 = 1024;

impl Clone for Polytope {
    fn clone(&self) -> Self {
        Polytope {
            points: self.points.clone(),
            scans: AtomicU32::new(self.scans.load(Ordering::Relaxed)),
            graph: self.graph.clone(),
        }
    }
}

impl Polytope {
    /// The polytope spanned by `points`.
    pub(crate) fn new(points: Vec<P>) -> Self {
        Polytope {
            points,
            scans: AtomicU32::new(0),
            graph: OnceLock::new(),
        }
    }

    /// The hull's vertex graph once the polytope has been asked [`BUILD_AFTER`] times (`None`
    /// before, or where no graph answers like the scan: see [`Graph::new`]).
    #[inline]
    fn graph(&self) -> Option<&Graph> {
        if let Some(g) = self.graph.get() {
            return g.as_ref();
        }
        // A count, not an exact one: threads may lose each other's increments, and a plain
        // load and store cost no locked instruction on the scans' path.
        let scans = self.scans.load(Ordering::Relaxed);
        if scans < BUILD_AFTER {
            self.scans.store(scans + 1, Ordering::Relaxed);
            return None;
        }
        self.graph.get_or_init(|| Graph::new(&self.points)).as_ref()
    }

    /// Builds the vertex graph now rather than after [`BUILD_AFTER`] scans.
    fn prepare(&self) {
        self.graph.get_or_init(|| Graph::new(&self.points));
    }

    /// The index of the first vertex farthest along `dir`, by a scan over all vertices.
    #[inline]
    fn scan(&self, dir: &Vector3<f64>) -> u32 {
        parry3d_f64::utils::point_cloud_support_point_id(dir, &self.points) as u32
    }

    /// The index of the support point along `dir`, climbing from `from` where the graph is
    /// built and the start given.
    #[inline]
    fn support_id(&self, dir: &Vector3<f64>, from: Option<u32>) -> u32 {
        match self.graph() {
            Some(g) => g
                .climb(
                    &self.points,
                    dir,
                    from.unwrap_or_else(|| g.start(&self.points, dir)),
                )
                .unwrap_or_else(|| self.scan(dir)),
            None => self.scan(dir),
        }
    }
}

/// A polytope as GJK asks it for support points, in one run or a run of them: each climb starts
/// where the last one ended, since GJK's directions change little from one step to the next
/// (the first at the best of the axis extremes).
pub(crate) struct Climb<'a> {
    poly: &'a Polytope,
    at: Cell<Option<u32>>,
}

impl<'a> Climb<'a> {
    #[inline]
    pub fn new(poly: &'a Polytope) -> Self {
        Climb {
            poly,
            at: Cell::new(None),
        }
    }
}

impl SupportMap for Climb<'_> {
    #[inline]
    fn local_support_point(&self, dir: &Vector3<f64>) -> P {
        let k = self.poly.support_id(dir, self.at.get());
        self.at.set(Some(k));
        self.poly.points[k as usize]
    }
}

/// The vertex graph of a polytope's hull, over the polytope's own vertex indices: for each
/// vertex, the vertices it shares a hull edge with (compressed rows; none for a vertex that
/// repeats an earlier one).
///
/// A linear function `d·x` on a convex polytope has no local maximum but the global one along
/// the hull's edges: if no edge from vertex `v` rises (`d·(w − v) ≤ 0` for every neighbour `w`),
/// the whole polytope lies in the cone of those edges at `v`, so below `d·v`. Climbing from
/// any vertex to a better neighbour until none is better thus ends at a support point, after
/// a few steps from a vertex near it instead of a scan of all.
#[derive(Clone, Debug)]
struct Graph {
    /// Neighbours of vertex `k`: `adjacent[offsets[k]..offsets[k + 1]]`.
    offsets: Vec<u32>,
    adjacent: Vec<u32>,
    /// The vertices farthest along `±x`, `±y`, `±z`: the climbs without a previous point start
    /// from the best of them.
    extremes: [u32; 6],
}

impl Graph {
    /// The graph of the hull of `points`, if it answers exactly like a scan: parry builds the
    /// hull, every point is one of its vertices, repeats an earlier point, lies inside it or on
    /// one of its faces (then joined to that face's vertices), and every hull vertex has at least
    /// three neighbours. Otherwise `None`.
    fn new(points: &[P]) -> Option<Graph> {
        let n = points.len();
        if n < 4 || n >= u32::MAX as usize {
            return None;
        }
        let (verts, triangles) = parry3d_f64::transformation::try_convex_hull(points).ok()?;
        // Hull vertex → the first point with its coordinates.
        let mut first = HashMap::with_capacity(n);
        for (k, p) in points.iter().enumerate() {
            first.entry(coordinate_key(p)).or_insert(k as u32);
        }
        let index: Vec<u32> = verts
            .iter()
            .map(|v| first.get(&coordinate_key(v)).copied())
            .collect::<Option<_>>()?;
        let mut edges: Vec<(u32, u32)> = Vec::with_capacity(6 * triangles.len() + 6);
        for t in &triangles {
            let [a, b, c] = t.map(|i| index[i as usize]);
            for (u, v) in [(a, b), (b, c), (c, a)] {
                edges.push((u, v));
                edges.push((v, u));
            }
        }
        if index.len() != first.len() {
            join_left_out(points, &verts, &triangles, &index, &first, &mut edges)?;
        }
        edges.sort_unstable();
        edges.dedup();
        let mut offsets = vec![0u32; n + 1];
        for &(a, _) in &edges {
            offsets[a as usize + 1] += 1;
        }
        for k in 0..n {
            offsets[k + 1] += offsets[k];
        }
        if index
            .iter()
            .any(|&k| offsets[k as usize + 1] - offsets[k as usize] < 3)
        {
            return None;
        }
        let axis = |d: Vector3<f64>| parry3d_f64::utils::point_cloud_support_point_id(&d, points);
        let extremes = [
            axis(Vector3::x()),
            axis(-Vector3::x()),
            axis(Vector3::y()),
            axis(-Vector3::y()),
            axis(Vector3::z()),
            axis(-Vector3::z()),
        ]
        .map(|k| k as u32);
        Some(Graph {
            offsets,
            adjacent: edges.iter().map(|&(_, b)| b).collect(),
            extremes,
        })
    }

    /// The best of the axis extremes along `dir`: a start a few edges from the support point.
    #[inline]
    fn start(&self, points: &[P], dir: &Vector3<f64>) -> u32 {
        let i = if dir.x >= 0.0 { 0 } else { 1 };
        let j = if dir.y >= 0.0 { 2 } else { 3 };
        let k = if dir.z >= 0.0 { 4 } else { 5 };
        let value = |v: u32| points[v as usize].coords.dot(dir);
        let mut best = self.extremes[i];
        for v in [self.extremes[j], self.extremes[k]] {
            if value(v) > value(best) {
                best = v;
            }
        }
        best
    }

    /// From vertex `from`, the steepest rising neighbour until none rises: the vertex farthest
    /// along `dir`. `None` where a neighbour ties with it (then which of the tied vertices the
    /// scan returns is left to the scan), or the direction is not a number.
    #[inline]
    fn climb(&self, points: &[P], dir: &Vector3<f64>, from: u32) -> Option<u32> {
        let mut at = from as usize;
        // The same expression as the scan's, so that the values compare exactly.
        let value = |k: usize| points[k].coords.dot(dir);
        let mut best = value(at);
        if best.is_nan() {
            return None;
        }
        loop {
            let (lo, hi) = (self.offsets[at] as usize, self.offsets[at + 1] as usize);
            let mut next = at;
            let mut tie = false;
            for &w in &self.adjacent[lo..hi] {
                let v = value(w as usize);
                if v > best {
                    best = v;
                    next = w as usize;
                    tie = false;
                } else if v == best {
                    tie = true;
                }
            }
            if next == at {
                return if tie { None } else { Some(at as u32) };
            }
            at = next;
        }
    }
}

/// Adds to `edges` the points of `points` that the hull (`verts`, `triangles`, hull vertex
/// `i` being point `index[i]`) left out: inside it they are never a support point alone and get
/// no edge; on a face they join that face's vertices, so that a climb sees them tie. `None` where
/// one lies outside (within the hull's tolerance), where the graph would miss it. `first` maps a
/// point's coordinates to the first point with them.
fn join_left_out(
    points: &[P],
    verts: &[P],
    triangles: &[[u32; 3]],
    index: &[u32],
    first: &HashMap<[u64; 3], u32>,
    edges: &mut Vec<(u32, u32)>,
) -> Option<()> {
    const ON: f64 = 1e-12;
    let mut on_hull = vec![false; points.len()];
    for &k in index {
        on_hull[k as usize] = true;
    }
    let centre = verts.iter().fold(Vector3::zeros(), |c, v| c + v.coords) / verts.len() as f64;
    let faces: Vec<([u32; 3], Vector3<f64>, f64)> = triangles
        .iter()
        .filter_map(|t| {
            let [a, b, c] = t.map(|i| verts[i as usize]);
            let mut normal = (b - a).cross(&(c - a)).try_normalize(0.0)?;
            if normal.dot(&(centre - a.coords)) > 0.0 {
                normal = -normal;
            }
            Some((t.map(|i| index[i as usize]), normal, normal.dot(&a.coords)))
        })
        .collect();
    for (k, p) in points.iter().enumerate() {
        if on_hull[k] || first[&coordinate_key(p)] != k as u32 {
            continue;
        }
        let outside = faces
            .iter()
            .map(|(_, nrm, off)| nrm.dot(&p.coords) - off)
            .fold(f64::NEG_INFINITY, f64::max);
        if outside > ON {
            return None;
        }
        if outside < -ON {
            continue;
        }
        let face = faces.iter().find(|(t, nrm, off)| {
            (nrm.dot(&p.coords) - off).abs() <= ON && {
                let [a, b, c] = t.map(|i| points[i as usize]);
                // Inside the triangle: on the inner side of each edge, in its plane.
                [(a, b), (b, c), (c, a)]
                    .iter()
                    .all(|(u, v)| (v - u).cross(&(p - u)).dot(nrm) >= -ON)
            }
        })?;
        for v in face.0 {
            edges.push((k as u32, v));
            edges.push((v, k as u32));
        }
    }
    Some(())
}

/// A point's coordinates as bits: equal keys, equal points.
#[inline]
fn coordinate_key(p: &P) -> [u64; 3] {
    p.coords.map(f64::to_bits).into()
}

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
    /// The vertices of the hull of all pieces, built when first asked (arm links never are):
    /// a linear function's least value over the pieces is its least value over these (the
    /// support-plane tests).
    hull: OnceLock<Vec<P>>,
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

    /// World `z` of the lowest vertex of the pieces with their frame at `frame`.
    pub fn lowest(&self, frame: &Isometry3<f64>) -> f64 {
        let row = frame
            .rotation
            .to_rotation_matrix()
            .matrix()
            .row(2)
            .transpose();
        let hull = self.hull.get_or_init(|| {
            let all: Vec<P> = self
                .pieces
                .iter()
                .flat_map(|p| p.poly.points.iter())
                .copied()
                .collect();
            hull_points(&all)
        });
        let low = hull
            .iter()
            .map(|v| row.dot(&v.coords))
            .fold(f64::INFINITY, f64::min);
        low + frame.translation.vector.z
    }
}

/// The axis-aligned box of a triangle.
fn tri_box(tri: &Triangle) -> (P, P) {
    (tri.a.inf(&tri.b).inf(&tri.c), tri.a.sup(&tri.b).sup(&tri.c))
}

/// The points of `all` that are vertices of its convex hull, exactly as given (parry returns
/// the input points it keeps); every point where no hull can be computed.
pub(crate) fn hull_points(all: &[P]) -> Vec<P> {
    match parry3d_f64::transformation::try_convex_hull(all) {
        Ok((verts, _)) => verts,
        Err(_) => all.to_vec(),
    }
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
    let pos12 = p1.inv_mul(p2);
    let slot = separator_slot(key);
    let cached = SEPARATORS.with(|s| {
        let (k, dir) = s[slot].get();
        (k == key).then_some(dir)
    });
    let mut answer = None;
    if let Some(dir) = cached {
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

/// Calls `f(piece pose in the mesh frame, polytope, piece's box in the mesh frame, piece key)`
/// for each piece of `t`, a mesh being at `mesh_pose`, until it returns `true`. The key names
/// the piece for as long as it lives (its address), for [`piece_near_triangle_keyed`].
pub(crate) fn any_piece_in(
    t: &Posed,
    mesh_pose: &Isometry3<f64>,
    mut f: impl FnMut(&Isometry3<f64>, &Climb, (P, P), usize) -> bool,
) -> bool {
    let rel = mesh_pose.inv_mul(t.frame);
    let m = rel.rotation.to_rotation_matrix().matrix().abs();
    t.tight.pieces.iter().any(|piece| {
        let c = rel * nalgebra::center(&piece.lo, &piece.hi);
        let ext: Vector3<f64> = m * (0.5 * (piece.hi - piece.lo));
        let key = piece as *const Piece as usize;
        f(&rel, &Climb::new(&piece.poly), (c - ext, c + ext), key)
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

/// Distance from the polytope at `pose` to the triangle (both in one frame; `0` in contact).
#[inline]
pub(crate) fn piece_triangle_distance(pose: &Isometry3<f64>, poly: &Climb, tri: &Triangle) -> f64 {
    distance_support_map_support_map(&pose.inverse(), poly, tri).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::parry_cylinder;
    use parry3d_f64::query;
    use parry3d_f64::shape::{Capsule as PCapsule, ConvexPolyhedron, Cuboid as PCuboid};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A remembered separating axis only ever answers what GJK answers: every piece of the
    /// UR5e against a box moved step by step towards, through and away from it, the box's
    /// clearance asked at a few margins, with and without the axis of the last step.
    #[test]
    fn remembered_axes_answer_as_gjk_does() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (mut asked, mut near_count, mut by_axis) = (0, 0, 0);
        let geometry = pregrasp_robot::arm_geometry(pregrasp_robot::UrModel::Ur5e);
        let boxed = PCuboid::new(Vector3::new(0.03, 0.05, 0.02));
        for (l, link) in geometry.links.iter().enumerate() {
            let Some(src) = link.pieces else { continue };
            for (k, pts) in src.pieces.iter().enumerate() {
                let poly = Polytope::new(pts.clone());
                poly.prepare();
                let climb = Climb::new(&poly);
                let c = pts.iter().fold(Vector3::zeros(), |a, p| a + p.coords) / pts.len() as f64;
                let from = Vector3::from_fn(|_, _| rng.random_range(-0.2..0.2)) + c;
                let to = c - (from - c);
                let turn = Vector3::from_fn(|_, _| rng.random_range(-0.2..0.2));
                for step in 0..60 {
                    let t = step as f64 / 59.0;
                    let pose = Isometry3::new(from + (to - from) * t, turn * t);
                    for margin in [0.0, 0.005, 0.03] {
                        let key = (1000 * l + k, usize::from(margin > 0.0) + 1);
                        let p1 = Isometry3::identity();
                        let cold = near(&p1, &climb, &pose, &boxed, margin);
                        let slot = separator_slot(key);
                        let known = SEPARATORS.with(|s| s[slot].get().0 == key);
                        let keyed = near_keyed(key, &p1, &climb, &pose, &boxed, margin);
                        assert_eq!(
                            keyed, cold,
                            "{} piece {k} step {step} margin {margin}",
                            link.name
                        );
                        asked += 1;
                        near_count += usize::from(cold);
                        by_axis += usize::from(known && !cold);
                    }
                }
            }
        }
        assert!(
            near_count > asked / 10 && by_axis > asked / 3,
            "{asked} asked, {near_count} near, {by_axis} apart with a remembered axis"
        );
    }

    /// Climbing the hull graph finds the vertex a scan finds, for every piece of every UR model,
    /// cold and warm started, in random and axis-aligned directions (where vertices tie).
    #[test]
    fn climbs_find_the_scans_support_points() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (mut pieces, mut graphs) = (0, 0);
        for model in pregrasp_robot::UrModel::ALL {
            let geometry = pregrasp_robot::arm_geometry(model);
            for link in &geometry.links {
                let Some(src) = link.pieces else { continue };
                for pts in &src.pieces {
                    let poly = Polytope::new(pts.clone());
                    let graph = Graph::new(pts);
                    pieces += 1;
                    graphs += usize::from(graph.is_some());
                    let _ = poly.graph.set(graph);
                    let warm = Climb::new(&poly);
                    for k in 0..200 {
                        let dir = if k < 6 {
                            let mut d = Vector3::zeros();
                            d[k / 2] = if k % 2 == 0 { 1.0 } else { -1.0 };
                            d
                        } else {
                            Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0))
                        };
                        let want = parry3d_f64::utils::point_cloud_support_point(&dir, pts);
                        assert_eq!(
                            Climb::new(&poly).local_support_point(&dir),
                            want,
                            "{model} {}",
                            link.name
                        );
                        assert_eq!(
                            warm.local_support_point(&dir),
                            want,
                            "{model} {}",
                            link.name
                        );
                    }
                }
            }
        }
        assert!(pieces > 300, "{pieces} pieces");
        assert!(
            graphs * 10 > pieces * 9,
            "{graphs} graphs of {pieces} pieces"
        );
    }

    /// A polytope builds its graph after [`BUILD_AFTER`] scans, not before.
    #[test]
    fn the_graph_is_built_once_asked_often() {
        let cube: Vec<P> = (0..8)
            .map(|k| P::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64))
            .collect();
        let poly = Polytope::new(cube);
        let dir = Vector3::new(0.3, 0.2, 0.1);
        for _ in 0..BUILD_AFTER {
            let cold = Climb::new(&poly);
            assert_eq!(cold.local_support_point(&dir), P::new(1.0, 1.0, 1.0));
            assert!(poly.graph.get().is_none());
        }
        let climb = Climb::new(&poly);
        assert_eq!(climb.local_support_point(&dir), P::new(1.0, 1.0, 1.0));
        assert!(matches!(poly.graph.get(), Some(Some(_))));
        // A cube's faces tie along the axes: the scan's answer, the first vertex.
        assert_eq!(
            climb.local_support_point(&Vector3::x()),
            P::new(1.0, 0.0, 0.0)
        );
        // Prepared, a polytope climbs from its first question.
        let prepared = Polytope::new(poly.points.clone());
        prepared.prepare();
        assert!(matches!(prepared.graph.get(), Some(Some(_))));
        assert_eq!(
            Climb::new(&prepared).local_support_point(&dir),
            P::new(1.0, 1.0, 1.0)
        );
    }

    /// The support-map GJK on raw vertices agrees with parry's own polyhedron (built as the
    /// hull of the same vertices) against capsules, rounded cylinders, boxes and other pieces:
    /// distances within 1e-5 (GJK's tolerance), and `within` is `distance ≤ margin` away from the boundary.
    #[test]
    fn pieces_agree_with_parry_polyhedra() {
        let mut rng = ChaCha8Rng::seed_from_u64(20);
        let cloud = |rng: &mut ChaCha8Rng, c: Vector3<f64>| -> Vec<P> {
            (0..30)
                .map(|_| P::from(c + Vector3::from_fn(|_, _| rng.random_range(-0.05..0.05))))
                .collect()
        };
        let frame = Isometry3::new(Vector3::new(0.1, -0.2, 0.3), Vector3::new(0.3, -0.5, 0.2));
        let mut checked = 0;
        for k in 0..300 {
            let pts = cloud(&mut rng, Vector3::zeros());
            let tight = Tight::new(&ConvexPieces {
                pieces: vec![pts.clone()],
                slack: 0.0,
            })
            .unwrap();
            let hull = ConvexPolyhedron::from_convex_hull(&pts).unwrap();
            let c = frame * P::from(Vector3::from_fn(|_, _| rng.random_range(-0.15..0.15)));
            let other_pts = cloud(&mut rng, c.coords);
            let (shape, reference) = match k % 4 {
                0 => {
                    let (a, b) = (c, c + Vector3::new(0.05, 0.02, -0.03));
                    let r = 0.02;
                    let d = query::distance(
                        &frame,
                        &hull,
                        &Isometry3::identity(),
                        &PCapsule::new(a, b, r),
                    );
                    (Placed::Capsule { a, b, radius: r }, d.unwrap())
                }
                1 => {
                    let (a, b, r, e) = (c, c + Vector3::new(0.0, 0.06, 0.01), 0.03, 0.005);
                    let (pose, cyl) = parry_cylinder(&a, &b, r);
                    let d = query::distance(&frame, &hull, &pose, &cyl).unwrap() - e;
                    (
                        Placed::Cylinder {
                            a,
                            b,
                            radius: r,
                            border: e,
                        },
                        d.max(0.0),
                    )
                }
                2 => {
                    let pose = Isometry3::new(c.coords, Vector3::new(0.1, 0.7, -0.3));
                    let half = Vector3::new(0.03, 0.01, 0.05);
                    let d = query::distance(&frame, &hull, &pose, &PCuboid::new(half));
                    (Placed::Cuboid { pose, half }, d.unwrap())
                }
                _ => {
                    let other = ConvexPolyhedron::from_convex_hull(&other_pts).unwrap();
                    let d = query::distance(&frame, &hull, &Isometry3::identity(), &other);
                    // The bounding sphere holds the other piece (its points lie within 0.087 of c).
                    (
                        Placed::Capsule {
                            a: c,
                            b: c,
                            radius: 0.09,
                        },
                        d.unwrap(),
                    )
                }
            };
            // Shape 0 of a one-shape arm posed with every DH frame at `frame`.
            let dummy = pregrasp_robot::Primitive::Capsule(pregrasp_robot::Capsule {
                a: P::origin(),
                b: P::origin(),
                radius: 0.0,
            });
            let parts = [(0usize, dummy)];
            let own_table = [Some(tight)];
            let frames = [frame; 7];
            let b1 = Bounded::new(Placed::Capsule {
                a: P::from(frame.translation.vector),
                b: P::from(frame.translation.vector),
                radius: 0.1,
            });
            let s1 = Part {
                bounded: &b1,
                lookup: Some(Lookup {
                    tight: &own_table,
                    parts: &parts,
                    frames: &frames,
                    gripper_tight: &[],
                    gripper_frames: &[],
                    k: 0,
                }),
            };
            let other_table = [Some(
                Tight::new(&ConvexPieces {
                    pieces: vec![other_pts],
                    slack: 0.0,
                })
                .unwrap(),
            )];
            let ids = [Isometry3::identity(); 7];
            let b2 = Bounded::new(shape);
            let s2 = if k % 4 == 3 {
                Part {
                    bounded: &b2,
                    lookup: Some(Lookup {
                        tight: &other_table,
                        parts: &parts,
                        frames: &ids,
                        gripper_tight: &[],
                        gripper_frames: &[],
                        k: 0,
                    }),
                }
            } else {
                Part::plain(&b2)
            };
            let d = distance(&s1, &s2);
            assert!(
                (d - reference).abs() < 1e-5,
                "case {k}: {d} vs parry {reference}"
            );
            for margin in [0.0, 0.005, 0.02] {
                if (reference - margin).abs() > 1e-5 {
                    assert_eq!(
                        within(&s1, &s2, margin),
                        reference <= margin,
                        "case {k}, margin {margin}"
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 800);
    }
}
