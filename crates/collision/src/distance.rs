//! Closed-form distances between points, segments and triangles (metres, any common frame).
//!
//! These are the narrow-phase kernels of the world: a capsule is a segment inflated by its
//! radius, so capsule–capsule and capsule–triangle tests reduce to segment–segment and
//! segment–triangle distances compared with the summed radii. Every function returns the
//! *squared* distance to avoid square roots in the hot loop; degenerate inputs (zero-length
//! segments, needle triangles) are handled without NaN.

use nalgebra::{Point3, Vector3};

type P = Point3<f64>;
type V = Vector3<f64>;

/// Squared distance between segments `[p1, q1]` and `[p2, q2]`.
///
/// Minimises `|p1 + s d1 − (p2 + t d2)|²` over `s, t ∈ [0, 1]` (Ericson, *Real-Time
/// Collision Detection*, §5.1.9): the unconstrained minimiser is clamped, then the other
/// parameter is recomputed and clamped once more, which is exact for a convex quadratic.
#[inline]
pub fn segment_segment_sq(p1: &P, q1: &P, p2: &P, q2: &P) -> f64 {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.norm_squared();
    let e = d2.norm_squared();
    let f = d2.dot(&r);
    const EPS: f64 = 1e-18;
    let (s, t);
    if a <= EPS && e <= EPS {
        return r.norm_squared();
    }
    if a <= EPS {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e <= EPS {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > EPS * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    let c1 = p1 + d1 * s;
    let c2 = p2 + d2 * t;
    (c1 - c2).norm_squared()
}

/// The point of triangle `(a, b, c)` closest to `p` (Ericson §5.1.5, Voronoi regions).
#[inline]
pub fn closest_point_on_triangle(p: &P, a: &P, b: &P, c: &P) -> P {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(&ap);
    let d2 = ac.dot(&ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = p - b;
    let d3 = ab.dot(&bp);
    let d4 = ac.dot(&bp);
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return a + ab * v;
    }
    let cp = p - c;
    let d5 = ab.dot(&cp);
    let d6 = ac.dot(&cp);
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return a + ac * w;
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return b + (c - b) * w;
    }
    let sum = va + vb + vc;
    if sum.abs() < 1e-300 {
        // Degenerate (zero-area) triangle: its edges were handled above.
        return *a;
    }
    let denom = 1.0 / sum;
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Whether segment `[p, q]` crosses the plane region of triangle `(a, b, c)`.
///
/// Signed volumes: the segment endpoints lie on opposite sides (or on) the triangle's plane
/// and the crossing point lies inside all three edges. Touching counts as crossing.
#[inline]
fn segment_crosses_triangle(p: &P, q: &P, a: &P, b: &P, c: &P) -> bool {
    let n: V = (b - a).cross(&(c - a));
    let dp = n.dot(&(p - a));
    let dq = n.dot(&(q - a));
    if (dp > 0.0 && dq > 0.0) || (dp < 0.0 && dq < 0.0) || dp == dq {
        return false;
    }
    let t = dp / (dp - dq);
    let x = p + (q - p) * t;
    let e0 = (b - a).cross(&(x - a)).dot(&n);
    let e1 = (c - b).cross(&(x - b)).dot(&n);
    let e2 = (a - c).cross(&(x - c)).dot(&n);
    (e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0)
}

/// Squared distance between segment `[p, q]` and the (filled) triangle `(a, b, c)`.
///
/// Zero when the segment crosses the triangle. Otherwise the closest pair has one point on
/// a boundary feature: an endpoint against the triangle, or the segment against an edge;
/// the minimum over those five sub-problems is exact.
#[inline]
pub fn segment_triangle_sq(p: &P, q: &P, a: &P, b: &P, c: &P) -> f64 {
    if segment_crosses_triangle(p, q, a, b, c) {
        return 0.0;
    }
    let dp = (p - closest_point_on_triangle(p, a, b, c)).norm_squared();
    let dq = (q - closest_point_on_triangle(q, a, b, c)).norm_squared();
    let e0 = segment_segment_sq(p, q, a, b);
    let e1 = segment_segment_sq(p, q, b, c);
    let e2 = segment_segment_sq(p, q, c, a);
    dp.min(dq).min(e0).min(e1).min(e2)
}

/// Squared distance between two axis-aligned boxes `[amin, amax]` and `[bmin, bmax]`
/// (zero when they overlap).
#[inline]
pub fn aabb_aabb_sq(amin: &P, amax: &P, bmin: &P, bmax: &P) -> f64 {
    let mut d = 0.0;
    for i in 0..3 {
        let gap = (amin[i] - bmax[i]).max(bmin[i] - amax[i]).max(0.0);
        d += gap * gap;
    }
    d
}

/// Whether the triangle `(a, b, c)` meets the closed box `|x_i| ≤ half_i` (both in the box's
/// frame): the separating-axis test (Akenine-Möller, *Fast 3D triangle-box overlap testing*)
/// over the box's three axes, the triangle's normal and the nine cross products of a box axis
/// with a triangle edge — thirteen axes, the cheapest first. Two convex bodies are disjoint
/// exactly when one of these separates them; a zero axis (an edge along a box axis) separates
/// nothing and is passed over.
#[inline]
pub fn triangle_box_intersect(a: &P, b: &P, c: &P, half: &V) -> bool {
    // The box's own axes: the triangle's extent along each.
    for i in 0..3 {
        if a[i].min(b[i]).min(c[i]) > half[i] || a[i].max(b[i]).max(c[i]) < -half[i] {
            return false;
        }
    }
    let (e0, e1, e2) = (b - a, c - b, a - c);
    // The triangle's plane.
    let n = e0.cross(&(c - a));
    let r = half.x * n.x.abs() + half.y * n.y.abs() + half.z * n.z.abs();
    if n.dot(&a.coords).abs() > r {
        return false;
    }
    // Box axis × triangle edge: the triangle projects onto two values (the edge's ends agree).
    for e in [e0, e1, e2] {
        for i in 0..3 {
            let mut axis = V::zeros();
            axis[(i + 1) % 3] = -e[(i + 2) % 3];
            axis[(i + 2) % 3] = e[(i + 1) % 3];
            let (pa, pb, pc) = (
                axis.dot(&a.coords),
                axis.dot(&b.coords),
                axis.dot(&c.coords),
            );
            let r = half.x * axis.x.abs() + half.y * axis.y.abs() + half.z * axis.z.abs();
            if pa.min(pb).min(pc) > r || pa.max(pb).max(pc) < -r {
                return false;
            }
        }
    }
    true
}

/// The world's `z` axis in the coordinates of `frame` (frame → world): a point `p` of the
/// frame lies `up · p` above the frame's origin.
#[inline]
pub fn world_up_in(frame: &nalgebra::Isometry3<f64>) -> V {
    frame
        .rotation
        .to_rotation_matrix()
        .matrix()
        .row(2)
        .transpose()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64, z: f64) -> P {
        P::new(x, y, z)
    }

    #[test]
    fn parallel_segments_at_unit_distance() {
        let d = segment_segment_sq(
            &p(0., 0., 0.),
            &p(1., 0., 0.),
            &p(0.5, 1., 0.),
            &p(3., 1., 0.),
        );
        assert!((d - 1.0).abs() < 1e-15);
    }

    #[test]
    fn skew_segments_closest_at_interior_points() {
        // x-axis segment and a z-offset y-axis segment crossing above it.
        let d = segment_segment_sq(
            &p(-1., 0., 0.),
            &p(1., 0., 0.),
            &p(0.2, -1., 0.3),
            &p(0.2, 1., 0.3),
        );
        assert!((d - 0.09).abs() < 1e-15);
    }

    #[test]
    fn segment_endpoint_regions_and_degenerate_points() {
        let d = segment_segment_sq(
            &p(0., 0., 0.),
            &p(1., 0., 0.),
            &p(2., 1., 0.),
            &p(3., 2., 0.),
        );
        assert!((d - 2.0).abs() < 1e-15); // (1,0,0)-(2,1,0)
        let d = segment_segment_sq(
            &p(0., 0., 0.),
            &p(0., 0., 0.),
            &p(1., 1., 0.),
            &p(1., 1., 0.),
        );
        assert!((d - 2.0).abs() < 1e-15);
        let d = segment_segment_sq(
            &p(0., 2., 0.),
            &p(0., 2., 0.),
            &p(-1., 0., 0.),
            &p(1., 0., 0.),
        );
        assert!((d - 4.0).abs() < 1e-15);
    }

    #[test]
    fn segment_segment_matches_dense_sampling() {
        let cases = [
            [
                p(0.1, 0.2, 0.3),
                p(1.0, -0.4, 0.2),
                p(0.5, 0.5, -0.5),
                p(0.2, -0.8, 0.9),
            ],
            [p(0., 0., 0.), p(1., 1., 1.), p(2., 0., 0.), p(0., 2., 0.5)],
            [
                p(-1., 0.3, 0.),
                p(1., 0.3, 0.),
                p(-0.5, 0.3, 0.),
                p(2., 0.3, 0.),
            ],
        ];
        for [a, b, c, d] in cases {
            let exact = segment_segment_sq(&a, &b, &c, &d);
            let mut best = f64::INFINITY;
            let n = 400;
            for i in 0..=n {
                let x = a + (b - a) * (i as f64 / n as f64);
                for j in 0..=n {
                    let y = c + (d - c) * (j as f64 / n as f64);
                    best = best.min((x - y).norm_squared());
                }
            }
            assert!(exact <= best + 1e-12, "exact {exact} > sampled {best}");
            assert!(
                best - exact < 1e-4,
                "exact {exact} far below sampled {best}"
            );
        }
    }

    #[test]
    fn triangle_closest_point_regions() {
        let (a, b, c) = (p(0., 0., 0.), p(1., 0., 0.), p(0., 1., 0.));
        assert!(
            (closest_point_on_triangle(&p(0.2, 0.2, 1.), &a, &b, &c) - p(0.2, 0.2, 0.)).norm()
                < 1e-15
        );
        assert_eq!(closest_point_on_triangle(&p(-1., -1., 0.), &a, &b, &c), a);
        assert_eq!(
            closest_point_on_triangle(&p(0.5, -1., 0.), &a, &b, &c),
            p(0.5, 0., 0.)
        );
        let q = closest_point_on_triangle(&p(1., 1., 0.), &a, &b, &c);
        assert!((q - p(0.5, 0.5, 0.)).norm() < 1e-15);
    }

    #[test]
    fn segment_through_triangle_is_zero_and_beside_it_is_not() {
        let (a, b, c) = (p(0., 0., 0.), p(1., 0., 0.), p(0., 1., 0.));
        assert_eq!(
            segment_triangle_sq(&p(0.2, 0.2, -1.), &p(0.2, 0.2, 1.), &a, &b, &c),
            0.0
        );
        // Passes beside the hypotenuse at distance 0.1·√2/… : check against the edge distance.
        let d = segment_triangle_sq(&p(0.6, 0.6, -1.), &p(0.6, 0.6, 1.), &a, &b, &c);
        assert!((d - 0.02).abs() < 1e-12, "{d}");
        // Parallel above the face.
        let d = segment_triangle_sq(&p(0.1, 0.1, 0.5), &p(0.3, 0.1, 0.5), &a, &b, &c);
        assert!((d - 0.25).abs() < 1e-12);
    }

    #[test]
    fn aabb_gap() {
        let d = aabb_aabb_sq(
            &p(0., 0., 0.),
            &p(1., 1., 1.),
            &p(2., 0., 3.),
            &p(3., 1., 4.),
        );
        assert!((d - 5.0).abs() < 1e-15);
        assert_eq!(
            aabb_aabb_sq(
                &p(0., 0., 0.),
                &p(1., 1., 1.),
                &p(0.5, 0.5, 0.5),
                &p(2., 2., 2.)
            ),
            0.0
        );
    }

    /// The thirteen-axis test agrees with parry's box–triangle intersection on random
    /// triangles through, across, near and away from random boxes.
    #[test]
    fn triangle_box_agrees_with_parry() {
        use nalgebra::Isometry3;
        use parry3d_f64::shape::{Cuboid, Triangle};
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(13);
        let (mut meet, mut apart) = (0, 0);
        for _ in 0..20000 {
            let half = V::from_fn(|_, _| rng.random_range(0.005..0.1));
            let mut corner = || P::from(V::from_fn(|_, _| rng.random_range(-0.2..0.2)));
            let (a, b, c) = (corner(), corner(), corner());
            let reference = parry3d_f64::query::intersection_test(
                &Isometry3::identity(),
                &Cuboid::new(half),
                &Isometry3::identity(),
                &Triangle::new(a, b, c),
            )
            .unwrap();
            assert_eq!(triangle_box_intersect(&a, &b, &c, &half), reference);
            if reference {
                meet += 1;
            } else {
                apart += 1;
            }
        }
        assert!(meet > 2000 && apart > 2000, "{meet} meet, {apart} apart");
    }
}
