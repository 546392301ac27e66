//! A convex polytope given by its vertices and its support point: a scan over the vertices, or,
//! once it has been asked often enough, a climb over its hull's vertex graph (the same answer,
//! vertex for vertex).

use std::cell::Cell;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::OnceLock;

use nalgebra::{Point3, Vector3};
use parry3d_f64::shape::SupportMap;

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
    pub(super) points: Vec<P>,
    scans: AtomicU32,
    pub(super) graph: OnceLock<Option<Graph>>,
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
        self.graph
            .get_or_init(|| Graph::new(&self.points, Hulled::Scanned))
            .as_ref()
    }

    /// The polytope whose hull has the vertices `points` and the faces `triangles` (indices
    /// into `points`, as parry's hull gives them): its vertex graph built now from those faces,
    /// with no hull to compute.
    pub(crate) fn with_faces(points: Vec<P>, triangles: &[[u32; 3]]) -> Self {
        let graph = Graph::from_faces(&points, triangles);
        let poly = Polytope::new(points);
        let _ = poly.graph.set(graph);
        poly
    }

    /// Builds the vertex graph now rather than after [`BUILD_AFTER`] scans.
    pub(super) fn prepare(&self) {
        self.graph
            .get_or_init(|| Graph::new(&self.points, Hulled::Prepared));
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

/// Compressed rows of the pairs `edges` over `n` vertices: `offsets[a]..offsets[a + 1]` in
/// `adjacent` holds the `b` of every pair `(a, b)`, ascending and each once — the rows of
/// `edges` sorted and deduplicated (`adjacency_is_the_sorted_pairs` compares).
pub(super) fn adjacency(n: usize, edges: &[(u32, u32)]) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; n + 1];
    for &(a, _) in edges {
        start[a as usize + 1] += 1;
    }
    for k in 0..n {
        start[k + 1] += start[k];
    }
    let mut fill = start.clone();
    let mut slots = vec![0u32; edges.len()];
    for &(a, b) in edges {
        let at = &mut fill[a as usize];
        slots[*at as usize] = b;
        *at += 1;
    }
    // Each row sorted, its repeats dropped, and moved down to where the rows before it end.
    let mut offsets = vec![0u32; n + 1];
    let mut len = 0usize;
    for a in 0..n {
        let (lo, hi) = (start[a] as usize, start[a + 1] as usize);
        slots[lo..hi].sort_unstable();
        let mut last = None;
        for k in lo..hi {
            let b = slots[k];
            if last != Some(b) {
                slots[len] = b;
                len += 1;
                last = Some(b);
            }
        }
        offsets[a + 1] = len as u32;
    }
    slots.truncate(len);
    (offsets, slots)
}

impl super::Tight {
    /// This hull ([`Tight::hull`](super::Tight::hull)) mirrored `x → −x`: what `Tight::hull`
    /// builds from the mirrored vertices and the same faces, bit for bit, its vertex graph
    /// this one's (the same edges; the `±x` extremes trade places) rather than built again.
    pub(crate) fn mirrored_hull(&self) -> Option<super::Tight> {
        let [piece] = &self.pieces[..] else {
            return None;
        };
        let points: Vec<P> = (piece.poly.points.iter())
            .map(|p| P::new(-p.x, p.y, p.z))
            .collect();
        let mut tight = super::Tight::new(&pregrasp_robot::ConvexPieces {
            pieces: vec![points.clone()],
            slack: 0.0,
        })?;
        let poly = Polytope::new(points);
        if let Some(graph) = piece.poly.graph.get() {
            let _ = poly.graph.set(graph.as_ref().map(Graph::mirrored_x));
        }
        tight.pieces[0].poly = poly;
        Some(tight)
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
        Climb::from(poly, None)
    }

    /// Climbs starting at vertex `at` (where an earlier run ended, say; the answers do not
    /// depend on it).
    #[inline]
    pub fn from(poly: &'a Polytope, at: Option<u32>) -> Self {
        Climb {
            poly,
            at: Cell::new(at),
        }
    }

    /// The vertex the last climb ended at.
    #[inline]
    pub fn at(&self) -> Option<u32> {
        self.at.get()
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

/// Why a polytope's vertex graph is built, which decides where its hull comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Hulled {
    /// Asked for ahead of use ([`Polytope::prepare`]): from the baked table
    /// ([`crate::baked_hulls`]) where it holds the points.
    Prepared,
    /// After [`BUILD_AFTER`] scans: from parry, always. Whether a polytope gets there in a plan
    /// depends on how many scans the queries' warm starts save (their cache is keyed by
    /// addresses), so the table, recorded from plans, cannot count on holding it; and a
    /// polytope scanned that often has spent more on scans than its hull costs.
    Scanned,
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
pub(super) struct Graph {
    /// Neighbours of vertex `k`: `adjacent[offsets[k]..offsets[k + 1]]`.
    offsets: Vec<u32>,
    adjacent: Vec<u32>,
    /// The vertices farthest along `±x`, `±y`, `±z`: the climbs without a previous point start
    /// from the best of them.
    extremes: [u32; 6],
}

impl Graph {
    /// The graph of the vertices mirrored `x → −x`: the same edges, the `±x` extremes swapped
    /// (a vertex's value along `+x` after the mirror is exactly its value along `−x` before).
    fn mirrored_x(&self) -> Graph {
        let mut extremes = self.extremes;
        extremes.swap(0, 1);
        Graph {
            offsets: self.offsets.clone(),
            adjacent: self.adjacent.clone(),
            extremes,
        }
    }

    /// The graph of the hull of `points`, if it answers exactly like a scan: parry builds the
    /// hull, every point is one of its vertices, repeats an earlier point, lies inside it or on
    /// one of its faces (then joined to that face's vertices), and every hull vertex has at least
    /// three neighbours. Otherwise `None`.
    pub(super) fn new(points: &[P], why: Hulled) -> Option<Graph> {
        let n = points.len();
        if n < 4 || n >= u32::MAX as usize {
            return None;
        }
        let (verts, triangles) = match why {
            Hulled::Prepared => crate::baked_hulls::convex_hull(points)?,
            Hulled::Scanned => parry3d_f64::transformation::try_convex_hull(points).ok()?,
        };
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
        Graph::from_edges(points, &edges, &index)
    }

    /// The graph of a hull whose vertices are all of `points`, its faces `triangles`.
    fn from_faces(points: &[P], triangles: &[[u32; 3]]) -> Option<Graph> {
        let n = points.len();
        if n < 4 || n >= u32::MAX as usize {
            return None;
        }
        let mut edges: Vec<(u32, u32)> = Vec::with_capacity(6 * triangles.len());
        for &[a, b, c] in triangles {
            for (u, v) in [(a, b), (b, c), (c, a)] {
                edges.push((u, v));
                edges.push((v, u));
            }
        }
        let all: Vec<u32> = (0..n as u32).collect();
        Graph::from_edges(points, &edges, &all)
    }

    /// The graph of the edges `edges` (both ways) over `points`; `None` unless each of the hull
    /// vertices `hull` has at least three neighbours.
    ///
    /// Each vertex's neighbours ascending and without repeats — what sorting the pairs and
    /// removing repeats gives — by buckets per vertex (counted, filled, each short list sorted
    /// and deduplicated in place, then closed up): linear in the edges, where the sort of all
    /// pairs cost 0.4 M instructions a hull, 3.8 M a process.
    fn from_edges(points: &[P], edges: &[(u32, u32)], hull: &[u32]) -> Option<Graph> {
        let (offsets, adjacent) = adjacency(points.len(), edges);
        if hull
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
            adjacent,
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
