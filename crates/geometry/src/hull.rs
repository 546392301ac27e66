//! Convex hulls with true faces and feature edges.
//!
//! A quickhull (parry3d's `try_convex_hull`) returns a triangulation: every flat face of the hull
//! is cut into triangles whose diagonals are hull edges too. Algorithm 1 of the paper (§IV)
//! takes hull edges as rotation axes, and a diagonal of a flat face is not an edge the part can
//! pivot about. So this module merges the triangles into planar [`HullFace`]s (coplanar within a
//! tolerance) and keeps as **feature edges** only the segments where two different faces meet,
//! each as one segment even if the triangulation split it at collinear vertices.
//!
//! A flat (zero-thickness) point set gets a two-sided hull: one polygon, two faces with opposite
//! normals, the polygon's sides as feature edges.

use nalgebra::{Matrix3, Unit};

use crate::{Mesh, Point, Vector};

/// Default coplanarity tolerance relative to the size of the point set (bounding-box diagonal).
/// 1e-6 is ~20× the rounding of `f32` mesh coordinates and far below any real face angle.
pub const RELATIVE_TOLERANCE: f64 = 1e-6;

/// One planar face of a hull: the plane `normal · x = offset`, `normal` pointing outwards.
#[derive(Clone, Debug, PartialEq)]
pub struct HullFace {
    pub normal: Unit<Vector>,
    pub offset: f64,
    /// Indices into [`ConvexHull::vertices`] of the vertices on this face, ascending.
    pub vertices: Vec<usize>,
}

/// The convex hull of a point set, in the frame of the points.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvexHull {
    pub vertices: Vec<Point>,
    /// The triangulation (outward counter-clockwise), indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
    /// Planar faces: coplanar triangles merged.
    pub faces: Vec<HullFace>,
    /// Segments where two faces meet, as indices into `vertices`, lower index first.
    pub feature_edges: Vec<[usize; 2]>,
    /// For each feature edge, the two faces (indices into `faces`) that meet there.
    pub edge_faces: Vec<[usize; 2]>,
    /// The distance tolerance (m) used to decide coplanarity.
    pub tolerance: f64,
}

/// Point sets that have no 2- or 3-dimensional hull.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HullError {
    #[error("convex hull needs at least 3 points, got {0}")]
    TooFewPoints(usize),
    #[error("convex hull of non-finite points")]
    NonFinite,
    #[error("points are collinear (the hull has no faces)")]
    Collinear,
    #[error("convex hull failed: {0}")]
    Quickhull(String),
}

impl ConvexHull {
    /// The hull of the vertices used by the mesh's triangles.
    pub fn of_mesh(mesh: &Mesh) -> Result<ConvexHull, HullError> {
        let mut used = vec![false; mesh.vertices.len()];
        for t in &mesh.triangles {
            for &i in t {
                used[i as usize] = true;
            }
        }
        let points: Vec<Point> = mesh
            .vertices
            .iter()
            .zip(&used)
            .filter(|(_, u)| **u)
            .map(|(p, _)| *p)
            .collect();
        ConvexHull::from_points(&points)
    }

    /// The hull of `points` with the default tolerance ([`RELATIVE_TOLERANCE`] × bounding-box
    /// diagonal).
    pub fn from_points(points: &[Point]) -> Result<ConvexHull, HullError> {
        if points.len() < 3 {
            return Err(HullError::TooFewPoints(points.len()));
        }
        if !points
            .iter()
            .all(|p| p.coords.iter().all(|c| c.is_finite()))
        {
            return Err(HullError::NonFinite);
        }
        let (lo, hi) = bounds(points);
        let tol = RELATIVE_TOLERANCE * (hi - lo).norm().max(f64::MIN_POSITIVE);
        ConvexHull::from_points_with_tolerance(points, tol)
    }

    /// The hull of `points`; faces are merged when every vertex lies within `tol` (m) of the
    /// plane of the face's largest triangle.
    pub fn from_points_with_tolerance(points: &[Point], tol: f64) -> Result<ConvexHull, HullError> {
        if points.len() < 3 {
            return Err(HullError::TooFewPoints(points.len()));
        }
        if let Some(normal) = flat_normal(points, tol) {
            return planar_hull(points, normal, tol);
        }
        let (vertices, triangles) = parry3d_f64::transformation::try_convex_hull(points)
            .map_err(|e| HullError::Quickhull(e.to_string()))?;
        Ok(merge_faces(vertices, triangles, tol))
    }

    /// Length (m) of feature edge `i`.
    pub fn feature_edge_length(&self, i: usize) -> f64 {
        let [a, b] = self.feature_edges[i];
        (self.vertices[b] - self.vertices[a]).norm()
    }
}

fn bounds(points: &[Point]) -> (Point, Point) {
    points
        .iter()
        .fold((points[0], points[0]), |(lo, hi), p| (lo.inf(p), hi.sup(p)))
}

/// If all points lie within `tol` of one plane, that plane's unit normal (least-variance
/// direction of the point cloud).
fn flat_normal(points: &[Point], tol: f64) -> Option<Unit<Vector>> {
    let n = points.len() as f64;
    let centroid = points.iter().fold(Vector::zeros(), |s, p| s + p.coords) / n;
    let cov = points.iter().fold(Matrix3::zeros(), |m, p| {
        let d = p.coords - centroid;
        m + d * d.transpose()
    });
    let eig = cov.symmetric_eigen();
    let k = eig.eigenvalues.imin();
    let normal = Unit::new_normalize(eig.eigenvectors.column(k).into_owned());
    let flat = points
        .iter()
        .all(|p| normal.dot(&(p.coords - centroid)).abs() <= tol);
    flat.then_some(normal)
}

/// Two-sided hull of a flat point set: the 2-D hull polygon in the plane ⊥ `normal`.
fn planar_hull(points: &[Point], normal: Unit<Vector>, tol: f64) -> Result<ConvexHull, HullError> {
    let helper = if normal.x.abs() < 0.9 {
        Vector::x()
    } else {
        Vector::y()
    };
    let e1 = Unit::new_normalize(normal.cross(&helper));
    let e2 = normal.cross(&e1);
    let uv: Vec<[f64; 2]> = points
        .iter()
        .map(|p| [e1.dot(&p.coords), e2.dot(&p.coords)])
        .collect();
    let ring = monotone_chain(&uv, tol);
    if ring.len() < 3 {
        return Err(HullError::Collinear);
    }
    let vertices: Vec<Point> = ring.iter().map(|&i| points[i]).collect();
    let m = vertices.len();
    let mut triangles = Vec::with_capacity(2 * (m - 2));
    for i in 1..m - 1 {
        triangles.push([0, i as u32, (i + 1) as u32]);
        triangles.push([0, (i + 1) as u32, i as u32]);
    }
    let offset = normal.dot(&vertices[0].coords);
    let all: Vec<usize> = (0..m).collect();
    let faces = vec![
        HullFace {
            normal,
            offset,
            vertices: all.clone(),
        },
        HullFace {
            normal: -normal,
            offset: -offset,
            vertices: all,
        },
    ];
    let feature_edges: Vec<[usize; 2]> = (0..m).map(|i| sorted2(i, (i + 1) % m)).collect();
    let edge_faces = vec![[0, 1]; m];
    Ok(ConvexHull {
        vertices,
        triangles,
        faces,
        feature_edges,
        edge_faces,
        tolerance: tol,
    })
}

/// Andrew's monotone chain; returns indices of the counter-clockwise hull polygon without
/// vertices closer than `tol` to the line through their neighbours.
fn monotone_chain(uv: &[[f64; 2]], tol: f64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..uv.len()).collect();
    order.sort_by(|&a, &b| uv[a].partial_cmp(&uv[b]).expect("finite").then(a.cmp(&b)));
    // Left turn test with a distance tolerance: signed distance of c from line a→b.
    let keeps_left = |a: usize, b: usize, c: usize| {
        let (ab, ac) = (
            [uv[b][0] - uv[a][0], uv[b][1] - uv[a][1]],
            [uv[c][0] - uv[a][0], uv[c][1] - uv[a][1]],
        );
        let cross = ab[0] * ac[1] - ab[1] * ac[0];
        let len = (ab[0] * ab[0] + ab[1] * ab[1]).sqrt();
        cross > tol * len
    };
    let mut hull: Vec<usize> = Vec::with_capacity(order.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &usize>> = if pass == 0 {
            Box::new(order.iter())
        } else {
            Box::new(order.iter().rev())
        };
        for &i in iter {
            while hull.len() >= start + 2
                && !keeps_left(hull[hull.len() - 2], hull[hull.len() - 1], i)
            {
                hull.pop();
            }
            hull.push(i);
        }
        hull.pop();
    }
    // Drop exact duplicates (same uv) that a zero-length edge may leave.
    hull.dedup_by(|a, b| uv[*a] == uv[*b]);
    hull
}

fn sorted2(a: usize, b: usize) -> [usize; 2] {
    if a < b {
        [a, b]
    } else {
        [b, a]
    }
}

/// Groups the quickhull triangles into planar faces and extracts the feature edges.
fn merge_faces(vertices: Vec<Point>, mut triangles: Vec<[u32; 3]>, tol: f64) -> ConvexHull {
    let centroid =
        vertices.iter().fold(Vector::zeros(), |s, p| s + p.coords) / vertices.len() as f64;
    // Per-triangle area vector (cross product), oriented outwards.
    let mut area: Vec<Vector> = Vec::with_capacity(triangles.len());
    for t in triangles.iter_mut() {
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        let mut n = (b - a).cross(&(c - a));
        if n.dot(&(a.coords - centroid)) < 0.0 {
            t.swap(1, 2);
            n = -n;
        }
        area.push(n);
    }
    // Undirected edge -> the (up to two) triangles using it, found by sorting.
    let mut edges: Vec<(u64, usize)> = Vec::with_capacity(3 * triangles.len());
    for (ti, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges.push(((u64::from(a.min(b)) << 32) | u64::from(a.max(b)), ti));
        }
    }
    edges.sort_unstable();
    // A closed hull triangulation: each triangle has at most three neighbours.
    let mut neighbours: Vec<[usize; 3]> = vec![[usize::MAX; 3]; triangles.len()];
    let push = |n: &mut [usize; 3], t: usize| {
        if let Some(slot) = n.iter_mut().find(|s| **s == usize::MAX) {
            *slot = t;
        }
    };
    let mut pairs: Vec<(u64, usize, usize)> = Vec::new();
    for w in edges.chunk_by(|x, y| x.0 == y.0) {
        if let [(key, t1), (_, t2)] = *w {
            push(&mut neighbours[t1], t2);
            push(&mut neighbours[t2], t1);
            pairs.push((key, t1, t2));
        }
    }
    // Region growing from the largest triangles, whose normals are the most accurate.
    let mut seeds: Vec<usize> = (0..triangles.len()).collect();
    seeds.sort_by(|&a, &b| area[b].norm().total_cmp(&area[a].norm()).then(a.cmp(&b)));
    let mut face_of = vec![usize::MAX; triangles.len()];
    let mut faces: Vec<HullFace> = Vec::new();
    let mut stack = Vec::new();
    for &seed in &seeds {
        if face_of[seed] != usize::MAX {
            continue;
        }
        let f = faces.len();
        let n0 = Unit::new_normalize(area[seed]);
        let d0 = n0.dot(&vertices[triangles[seed][0] as usize].coords);
        let on_plane = |t: &[u32; 3]| {
            t.iter()
                .all(|&i| (n0.dot(&vertices[i as usize].coords) - d0).abs() <= tol)
        };
        face_of[seed] = f;
        stack.push(seed);
        let mut members = Vec::new();
        while let Some(t) = stack.pop() {
            members.push(t);
            for &nb in &neighbours[t] {
                if nb != usize::MAX
                    && face_of[nb] == usize::MAX
                    && area[nb].dot(&n0) > 0.0
                    && on_plane(&triangles[nb])
                {
                    face_of[nb] = f;
                    stack.push(nb);
                }
            }
        }
        let sum = members.iter().fold(Vector::zeros(), |s, &t| s + area[t]);
        let normal = Unit::new_normalize(sum);
        let mut vs: Vec<usize> = members
            .iter()
            .flat_map(|&t| triangles[t].map(|i| i as usize))
            .collect();
        vs.sort_unstable();
        vs.dedup();
        let offset = vs
            .iter()
            .map(|&i| normal.dot(&vertices[i].coords))
            .fold(f64::MIN, f64::max);
        faces.push(HullFace {
            normal,
            offset,
            vertices: vs,
        });
    }
    // Feature edges: triangulation edges between different faces, grouped by face pair; each
    // group is one segment (two convex faces meet along one segment), spanned by its extremes.
    let mut by_pair: Vec<([usize; 2], u32, u32)> = pairs
        .iter()
        .filter(|(_, t1, t2)| face_of[*t1] != face_of[*t2])
        .map(|&(key, t1, t2)| {
            (
                sorted2(face_of[t1], face_of[t2]),
                (key >> 32) as u32,
                key as u32,
            )
        })
        .collect();
    by_pair.sort_unstable();
    let mut feature_edges = Vec::new();
    let mut edge_faces = Vec::new();
    for group in by_pair.chunk_by(|x, y| x.0 == y.0) {
        let (a0, b0) = (group[0].1 as usize, group[0].2 as usize);
        let dir = vertices[b0] - vertices[a0];
        let ends = group.iter().flat_map(|g| [g.1 as usize, g.2 as usize]);
        let key = |i: &usize| dir.dot(&vertices[*i].coords);
        let lo = ends
            .clone()
            .min_by(|x, y| key(x).total_cmp(&key(y)).then(x.cmp(y)))
            .expect("non-empty");
        let hi = ends
            .max_by(|x, y| key(x).total_cmp(&key(y)).then(y.cmp(x)))
            .expect("non-empty");
        feature_edges.push(sorted2(lo, hi));
        edge_faces.push(group[0].0);
    }
    ConvexHull {
        vertices,
        triangles,
        faces,
        feature_edges,
        edge_faces,
        tolerance: tol,
    }
}
