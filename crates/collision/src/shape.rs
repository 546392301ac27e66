//! Convex primitives placed in the world frame, with their bounding volumes and pair tests.
//!
//! Every arm link, gripper part and static obstacle is one [`Placed`] primitive: a capsule
//! (segment `[a, b]` inflated by `radius`; a sphere when `a == b`), a cylinder (its rim
//! possibly rounded) or an oriented cuboid.
//! Pair tests run from cheap to exact: bounding spheres first, then closed forms for
//! capsule–capsule (segment–segment distance) and anything–plane (support function along
//! `z`), slab clipping for capsule–box, a convex search for segment–cylinder, and GJK on
//! parry's support maps ([`crate::gjk::within`]) only for what those leave open.
//!
//! Distances are signed where a closed form gives it (capsules, plane): `≤ 0` means contact,
//! a negative value is a penetration depth estimate. Parry-backed pairs return `0` in contact.

use std::ops::ControlFlow;

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::query;
use parry3d_f64::shape::{
    Capsule as PCapsule, Cuboid as PCuboid, Cylinder as PCylinder, Segment as PSegment, SupportMap,
};

use crate::distance::segment_segment_sq;

type P = Point3<f64>;
type V = Vector3<f64>;

/// One convex primitive in the world frame (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Placed {
    /// Points within `radius` of the segment `[a, b]`.
    Capsule { a: P, b: P, radius: f64 },
    /// A cylinder with rounded rims: the flat-ended cylinder with end-face centres `a`, `b`
    /// and radius `radius`, inflated by `border` (its Minkowski sum with a ball of that
    /// radius; `border = 0`: the sharp cylinder itself). Every test runs on the flat-ended
    /// core with the margin grown by `border`, which is exact.
    Cylinder {
        a: P,
        b: P,
        radius: f64,
        border: f64,
    },
    /// The box `|x_i| ≤ half_i` in the frame `pose` (box frame → world).
    Cuboid { pose: Isometry3<f64>, half: V },
}

/// A placed primitive with its bounding sphere (centre, radius) cached, and how far the exact
/// solid it bounds may reach outside it (`slack`: an arm link's pieces, see [`crate::tight`];
/// 0 when the primitive is the solid). The sphere holds the exact solid too.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bounded {
    pub shape: Placed,
    pub center: P,
    pub radius: f64,
    pub slack: f64,
}

impl Bounded {
    pub const EMPTY: Bounded = Bounded {
        shape: Placed::Capsule {
            a: P::new(0.0, 0.0, 0.0),
            b: P::new(0.0, 0.0, 0.0),
            radius: 0.0,
        },
        center: P::new(0.0, 0.0, 0.0),
        radius: 0.0,
        slack: 0.0,
    };

    /// A sphere of `radius` about `center`.
    #[inline]
    pub fn sphere(center: P, radius: f64) -> Self {
        Bounded {
            shape: Placed::Capsule {
                a: center,
                b: center,
                radius,
            },
            center,
            radius,
            slack: 0.0,
        }
    }

    #[inline]
    pub fn new(shape: Placed) -> Self {
        let (center, radius) = match shape {
            Placed::Capsule { a, b, radius } => {
                (nalgebra::center(&a, &b), 0.5 * (b - a).norm() + radius)
            }
            Placed::Cylinder {
                a,
                b,
                radius,
                border,
            } => (
                nalgebra::center(&a, &b),
                (0.25 * (b - a).norm_squared() + radius * radius).sqrt() + border,
            ),
            Placed::Cuboid { pose, half } => (P::from(pose.translation.vector), half.norm()),
        };
        Bounded {
            shape,
            center,
            radius,
            slack: 0.0,
        }
    }

    /// Axis-aligned bounding box `(min, max)` of the primitive.
    #[cfg(test)]
    pub fn aabb(&self) -> (P, P) {
        match self.shape {
            Placed::Capsule { a, b, radius } => {
                let r = V::repeat(radius);
                (a.inf(&b) - r, a.sup(&b) + r)
            }
            Placed::Cylinder {
                a,
                b,
                radius,
                border,
            } => {
                let r = cylinder_rim_extent(&a, &b, radius).add_scalar(border);
                (a.inf(&b) - r, a.sup(&b) + r)
            }
            Placed::Cuboid { pose, half } => {
                let m = pose.rotation.to_rotation_matrix();
                let ext = m.matrix().abs() * half;
                let c = P::from(pose.translation.vector);
                (c - ext, c + ext)
            }
        }
    }

    /// Squared distance from the sphere's centre to the box `|x_i| ≤ half_i` in the frame
    /// `pose` (`0` inside): the sphere comes within `m` of the box iff it is at most
    /// `(radius + m)²`. Far tighter than the box's own bounding sphere for a flat box (a table).
    #[inline]
    pub fn centre_box_gap_sq(&self, pose: &Isometry3<f64>, half: &V) -> f64 {
        point_box_sq(&pose.inverse_transform_point(&self.center), half)
    }

    /// Whether the bounding spheres are within `margin` of each other.
    #[inline]
    pub fn spheres_near(&self, other: &Bounded, margin: f64) -> bool {
        let r = self.radius + other.radius + margin;
        (self.center - other.center).norm_squared() < r * r
    }
}

/// Signed height of the lowest point of `shape` above the plane `z = height`
/// (the support is the half-space `z ≤ height`): `min_x z(x) − height`.
///
/// Capsule: `min(a_z, b_z) − radius`. Cuboid: centre `z` minus its support extent
/// `Σ_i |R_{z,i}| h_i` along world `z`.
/// Cylinder: lowest end-face centre minus the rim's reach below it, `r·√(1 − d_z²)` for the
/// unit axis `d`, minus the border.
#[inline]
pub fn plane_distance(shape: &Placed, height: f64) -> f64 {
    match shape {
        Placed::Capsule { a, b, radius } => a.z.min(b.z) - radius - height,
        Placed::Cylinder {
            a,
            b,
            radius,
            border,
        } => a.z.min(b.z) - cylinder_rim_extent(a, b, *radius).z - border - height,
        Placed::Cuboid { pose, half } => {
            let m = pose.rotation.to_rotation_matrix();
            let row = m.matrix().row(2);
            let ext = row[0].abs() * half.x + row[1].abs() * half.y + row[2].abs() * half.z;
            pose.translation.vector.z - ext - height
        }
    }
}

/// Per world axis, how far the rim of a cylinder (end-face centres `a`, `b`, radius `r`)
/// reaches beyond its end-face centres: `r·√(1 − d_i²)` for the unit axis `d`.
#[inline]
pub fn cylinder_rim_extent(a: &P, b: &P, r: f64) -> V {
    let d = b - a;
    let len2 = d.norm_squared();
    if len2 == 0.0 {
        return V::repeat(r);
    }
    let d2 = d.component_mul(&d) / len2;
    V::new(
        r * (1.0 - d2.x).max(0.0).sqrt(),
        r * (1.0 - d2.y).max(0.0).sqrt(),
        r * (1.0 - d2.z).max(0.0).sqrt(),
    )
}

/// A cylinder as parry sees it: parry's cylinder is centred on its frame with its axis along
/// local `y`; returns that frame (world) and the shape.
pub fn parry_cylinder(a: &P, b: &P, r: f64) -> (Isometry3<f64>, PCylinder) {
    let d = b - a;
    let len = d.norm();
    let rot = if len > 0.0 {
        nalgebra::UnitQuaternion::rotation_between(&V::y(), &(d / len)).unwrap_or_else(|| {
            nalgebra::UnitQuaternion::from_axis_angle(&V::x_axis(), std::f64::consts::PI)
        })
    } else {
        nalgebra::UnitQuaternion::identity()
    };
    let pose = Isometry3::from_parts(nalgebra::center(a, b).coords.into(), rot);
    (pose, PCylinder::new(0.5 * len, r))
}

/// Calls `f` with a primitive as a parry support map: its pose, the shape, and the radius by
/// which that shape must be inflated to be the primitive.
pub(crate) fn with_primitive(
    s: &Placed,
    f: impl FnOnce(&Isometry3<f64>, &dyn SupportMap, f64) -> ControlFlow<()>,
) -> ControlFlow<()> {
    let id = Isometry3::identity();
    match *s {
        Placed::Capsule { a, b, radius } => f(&id, &PSegment::new(a, b), radius),
        Placed::Cylinder {
            a,
            b,
            radius,
            border,
        } => {
            let (pose, cyl) = parry_cylinder(&a, &b, radius);
            f(&pose, &cyl, border)
        }
        Placed::Cuboid { pose, half } => f(&pose, &PCuboid::new(half), 0.0),
    }
}

/// The capsule that a cylinder lies inside (same axis segment and radius) and the capsule
/// that lies inside the cylinder (the axis segment inset by the radius at both ends, same
/// radius; `None` when the cylinder is shorter than its diameter).
#[inline]
pub(crate) fn cylinder_capsules(a: &P, b: &P, r: f64) -> (P, P, Option<(P, P)>) {
    let d = b - a;
    let len = d.norm();
    let inner = (len > 2.0 * r).then(|| {
        let u = d * (r / len);
        (a + u, b - u)
    });
    (*a, *b, inner)
}

/// The segment and radius of a primitive's enclosing capsule (capsules: itself; cylinders: the
/// capsule on the same axis segment), or `None` for a cuboid.
#[inline]
fn outer_capsule(s: &Placed) -> Option<(P, P, f64)> {
    match *s {
        Placed::Capsule { a, b, radius } => Some((a, b, radius)),
        Placed::Cylinder {
            a,
            b,
            radius,
            border,
        } => Some((a, b, radius + border)),
        Placed::Cuboid { .. } => None,
    }
}

/// The segment and radius of a capsule lying inside the primitive, if it has one.
#[inline]
fn inner_capsule(s: &Placed) -> Option<(P, P, f64)> {
    match *s {
        Placed::Capsule { a, b, radius } => Some((a, b, radius)),
        Placed::Cylinder {
            a,
            b,
            radius,
            border,
        } => cylinder_capsules(&a, &b, radius)
            .2
            .map(|(a, b)| (a, b, radius + border)),
        Placed::Cuboid { .. } => None,
    }
}

/// Distance from a point to a solid flat-ended cylinder (the robot crate's, one definition for
/// the link shapes and the collision tests).
pub use pregrasp_robot::point_cylinder_distance;

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
fn point_box_sq(p: &P, half: &V) -> f64 {
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
fn segment_meets_box(p: &P, q: &P, half: &V) -> bool {
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

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

    /// Numbers uniform in `[−1, 1)`, the same for the same `seed` (a 64-bit LCG).
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    fn cap(a: [f64; 3], b: [f64; 3], r: f64) -> Placed {
        Placed::Capsule {
            a: P::from(a),
            b: P::from(b),
            radius: r,
        }
    }

    #[test]
    fn capsule_plane_is_lowest_point() {
        let c = cap([0., 0., 0.5], [0., 0., 0.2], 0.05);
        assert!((plane_distance(&c, 0.1) - 0.05).abs() < 1e-15);
    }

    #[test]
    fn rotated_cuboid_plane_uses_support_extent() {
        // A unit cube rotated 45° about x: its lowest edge is √2/2·... below the centre.
        let pose = Isometry3::from_parts(
            nalgebra::Translation3::new(0., 0., 1.),
            UnitQuaternion::from_euler_angles(std::f64::consts::FRAC_PI_4, 0., 0.),
        );
        let c = Placed::Cuboid {
            pose,
            half: V::new(0.5, 0.5, 0.5),
        };
        let expect = 1.0 - 0.5 * std::f64::consts::SQRT_2;
        assert!((plane_distance(&c, 0.0) - expect).abs() < 1e-12);
    }

    #[test]
    fn capsule_pair_distance_and_margin() {
        let c1 = cap([0., 0., 0.], [1., 0., 0.], 0.1);
        let c2 = cap([0.5, 0.5, -1.], [0.5, 0.5, 1.], 0.1);
        assert!((pair_distance(&c1, &c2) - 0.3).abs() < 1e-12);
        assert!(!pair_intersects(&c1, &c2, 0.0));
        assert!(!pair_intersects(&c1, &c2, 0.29));
        assert!(pair_intersects(&c1, &c2, 0.31));
    }

    #[test]
    fn capsule_cuboid_agrees_with_distance() {
        let pose = Isometry3::from_parts(
            nalgebra::Translation3::new(0.3, -0.2, 0.1),
            UnitQuaternion::from_euler_angles(0.3, -0.5, 1.1),
        );
        let cub = Placed::Cuboid {
            pose,
            half: V::new(0.2, 0.1, 0.05),
        };
        for (i, z) in [0.0, 0.1, 0.2, 0.3, 0.4, 0.6].iter().enumerate() {
            let c = cap([-0.5, -0.2, *z], [0.8, 0.1, *z + 0.05], 0.03);
            let d = pair_distance(&c, &cub);
            assert_eq!(
                pair_intersects(&c, &cub, 0.0),
                d <= 1e-9,
                "case {i}: d = {d}"
            );
            assert_eq!(
                pair_intersects(&c, &cub, 0.02),
                d < 0.02 + 1e-9,
                "case {i}: d = {d}"
            );
        }
    }

    #[test]
    fn capsule_cuboid_agrees_with_gjk_distance_on_random_pairs() {
        // Segments through faces, past edges and corners, parallel to faces, points.
        let mut next = uniform(11);
        let (mut hits, mut misses) = (0, 0);
        for case in 0..20_000 {
            let pose = Isometry3::from_parts(
                nalgebra::Translation3::new(next() * 0.1, next() * 0.1, next() * 0.1),
                UnitQuaternion::from_euler_angles(next() * 3.0, next() * 1.5, next() * 3.0),
            );
            let half = V::new(0.02 + 0.2 * next().abs(), 0.02 + 0.1 * next().abs(), 0.01);
            let a = P::new(next() * 0.3, next() * 0.3, next() * 0.3);
            let b = match case % 4 {
                0 => a,
                1 => a + V::new(next() * 0.5, 0.0, 0.0),
                _ => P::new(next() * 0.3, next() * 0.3, next() * 0.3),
            };
            let r = 0.005 + 0.08 * next().abs();
            let cub = Placed::Cuboid { pose, half };
            let capsule = Placed::Capsule { a, b, radius: r };
            // The truth: the segment's distance from the box (parry's GJK) against the radius.
            let segment = PCapsule::new(a, b, 0.0);
            let id = Isometry3::identity();
            let d = query::distance(&id, &segment, &pose, &PCuboid::new(half)).unwrap() - r;
            if d.abs() < 1e-9 {
                continue;
            }
            let got = pair_intersects(&capsule, &cub, 0.0);
            assert_eq!(got, d <= 0.0, "case {case}: distance {d}");
            if got {
                hits += 1;
            } else {
                misses += 1;
            }
        }
        assert!(hits > 3000 && misses > 3000, "{hits} hits, {misses} misses");
    }

    #[test]
    fn the_loose_filter_passes_every_pair_that_meets() {
        let mut next = uniform(5);
        let (mut meet, mut filtered) = (0, 0);
        for case in 0..6000 {
            let mut shape = |kind: usize| {
                let a = P::new(next() * 0.1, next() * 0.1, next() * 0.1);
                let b = a + V::new(next(), next(), next()) * 0.15;
                let r = 0.01 + 0.05 * next().abs();
                match kind {
                    0 => Placed::Capsule { a, b, radius: r },
                    1 => Placed::Cylinder {
                        a,
                        b,
                        radius: r,
                        border: 0.01 * next().abs(),
                    },
                    _ => Placed::Cuboid {
                        pose: Isometry3::from_parts(
                            nalgebra::Translation3::from(a.coords),
                            UnitQuaternion::from_euler_angles(next() * 3.0, next(), next() * 3.0),
                        ),
                        half: V::new(r, 2.0 * r, 0.5 * r),
                    },
                }
            };
            let (s1, s2) = (shape(case % 3), shape(case / 3 % 3));
            let margin = 0.02 * next().abs();
            let exact = pair_intersects(&s1, &s2, margin);
            let may = pair_may_intersect(&s1, &s2, margin);
            assert!(may || !exact, "case {case}: {s1:?} {s2:?} at {margin}");
            meet += usize::from(exact);
            filtered += usize::from(!may);
        }
        assert!(
            meet > 1000 && filtered > 1000,
            "{meet} meet, {filtered} filtered out"
        );
    }

    #[test]
    fn boxes_meet_within_a_margin_exactly_when_their_distance_says() {
        let mut next = uniform(3);
        let (mut corners, mut cases) = (0, 0);
        for case in 0..5000 {
            let mut cuboid = |spread: f64| Placed::Cuboid {
                pose: Isometry3::from_parts(
                    nalgebra::Translation3::new(next() * spread, next() * spread, next() * spread),
                    UnitQuaternion::from_euler_angles(next() * 3.0, next() * 1.5, next() * 3.0),
                ),
                half: V::new(0.02 + 0.05 * next().abs(), 0.01 + 0.03 * next().abs(), 0.02),
            };
            let (b1, b2) = (cuboid(0.12), cuboid(0.0));
            let margin = 0.03 * next().abs();
            let d = pair_distance(&b1, &b2);
            if (d - margin).abs() < 1e-9 {
                continue;
            }
            cases += 1;
            assert_eq!(
                pair_intersects(&b1, &b2, margin),
                d <= margin,
                "case {case}: {d}"
            );
            // Past a face's slab of the grown box, where growing it along its axes would hit.
            let grown = match b1 {
                Placed::Cuboid { pose, half } => Placed::Cuboid {
                    pose,
                    half: half + V::repeat(margin),
                },
                _ => unreachable!(),
            };
            corners += usize::from(d > margin && pair_distance(&grown, &b2) <= 0.0);
        }
        assert!(
            cases > 4000 && corners > 20,
            "{cases} cases, {corners} at corners"
        );
    }

    #[test]
    fn segments_meet_boxes_as_clipping_says() {
        let half = V::new(1.0, 0.5, 0.25);
        let meets = |p: [f64; 3], q: [f64; 3]| segment_meets_box(&P::from(p), &P::from(q), &half);
        assert!(meets([0.0; 3], [0.0; 3]), "a point inside");
        assert!(meets([-2.0, 0.0, 0.0], [2.0, 0.0, 0.0]), "through");
        assert!(
            meets([1.0, 0.5, 0.25], [3.0, 3.0, 3.0]),
            "touching a corner"
        );
        assert!(!meets([1.1, 0.0, 0.0], [3.0, 0.0, 0.0]), "beyond a face");
        assert!(
            !meets([0.0, 0.6, -1.0], [0.0, 0.6, 1.0]),
            "parallel, outside"
        );
        assert!(
            !meets([2.0, 0.0, 0.0], [0.0, 2.0, 0.0]),
            "past the corner region"
        );
        assert!(meets([1.4, 0.0, 0.0], [0.0, 1.4, 0.0]), "across the corner");
    }

    fn cyl(a: [f64; 3], b: [f64; 3], r: f64) -> Placed {
        Placed::Cylinder {
            a: P::from(a),
            b: P::from(b),
            radius: r,
            border: 0.0,
        }
    }

    #[test]
    fn cylinder_plane_distance_is_the_lowest_rim_point() {
        // Upright: the end face. Lying: the side. Tilted 45°: rim r·√½ below the low face centre.
        assert!(
            (plane_distance(&cyl([0., 0., 0.1], [0., 0., 0.3], 0.05), 0.0) - 0.1).abs() < 1e-15
        );
        assert!(
            (plane_distance(&cyl([0., 0., 0.1], [0.2, 0., 0.1], 0.05), 0.0) - 0.05).abs() < 1e-15
        );
        let h = 0.1 / 2f64.sqrt();
        let tilted = cyl([0., 0., 0.2], [h, 0., 0.2 + h], 0.05);
        assert!((plane_distance(&tilted, 0.0) - (0.2 - 0.05 * 0.5f64.sqrt())).abs() < 1e-12);
    }

    #[test]
    fn flat_ends_do_not_reach_as_far_as_round_caps() {
        // A point 1 cm beyond the flat end, on the axis: clear of the cylinder, inside the
        // capsule of the same segment and radius.
        let c = cyl([0., 0., 0.], [0., 0., 0.1], 0.06);
        let probe = cap([0., 0., 0.11], [0., 0., 0.11], 0.0);
        assert!(!pair_intersects(&c, &probe, 0.0));
        assert!((pair_distance(&c, &probe) - 0.01).abs() < 1e-9);
        assert!(pair_intersects(&c, &probe, 0.0101));
        let capsule = cap([0., 0., 0.], [0., 0., 0.1], 0.06);
        assert!(pair_intersects(&capsule, &probe, 0.0));
    }

    /// The yes/no segment–cylinder search answers as the full search does at every distance
    /// asked, the segments placed through, near and far from the cylinders.
    #[test]
    fn segment_cylinder_within_answers_as_the_distance() {
        let mut u = uniform(17);
        let mut pt = |s: f64| P::new(s * u(), s * u(), s * u());
        let (mut near, mut far) = (0, 0);
        for i in 0..3000 {
            let (a, b) = (pt(0.1), pt(0.1));
            let (p, q) = (pt(0.3), pt(0.3));
            let r = 0.01 + 0.03 * (i % 7) as f64 / 7.0;
            let d = segment_cylinder_distance(&p, &q, &a, &b, r);
            for dist in [0.0, 0.005, 0.02, 0.1] {
                let within = segment_cylinder_within(&p, &q, &a, &b, r, dist);
                assert_eq!(within, d <= dist, "case {i}, dist {dist}: d = {d}");
                if within {
                    near += 1;
                } else {
                    far += 1;
                }
            }
        }
        assert!(near > 1000 && far > 1000, "{near} near, {far} far");
    }

    #[test]
    fn cylinder_pairs_agree_with_parry() {
        // Random cylinder–capsule, cylinder–cylinder and cylinder–box pairs: the exact
        // segment–cylinder distance and the cascades agree with parry's GJK distance.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let pt = |rng: &mut rand_chacha::ChaCha8Rng| {
            P::new(
                rng.random_range(-0.2..0.2),
                rng.random_range(-0.2..0.2),
                rng.random_range(-0.2..0.2),
            )
        };
        // The reference: parry's GJK on its own shapes, rounded cylinders as `RoundCylinder`.
        let parry = |s: &Placed| -> (Isometry3<f64>, Box<dyn parry3d_f64::shape::Shape>) {
            match *s {
                Placed::Cylinder {
                    a,
                    b,
                    radius,
                    border,
                } => {
                    let (pose, c) = parry_cylinder(&a, &b, radius);
                    let round = parry3d_f64::shape::RoundCylinder {
                        inner_shape: c,
                        border_radius: border,
                    };
                    (pose, Box::new(round))
                }
                Placed::Capsule { a, b, radius } => {
                    (Isometry3::identity(), Box::new(PCapsule::new(a, b, radius)))
                }
                Placed::Cuboid { pose, half } => (pose, Box::new(PCuboid::new(half))),
            }
        };
        for i in 0..600 {
            let c = Placed::Cylinder {
                a: pt(&mut rng),
                b: pt(&mut rng),
                radius: rng.random_range(0.01..0.08),
                border: if i % 2 == 0 {
                    0.0
                } else {
                    rng.random_range(0.0..0.02)
                },
            };
            let other = match i % 3 {
                0 => Placed::Capsule {
                    a: pt(&mut rng),
                    b: pt(&mut rng),
                    radius: rng.random_range(0.0..0.05),
                },
                1 => Placed::Cylinder {
                    a: pt(&mut rng),
                    b: pt(&mut rng),
                    radius: rng.random_range(0.01..0.05),
                    border: if i % 4 == 1 {
                        0.0
                    } else {
                        rng.random_range(0.0..0.01)
                    },
                },
                _ => Placed::Cuboid {
                    pose: Isometry3::from_parts(
                        pt(&mut rng).coords.into(),
                        UnitQuaternion::from_euler_angles(0.3 * i as f64, 0.2, -0.1),
                    ),
                    half: V::new(0.03, 0.05, 0.02),
                },
            };
            let ((p1, g1), (p2, g2)) = (parry(&c), parry(&other));
            let reference = query::distance(&p1, &*g1, &p2, &*g2).unwrap().max(0.0);
            let d = pair_distance(&c, &other).max(0.0);
            assert!((d - reference).abs() < 1e-5, "case {i}: {d} vs {reference}");
            for margin in [0.0, 0.01] {
                if (reference - margin).abs() > 1e-5 {
                    assert_eq!(
                        pair_intersects(&c, &other, margin),
                        reference <= margin,
                        "case {i}, margin {margin}: d = {reference}"
                    );
                }
            }
        }
    }

    #[test]
    fn aabb_of_rotated_cuboid_contains_corners() {
        let pose = Isometry3::from_parts(
            nalgebra::Translation3::new(1., 2., 3.),
            UnitQuaternion::from_euler_angles(0.4, 0.2, -0.7),
        );
        let half = V::new(0.3, 0.2, 0.1);
        let (lo, hi) = Bounded::new(Placed::Cuboid { pose, half }).aabb();
        for s in 0..8 {
            let l = P::new(
                if s & 1 == 0 { -half.x } else { half.x },
                if s & 2 == 0 { -half.y } else { half.y },
                if s & 4 == 0 { -half.z } else { half.z },
            );
            let w = pose * l;
            for i in 0..3 {
                assert!(w[i] >= lo[i] - 1e-12 && w[i] <= hi[i] + 1e-12);
            }
        }
    }
}
