//! Convex pieces: the convex hull of a collision element, and the containment test.
//!
//! A piece is the convex hull of a point set, computed with parry's quickhull
//! (`try_convex_hull`) and kept as its hull vertices. Quickhull decides "above a face" with a
//! tolerance, so a point within rounding of a face may be left out; [`hull_piece`] therefore
//! checks every input point against the hull's face planes and re-runs the hull with the
//! points found outside (by more than [`CONTAIN_TOLERANCE`]) added, and as a last resort
//! scales the hull about its centroid just enough to take them in. The result contains every
//! input point to [`CONTAIN_TOLERANCE`].
//!
//! Face planes: each hull triangle `(a, b, c)` (outward counter-clockwise) gives the plane
//! `n·x = d`, `n = (b − a) × (c − a) / |…|`, `d = max(n·a, n·b, n·c)`. For a convex
//! polytope, `max over faces (n·p − d)` is ≤ 0 exactly for the points inside, and when
//! positive it is a lower bound of the distance from `p` to the polytope.

use nalgebra::{Point3, Unit, Vector3};

/// How far outside its piece an input point may lie (m): rounding, far below any mesh
/// accuracy (binary STL stores `f32`, 1e-8 m steps at 0.1 m).
pub const CONTAIN_TOLERANCE: f64 = 1e-12;

/// Points of a flat (or collinear) set are padded to a box at least this thick (m) so the
/// piece is a solid ...
pub const FLAT_PAD: f64 = 1e-6;

/// ... and at least this fraction of the box diagonal (quickhull, working on points scaled to
/// a unit box, takes thinner sets for flat).
pub const FLAT_PAD_RELATIVE: f64 = 1e-3;

/// The face planes of a convex hull.
#[derive(Clone, Debug)]
pub struct Planes {
    /// `(n, d)`: outward unit normal and offset, `n·x ≤ d` inside.
    pub planes: Vec<(Unit<Vector3<f64>>, f64)>,
}

impl Planes {
    /// The planes of the convex hull of `points`; `None` when it has no volume.
    pub fn of(points: &[Point3<f64>]) -> Option<Planes> {
        let (v, t) = parry3d_f64::transformation::try_convex_hull(points).ok()?;
        Self::of_triangles(&v, &t)
    }

    fn of_triangles(v: &[Point3<f64>], t: &[[u32; 3]]) -> Option<Planes> {
        if t.len() < 4 {
            return None;
        }
        // A flat hull (every vertex on the first face's plane) has no volume.
        let [a, b, c] = t[0].map(|i| v[i as usize]);
        let n0 = Unit::try_new((b - a).cross(&(c - a)), 1e-300)?;
        if v.iter().all(|p| n0.dot(&(p - a)).abs() < FLAT_PAD / 4.0) {
            return None;
        }
        let mut planes = Vec::with_capacity(t.len());
        for &[a, b, c] in t {
            let (a, b, c) = (v[a as usize], v[b as usize], v[c as usize]);
            let n = (b - a).cross(&(c - a));
            if let Some(n) = Unit::try_new(n, 1e-300) {
                let d = n.dot(&a.coords).max(n.dot(&b.coords)).max(n.dot(&c.coords));
                planes.push((n, d));
            }
        }
        (planes.len() >= 4).then_some(Planes { planes })
    }
}

/// `max over faces (n·p − d)`: ≤ 0 inside, a lower bound of the distance when positive.
pub fn outside_distance(planes: &Planes, p: &Point3<f64>) -> f64 {
    planes
        .planes
        .iter()
        .map(|(n, d)| n.dot(&p.coords) - d)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The largest [`outside_distance`] of `points` from the hull of `piece` (−∞ for no points,
/// +∞ when the piece has no volume).
pub fn max_outside(piece: &[Point3<f64>], points: &[Point3<f64>]) -> f64 {
    match Planes::of(piece) {
        Some(planes) => points
            .iter()
            .map(|p| outside_distance(&planes, p))
            .fold(f64::NEG_INFINITY, f64::max),
        None => f64::INFINITY,
    }
}

/// The vertices of a convex polytope containing every point of `points` (non-empty) to
/// [`CONTAIN_TOLERANCE`]: their convex hull (see the module documentation), or for a flat
/// set its bounding box padded (see [`FLAT_PAD`]).
pub fn hull_piece(points: &[Point3<f64>]) -> Vec<Point3<f64>> {
    let mut set: Vec<Point3<f64>> = points.to_vec();
    for _ in 0..3 {
        let Ok((v, t)) = parry3d_f64::transformation::try_convex_hull(&set) else {
            return padded_box(points);
        };
        let Some(planes) = Planes::of_triangles(&v, &t) else {
            return padded_box(points);
        };
        let out: Vec<Point3<f64>> = points
            .iter()
            .filter(|p| outside_distance(&planes, p) > CONTAIN_TOLERANCE)
            .copied()
            .collect();
        if out.is_empty() {
            return v;
        }
        set = v;
        set.extend(out);
    }
    // Still points outside by rounding: scale about the centroid c by 1 + ε, which moves
    // every face plane out by ε·(d − n·c) ≥ ε·min_face (d − n·c).
    let Some(planes) = Planes::of(&set) else {
        return padded_box(points);
    };
    let c = Point3::from(set.iter().map(|p| p.coords).sum::<Vector3<f64>>() / set.len() as f64);
    let worst = points
        .iter()
        .map(|p| outside_distance(&planes, p))
        .fold(0.0, f64::max);
    let inner = planes
        .planes
        .iter()
        .map(|(n, d)| d - n.dot(&c.coords))
        .fold(f64::INFINITY, f64::min);
    let eps = 2.0 * (worst + CONTAIN_TOLERANCE) / inner.max(1e-12);
    let (v, _) = parry3d_f64::transformation::try_convex_hull(&set).unwrap_or_default();
    v.iter().map(|p| c + (p - c) * (1.0 + eps)).collect()
}

/// The axis-aligned bounding box of `points`, each side at least [`FLAT_PAD`] and
/// [`FLAT_PAD_RELATIVE`] × its diagonal.
fn padded_box(points: &[Point3<f64>]) -> Vec<Point3<f64>> {
    let mut lo = points[0];
    let mut hi = points[0];
    for p in points {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let pad = FLAT_PAD.max(FLAT_PAD_RELATIVE * (hi - lo).norm());
    for i in 0..3 {
        let grow = (pad - (hi[i] - lo[i])).max(0.0) / 2.0;
        lo[i] -= grow;
        hi[i] += grow;
    }
    let mut out = Vec::with_capacity(8);
    for k in 0..8 {
        let pick = |i: usize| if k & (1 << i) == 0 { lo[i] } else { hi[i] };
        out.push(Point3::new(pick(0), pick(1), pick(2)));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_contains_its_points_and_flat_sets_get_a_box() {
        let mut pts = Vec::new();
        for i in 0..20 {
            for j in 0..20 {
                let (a, b) = (i as f64 * 0.31, j as f64 * 0.17);
                pts.push(Point3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos()) * 0.1);
            }
        }
        let piece = hull_piece(&pts);
        assert!(piece.len() < pts.len());
        assert!(max_outside(&piece, &pts) <= CONTAIN_TOLERANCE);
        let flat: Vec<_> = pts.iter().map(|p| Point3::new(p.x, p.y, 0.0)).collect();
        let piece = hull_piece(&flat);
        assert_eq!(piece.len(), 8);
        assert!(max_outside(&piece, &flat) <= CONTAIN_TOLERANCE);
    }
}
