//! Pair tests of placed primitives, from cheap to exact: bounding spheres, closed forms
//! (capsule–capsule, capsule–box by slab clipping), the segment–cylinder search, and GJK on
//! parry's support maps for what those leave open.

use std::ops::ControlFlow;

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::query;
use parry3d_f64::shape::{Capsule as PCapsule, Cuboid as PCuboid, Segment as PSegment};

use crate::distance::segment_segment_sq;

type P = Point3<f64>;
type V = Vector3<f64>;

/// Distance between two primitives by parry's GJK (`0` in contact), shapes built on the stack.
fn gjk_distance(s1: &Placed, s2: &Placed) -> f64 {
    let id = Isometry3::identity();
    match (*s1, *s2) {
        (Placed::Cylinder { a, b, radius, .. }, other)
        | (other, Placed::Cylinder { a, b, radius, .. }) => {
            let (cp, cyl) = parry_cylinder(&a, &b, radius);
            let d = match other {
                Placed::Capsule { a, b, radius } => {
                    query::distance(&cp, &cyl, &id, &PCapsule::new(a, b, radius))
                }
                Placed::Cylinder { a, b, radius, .. } => {
                    let (cp2, cyl2) = parry_cylinder(&a, &b, radius);
                    query::distance(&cp, &cyl, &cp2, &cyl2)
                }
                Placed::Cuboid { pose, half } => {
                    query::distance(&cp, &cyl, &pose, &PCuboid::new(half))
                }
            };
            d.unwrap_or(0.0)
        }
        _ => pair_distance(s1, s2),
    }
}

/// A segment `(a, b)` with a radius: a capsule's, or the axis and radius of a cylinder.
type SweptSegment = (P, P, f64);

use super::cylinder::{segment_cylinder_distance, segment_cylinder_within};
use super::{
    cylinder_capsules, inner_capsule, outer_capsule, parry_cylinder, with_primitive, Placed,
};

/// `(cylinder, capsule)` when the pair is one of each, in either order.
#[inline]
fn cylinder_and_capsule(s1: &Placed, s2: &Placed) -> Option<(SweptSegment, SweptSegment)> {
    match (*s1, *s2) {
        (
            Placed::Cylinder { a, b, radius, .. },
            Placed::Capsule {
                a: p,
                b: q,
                radius: r,
            },
        )
        | (
            Placed::Capsule {
                a: p,
                b: q,
                radius: r,
            },
            Placed::Cylinder { a, b, radius, .. },
        ) => Some(((a, b, radius), (p, q, r))),
        _ => None,
    }
}

/// A primitive's flat-ended core and its border: a rounded cylinder as its sharp core and the
/// rim radius; anything else as itself and 0.
#[inline]
fn core(s: &Placed) -> (Placed, f64) {
    match *s {
        Placed::Cylinder {
            a,
            b,
            radius,
            border,
        } if border > 0.0 => (
            Placed::Cylinder {
                a,
                b,
                radius,
                border: 0.0,
            },
            border,
        ),
        other => (other, 0.0),
    }
}

/// Distance between two primitives (signed for capsule pairs, `0` in contact otherwise; a
/// rounded cylinder's border is subtracted from its core's distance).
pub fn pair_distance(s1: &Placed, s2: &Placed) -> f64 {
    let ((c1, e1), (c2, e2)) = (core(s1), core(s2));
    if e1 + e2 > 0.0 {
        return pair_distance(&c1, &c2) - e1 - e2;
    }
    if let Some(((a, b, radius), (p, q, rc))) = cylinder_and_capsule(s1, s2) {
        return segment_cylinder_distance(&p, &q, &a, &b, radius) - rc;
    }
    if matches!(s1, Placed::Cylinder { .. }) || matches!(s2, Placed::Cylinder { .. }) {
        return gjk_distance(s1, s2);
    }
    match (s1, s2) {
        (
            Placed::Capsule {
                a: a1,
                b: b1,
                radius: r1,
            },
            Placed::Capsule {
                a: a2,
                b: b2,
                radius: r2,
            },
        ) => segment_segment_sq(a1, b1, a2, b2).sqrt() - r1 - r2,
        (Placed::Capsule { a, b, radius }, Placed::Cuboid { pose, half })
        | (Placed::Cuboid { pose, half }, Placed::Capsule { a, b, radius }) => {
            let seg = PSegment::new(*a, *b);
            let cub = PCuboid::new(*half);
            query::distance(&Isometry3::identity(), &seg, pose, &cub).unwrap_or(0.0) - radius
        }
        (Placed::Cuboid { pose: p1, half: h1 }, Placed::Cuboid { pose: p2, half: h2 }) => {
            query::distance(p1, &PCuboid::new(*h1), p2, &PCuboid::new(*h2)).unwrap_or(0.0)
        }
        _ => unreachable!("cylinder pairs are handled above"),
    }
}

/// Whether two primitives are closer than `margin` (touching counts when `margin == 0`).
///
/// Exact for capsule pairs and capsule–box (the capsule radius grows by `margin`); for
/// box–box the margin grows one box's half extents, which is conservative by at most
/// `(√3 − 1)·margin` near its corners.
///
/// Pairs with a cylinder: bounded first by the cylinder's enclosing capsule (no contact there,
/// none at all) and inscribed capsule (contact there, contact), then GJK on parry's support
/// maps, asked only whether they come within the margin ([`crate::gjk::within`]).
/// A rounded cylinder is its core with the margin grown by its border (exact).
#[inline]
pub fn pair_intersects(s1: &Placed, s2: &Placed, margin: f64) -> bool {
    let ((c1, e1), (c2, e2)) = (core(s1), core(s2));
    if e1 + e2 > 0.0 {
        return pair_intersects(&c1, &c2, margin + e1 + e2);
    }
    if matches!(s1, Placed::Cylinder { .. }) || matches!(s2, Placed::Cylinder { .. }) {
        return cylinder_pair_intersects(s1, s2, margin);
    }
    match (s1, s2) {
        (
            Placed::Capsule {
                a: a1,
                b: b1,
                radius: r1,
            },
            Placed::Capsule {
                a: a2,
                b: b2,
                radius: r2,
            },
        ) => {
            let r = r1 + r2 + margin;
            segment_segment_sq(a1, b1, a2, b2) <= r * r
        }
        (Placed::Capsule { a, b, radius }, Placed::Cuboid { pose, half })
        | (Placed::Cuboid { pose, half }, Placed::Capsule { a, b, radius }) => {
            capsule_cuboid_intersects(a, b, radius + margin, pose, half)
        }
        (Placed::Cuboid { pose: p1, half: h1 }, Placed::Cuboid { pose: p2, half: h2 }) => {
            // SAT with one box grown by the margin along its axes: a miss is a miss, a hit
            // may be a corner or edge of the grown box only, so the distance decides.
            let (c1, c2) = (PCuboid::new(*h1), PCuboid::new(*h2));
            let grown = PCuboid::new(h1 + V::repeat(margin));
            query::intersection_test(p1, &grown, p2, &c2).unwrap_or(true)
                && (margin <= 0.0
                    || query::intersection_test(p1, &c1, p2, &c2).unwrap_or(true)
                    || query::distance(p1, &c1, p2, &c2).unwrap_or(0.0) <= margin)
        }
        _ => unreachable!("cylinder pairs are handled above"),
    }
}

/// Whether `s1` and `s2` may come within `margin` of each other: `false` only where
/// [`pair_intersects`] is, at a fraction of its price for cylinders, which stand here for their
/// enclosing capsules (exact for capsule pairs, slab clipping then GJK for a capsule and a box,
/// SAT for two boxes). For pairs whose exact pieces decide anyway, a filter that need not be
/// exact: the cylinder's own GJK distance would be paid on top of the pieces'.
pub fn pair_may_intersect(s1: &Placed, s2: &Placed, margin: f64) -> bool {
    let outer = |s: &Placed| match outer_capsule(s) {
        Some((a, b, radius)) => Placed::Capsule { a, b, radius },
        None => *s,
    };
    if matches!(s1, Placed::Cylinder { .. }) || matches!(s2, Placed::Cylinder { .. }) {
        pair_intersects(&outer(s1), &outer(s2), margin)
    } else {
        pair_intersects(s1, s2, margin)
    }
}

/// [`pair_intersects`] for pairs with at least one cylinder.
fn cylinder_pair_intersects(s1: &Placed, s2: &Placed, margin: f64) -> bool {
    // Cylinder vs capsule: exact, by the segment–cylinder distance.
    if let Some(((a, b, radius), (p, q, rc))) = cylinder_and_capsule(s1, s2) {
        let reach = rc + margin;
        let r = radius + reach;
        if segment_segment_sq(&p, &q, &a, &b) > r * r {
            return false;
        }
        return segment_cylinder_within(&p, &q, &a, &b, radius, reach);
    }
    let as_capsule = |a: P, b: P, r: f64| Placed::Capsule { a, b, radius: r };
    if let (Some((a1, b1, r1)), Some((a2, b2, r2))) = (outer_capsule(s1), outer_capsule(s2)) {
        let r = r1 + r2 + margin;
        if segment_segment_sq(&a1, &b1, &a2, &b2) > r * r {
            return false;
        }
    } else {
        // Cylinder vs cuboid: the enclosing capsule against the box.
        let (cyl, other) = if matches!(s1, Placed::Cylinder { .. }) {
            (s1, s2)
        } else {
            (s2, s1)
        };
        let (a, b, r) = outer_capsule(cyl).expect("a cylinder");
        if !pair_intersects(&as_capsule(a, b, r), other, margin) {
            return false;
        }
    }
    // Cylinder vs cylinder: each exact against the other's enclosing capsule (a miss there is a
    // miss), and against its inscribed capsule (a hit there is a hit).
    if let (
        Placed::Cylinder {
            a: a1,
            b: b1,
            radius: r1,
            ..
        },
        Placed::Cylinder {
            a: a2,
            b: b2,
            radius: r2,
            ..
        },
    ) = (*s1, *s2)
    {
        if !segment_cylinder_within(&a1, &b1, &a2, &b2, r2, r1 + margin)
            || !segment_cylinder_within(&a2, &b2, &a1, &b1, r1, r2 + margin)
        {
            return false;
        }
        for (seg, other) in [
            (cylinder_capsules(&a1, &b1, r1).2, (a2, b2, r2, r1)),
            (cylinder_capsules(&a2, &b2, r2).2, (a1, b1, r1, r2)),
        ] {
            if let Some((p, q)) = seg {
                let (oa, ob, or, own) = other;
                if segment_cylinder_within(&p, &q, &oa, &ob, or, own + margin) {
                    return true;
                }
            }
        }
        return primitives_within(s1, s2, margin);
    }
    let inner = |s: &Placed| inner_capsule(s).map(|(a, b, r)| as_capsule(a, b, r));
    let (i1, i2) = (inner(s1), inner(s2));
    match (i1, i2) {
        (Some(c1), Some(c2)) if pair_intersects(&c1, &c2, margin) => return true,
        (Some(c1), None)
            if !matches!(s2, Placed::Cylinder { .. }) && pair_intersects(&c1, s2, margin) =>
        {
            return true
        }
        (None, Some(c2))
            if !matches!(s1, Placed::Cylinder { .. }) && pair_intersects(s1, &c2, margin) =>
        {
            return true
        }
        _ => {}
    }
    primitives_within(s1, s2, margin)
}

/// Whether two primitives come within `margin` of each other, by GJK on parry's support maps
/// ([`crate::gjk::within`]; a capsule as its segment within `margin` plus its radius).
fn primitives_within(s1: &Placed, s2: &Placed, margin: f64) -> bool {
    with_primitive(s1, |p1, g1, e1| {
        with_primitive(s2, |p2, g2, e2| {
            match crate::gjk::within(&p1.inv_mul(p2), g1, g2, margin + e1 + e2, None) {
                Ok(()) => ControlFlow::Break(()),
                Err(_) => ControlFlow::Continue(()),
            }
        })
    })
    .is_break()
}

/// Squared distance from `p` to the box `|x_i| ≤ half_i` (`0` inside), in the box's frame.
#[inline]
pub(super) fn point_box_sq(p: &P, half: &V) -> f64 {
    let mut d = 0.0;
    for i in 0..3 {
        let e = (p[i].abs() - half[i]).max(0.0);
        d += e * e;
    }
    d
}

/// Capsule `([a, b], r)` vs oriented box, in the box's frame: the endpoint spheres and the
/// capsule's bounding sphere against the box (closed form: clamp the point into the box), then
/// slab clipping against the box grown by `r`; only a segment through a rounded edge or corner
/// region is left to GJK — the segment against the box within `r`.
#[inline]
fn capsule_cuboid_intersects(a: &P, b: &P, r: f64, pose: &Isometry3<f64>, half: &V) -> bool {
    let la = pose.inverse_transform_point(a);
    let lb = pose.inverse_transform_point(b);
    // Point–box distance of each endpoint: if one endpoint sphere already touches, done.
    if point_box_sq(&la, half) <= r * r || point_box_sq(&lb, half) <= r * r {
        return true;
    }
    let c = nalgebra::center(&la, &lb);
    let reach = 0.5 * (lb - la).norm() + r;
    if point_box_sq(&c, half) > reach * reach {
        return false;
    }
    // The box grown by `r` (its Minkowski sum with the ball) lies within the box `half + r`
    // and holds the three boxes grown by `r` along one axis each: a segment that misses the
    // first misses the capsule's box, one that meets any of the others meets it. Only a
    // segment through a rounded edge or corner region is left to GJK.
    if !segment_meets_box(&la, &lb, &(half + V::repeat(r + SLAB_ROUNDING))) {
        return false;
    }
    if (0..3).any(|i| {
        let mut grown = *half;
        grown[i] += r;
        segment_meets_box(&la, &lb, &grown)
    }) {
        return true;
    }
    // GJK on the segment and the box (polytopes: a few steps, exact), started along the line
    // from the box's centre to the segment's.
    crate::gjk::within(
        &Isometry3::identity(),
        &PSegment::new(la, lb),
        &PCuboid::new(*half),
        r,
        Some(c.coords),
    )
    .is_ok()
}

/// Added to a box before a segment that misses it is taken to miss the capsule: the clipping
/// is computed in floating point.
const SLAB_ROUNDING: f64 = 1e-12;

/// Whether the segment `[p, q]` meets the closed box `|x_i| ≤ half_i` (Liang–Barsky clipping:
/// the parameter interval of the segment within each slab, intersected).
#[inline]
pub(super) fn segment_meets_box(p: &P, q: &P, half: &V) -> bool {
    let d = q - p;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for i in 0..3 {
        if d[i] == 0.0 {
            if p[i].abs() > half[i] {
                return false;
            }
            continue;
        }
        let inv = 1.0 / d[i];
        let (mut ta, mut tb) = ((-half[i] - p[i]) * inv, (half[i] - p[i]) * inv);
        if ta > tb {
            std::mem::swap(&mut ta, &mut tb);
        }
        t0 = t0.max(ta);
        t1 = t1.min(tb);
        if t0 > t1 {
            return false;
        }
    }
    true
}
