//! Convex primitives placed in the world frame, with their bounding volumes and pair tests.
//!
//! Every arm link, gripper part and static obstacle is one [`Placed`] primitive: a capsule
//! (segment `[a, b]` inflated by `radius`; a sphere when `a == b`) or an oriented cuboid.
//! Pair tests run from cheap to exact: bounding spheres first, then closed forms for
//! capsule–capsule (segment–segment distance) and anything–plane (support function along
//! `z`), and parry's GJK only for pairs involving a cuboid.
//!
//! Distances are signed where a closed form gives it (capsules, plane): `≤ 0` means contact,
//! a negative value is a penetration depth estimate. Parry-backed pairs return `0` in contact.

use nalgebra::{Isometry3, Point3, Vector3};
use parry3d_f64::query;
use parry3d_f64::shape::{Capsule as PCapsule, Cuboid as PCuboid, Segment as PSegment};

use crate::distance::segment_segment_sq;

type P = Point3<f64>;
type V = Vector3<f64>;

/// One convex primitive in the world frame (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Placed {
    /// Points within `radius` of the segment `[a, b]`.
    Capsule { a: P, b: P, radius: f64 },
    /// The box `|x_i| ≤ half_i` in the frame `pose` (box frame → world).
    Cuboid { pose: Isometry3<f64>, half: V },
}

/// A placed primitive with its bounding sphere (centre, radius) cached.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bounded {
    pub shape: Placed,
    pub center: P,
    pub radius: f64,
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
    };

    #[inline]
    pub fn new(shape: Placed) -> Self {
        let (center, radius) = match shape {
            Placed::Capsule { a, b, radius } => {
                (nalgebra::center(&a, &b), 0.5 * (b - a).norm() + radius)
            }
            Placed::Cuboid { pose, half } => (P::from(pose.translation.vector), half.norm()),
        };
        Bounded {
            shape,
            center,
            radius,
        }
    }

    /// Axis-aligned bounding box `(min, max)` of the primitive.
    #[inline]
    pub fn aabb(&self) -> (P, P) {
        match self.shape {
            Placed::Capsule { a, b, radius } => {
                let r = V::repeat(radius);
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
#[inline]
pub fn plane_distance(shape: &Placed, height: f64) -> f64 {
    match shape {
        Placed::Capsule { a, b, radius } => a.z.min(b.z) - radius - height,
        Placed::Cuboid { pose, half } => {
            let m = pose.rotation.to_rotation_matrix();
            let row = m.matrix().row(2);
            let ext = row[0].abs() * half.x + row[1].abs() * half.y + row[2].abs() * half.z;
            pose.translation.vector.z - ext - height
        }
    }
}

/// Distance between two primitives (signed for capsule pairs, `0` in contact otherwise).
pub fn pair_distance(s1: &Placed, s2: &Placed) -> f64 {
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
    }
}

/// Whether two primitives are closer than `margin` (touching counts when `margin == 0`).
///
/// Exact for capsule pairs and capsule–box (the capsule radius grows by `margin`); for
/// box–box the margin grows one box's half extents, which is conservative by at most
/// `(√3 − 1)·margin` near its corners.
#[inline]
pub fn pair_intersects(s1: &Placed, s2: &Placed, margin: f64) -> bool {
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
            // Margin by growing one box (conservative at its edges and corners), then SAT.
            let (c1, c2) = (PCuboid::new(h1 + V::repeat(margin)), PCuboid::new(*h2));
            query::intersection_test(p1, &c1, p2, &c2).unwrap_or(true)
        }
    }
}

/// Capsule `([a, b], r)` vs oriented box: a sphere–box reject on the capsule's bounding
/// sphere first (closed form: clamp the centre into the box), then parry's GJK.
#[inline]
fn capsule_cuboid_intersects(a: &P, b: &P, r: f64, pose: &Isometry3<f64>, half: &V) -> bool {
    let la = pose.inverse_transform_point(a);
    let lb = pose.inverse_transform_point(b);
    // Point–box distance of each endpoint: if one endpoint sphere already touches, done.
    let point_box_sq = |p: &P| -> f64 {
        let mut d = 0.0;
        for i in 0..3 {
            let e = (p[i].abs() - half[i]).max(0.0);
            d += e * e;
        }
        d
    };
    if point_box_sq(&la) <= r * r || point_box_sq(&lb) <= r * r {
        return true;
    }
    let c = nalgebra::center(&la, &lb);
    let reach = 0.5 * (lb - la).norm() + r;
    if point_box_sq(&c) > reach * reach {
        return false;
    }
    let cap = PCapsule::new(la, lb, r);
    query::intersection_test(
        &Isometry3::identity(),
        &cap,
        &Isometry3::identity(),
        &PCuboid::new(*half),
    )
    .unwrap_or(true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::UnitQuaternion;

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
