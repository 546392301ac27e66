//! The edge searches of [`super::depth_in_part`]: the largest `f` (depth in the part) on an
//! edge of the piece, by branch and bound on Piyavskii's and the nearest triangles' bounds, and
//! the largest `g` (depth in the piece) on an edge of the part, by golden-section search. The
//! measure and both bounds are stated in the parent module's documentation.

use nalgebra::Point3;

use super::Hull;
use crate::solid::PartSolid;

type P = Point3<f64>;

/// Absolute tolerance (m) of the edge search above the floor.
pub(super) const ABS_TOL: f64 = 2e-5;
/// Relative tolerance of the edge search above the floor.
pub(super) const REL_TOL: f64 = 0.01;
/// Shortest edge interval (m) the search still halves.
const MIN_INTERVAL: f64 = 1e-7;
/// Golden-section steps of the concave search (shrinks the interval by 0.618⁶⁰ ≈ 3e-13).
const GOLDEN_STEPS: usize = 60;

/// The largest `f` on the segment between `ends` (points with their `f` and their nearest
/// triangle), by Piyavskii's bound and the nearest triangles' (module documentation), at
/// least `best`.
pub(super) fn max_on_segment(part: &PartSolid, ends: [End; 2], floor: f64, best: f64) -> f64 {
    let mut best = best;
    let mut stack = vec![ends];
    while let Some([a, b]) = stack.pop() {
        let len = (b.x - a.x).norm();
        let enough = floor.max(best) + ABS_TOL + REL_TOL * best.max(0.0);
        if 0.5 * (a.f + b.f + len) <= enough || len < MIN_INTERVAL {
            continue;
        }
        // `f ≤ max(0, dist(·, T))` for any triangle `T` of the surface, and the distance to a
        // triangle is convex: on the segment it is at most its larger end value. With `T` the
        // nearest triangle of either end, one end value is that end's `|f|`.
        let by = |t: u32, near: &End, other: &End| {
            let far = if other.triangle == t {
                other.f.abs()
            } else {
                part.triangle_distance(&other.x, t)
            };
            near.f.abs().max(far)
        };
        if by(a.triangle, &a, &b).min(by(b.triangle, &b, &a)) <= enough {
            continue;
        }
        let x = nalgebra::center(&a.x, &b.x);
        let Some((f, triangle)) = part.signed_distance_near(&x) else {
            continue;
        };
        best = best.max(f);
        let m = End { x, f, triangle };
        stack.push([a, m]);
        stack.push([m, b]);
    }
    best
}

/// A point of an edge with its `f` and the triangle nearest it.
#[derive(Clone, Copy, Debug)]
pub(super) struct End {
    pub(super) x: P,
    pub(super) f: f64,
    pub(super) triangle: u32,
}

/// The largest `g` on the segment `[a, b]` (piece frame), 0 if it misses the piece's interior:
/// the segment clipped to the piece (Cyrus–Beck), then golden-section search of the concave
/// `g` on what is left.
pub(super) fn max_depth_on_edge(solid: &Hull, a: &P, b: &P) -> f64 {
    let ab = b - a;
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for (n, d) in &solid.planes {
        let num = d - n.dot(&a.coords);
        let den = n.dot(&ab);
        if den.abs() < 1e-300 {
            if num < 0.0 {
                return 0.0;
            }
        } else if den > 0.0 {
            hi = hi.min(num / den);
        } else {
            lo = lo.max(num / den);
        }
        if lo > hi {
            return 0.0;
        }
    }
    let g = |t: f64| solid.depth_of(&(a + ab * t));
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
    let (mut g1, mut g2) = (g(x1), g(x2));
    for _ in 0..GOLDEN_STEPS {
        if g1 < g2 {
            lo = x1;
            x1 = x2;
            g1 = g2;
            x2 = lo + r * (hi - lo);
            g2 = g(x2);
        } else {
            hi = x2;
            x2 = x1;
            g2 = g1;
            x1 = hi - r * (hi - lo);
            g1 = g(x1);
        }
    }
    g1.max(g2).max(g(lo)).max(g(hi)).max(0.0)
}
