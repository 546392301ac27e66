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
use parry3d_f64::shape::{
    Cuboid as PCuboid, Cylinder as PCylinder, Segment as PSegment, SupportMap,
};

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
            let row = crate::distance::world_up_in(pose);
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

mod cylinder;
mod pair;

pub use cylinder::{segment_cylinder_distance, segment_cylinder_within};
use pair::point_box_sq;
pub use pair::{pair_distance, pair_intersects, pair_may_intersect};

#[cfg(test)]
mod tests;
