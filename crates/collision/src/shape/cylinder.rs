//! The distance from a segment to a (flat-ended) cylinder, by a convex search along the segment
//! that stops once it knows the answer asked.

use nalgebra::Point3;

use pregrasp_robot::point_cylinder_distance;

type P = Point3<f64>;

/// Distance from the segment `[p, q]` to the solid cylinder (`0` when they meet).
pub fn segment_cylinder_distance(p: &P, q: &P, a: &P, b: &P, r: f64) -> f64 {
    let f = |t: f64| point_cylinder_distance(&(p + (q - p) * t), a, b, r);
    convex_minimum(f, 0.0, false)
}

/// Whether the segment `[p, q]` comes within `dist` of the solid cylinder: the search of
/// [`segment_cylinder_distance`], stopping once it knows either way.
pub fn segment_cylinder_within(p: &P, q: &P, a: &P, b: &P, r: f64, dist: f64) -> bool {
    let f = |t: f64| point_cylinder_distance(&(p + (q - p) * t), a, b, r);
    convex_minimum(f, dist, true) <= dist
}

/// The minimum over `t ∈ [0, 1]` of a convex `f` by golden-section search (60 steps shrink the
/// bracket below 1e-12), returned as soon as a value at most `stop` is found. With `bound`, it
/// also stops once convexity shows the minimum above `stop`, and then returns that lower bound.
///
/// The distance from a point moving along a segment to a convex set is a convex function of
/// the position. The bound: a secant of a convex function lies below it outside its chord, so
/// with values at `lo < x1 < x2 < hi` the chord `x1x2` extended bounds `f` on `[lo, x1]` and
/// `[x2, hi]`, and on `[x1, x2]` `f` lies above both outer chords extended inwards (their
/// maximum is smallest at an end or where they cross). It is only taken while the bracket is
/// wide enough for the slopes to be well computed, and above `stop` by a guard far beyond
/// round-off, so where the search would have found a value within `stop` this never claims
/// otherwise.
fn convex_minimum(f: impl Fn(f64) -> f64, stop: f64, bound: bool) -> f64 {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f_lo, mut f_hi) = (f(lo), f(hi));
    let (mut f1, mut f2) = (f(x1), f(x2));
    let mut best = f_lo.min(f_hi).min(f1).min(f2);
    for _ in 0..60 {
        if best <= stop {
            return best;
        }
        if bound && hi - lo > BRACKET_FOR_BOUND {
            let below = convex_lower_bound([lo, x1, x2, hi], [f_lo, f1, f2, f_hi]);
            if below > stop + BOUND_GUARD {
                return below;
            }
        }
        if f1 <= f2 {
            (hi, f_hi) = (x2, f2);
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
            best = best.min(f1);
        } else {
            (lo, f_lo) = (x1, f1);
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
            best = best.min(f2);
        }
    }
    best
}

/// Narrowest bracket (of `t ∈ [0, 1]`) on which [`convex_minimum`] takes its convexity bound.
const BRACKET_FOR_BOUND: f64 = 1e-6;

/// How far above `stop` the convexity bound must be to end the search (m).
const BOUND_GUARD: f64 = 1e-9;

/// A lower bound of the minimum on `[x[0], x[3]]` of a convex function with values `y` at the
/// increasing `x`, where the minimum lies in that bracket (see [`convex_minimum`]).
fn convex_lower_bound(x: [f64; 4], y: [f64; 4]) -> f64 {
    let slope = |i: usize, j: usize| (y[j] - y[i]) / (x[j] - x[i]);
    let s = slope(1, 2);
    // Outside [x1, x2]: the middle chord, lowest at the far end it falls towards.
    let left = if s > 0.0 {
        y[1] - s * (x[1] - x[0])
    } else {
        y[1]
    };
    let right = if s < 0.0 {
        y[2] + s * (x[3] - x[2])
    } else {
        y[2]
    };
    // Inside: the larger of the outer chords, continued inwards.
    let (sa, sb) = (slope(0, 1), slope(2, 3));
    let a = |t: f64| y[1] + sa * (t - x[1]);
    let b = |t: f64| y[2] + sb * (t - x[2]);
    let mut mid = a(x[1]).max(b(x[1])).min(a(x[2]).max(b(x[2])));
    if sa != sb {
        let tc = (y[2] - y[1] - sb * x[2] + sa * x[1]) / (sa - sb);
        if tc > x[1] && tc < x[2] {
            mid = mid.min(a(tc));
        }
    }
    left.min(right).min(mid)
}
