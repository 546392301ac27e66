//! Conservative collision geometry of the arm links, in the DH frames they move with.
//!
//! Source: the UR5e link envelopes measured from the MuJoCo Menagerie meshes
//! (`shared/facts/ur5e-2f85.md`). Each housing is a cylinder (end-face centres `a`, `b`,
//! radius r) enclosed by a capsule whose segment is inset by `e = min(h, r/2)` from each face
//! (h = half length) and whose radius is `√(r² + e²) + m`: every cylinder point is within
//! `√(r² + e²)` of the segment, so the capsule contains the cylinder grown by the margin
//! `m = 5 mm`. Tubes between two housings use their measured radius rounded up, plus `m`.
//!
//! Placement: lengths along the links come from the model's DH parameters (a2, a3, d5,
//! d6); housing radii and the lateral offsets of the housings along the joint axes are the
//! UR5e values scaled by `k = (d4 + d5 + d6) / (d4 + d5 + d6)_UR5e` (the wrist offsets are
//! set by the housing sizes). Only the UR5e is measured; the other models are this scaling,
//! not a measurement.
//!
//! DH frames at q = 0 (UR5e, base coordinates): frames 1–3 have x = X, y = Z, z = −Y;
//! frame 4 has x = X, y = −Y, z = −Z; frames 5 and 6 have x = X, y = Z, z = −Y. The link
//! carried by joint i is expressed in DH frame i (shoulder 1, upper arm 2, forearm 3,
//! wrist_1 4, wrist_2 5, wrist_3 6); the base is in frame 0.

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

use crate::gripper::{Gripper2F85, GripperState};
use crate::model::{Joints, UrModel};

/// Safety margin added around every measured envelope (m).
pub const LINK_MARGIN: f64 = 0.005;

/// Sum d4 + d5 + d6 of the UR5e (m), the reference for the housing scale.
const UR5E_WRIST_SUM: f64 = 0.1333 + 0.0997 + 0.0996;

/// A capsule: the points within `radius` of the segment `a`–`b` (a sphere when `a == b`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    /// First segment end, in the owning frame (m).
    pub a: Point3<f64>,
    /// Second segment end, in the owning frame (m).
    pub b: Point3<f64>,
    /// Radius (m).
    pub radius: f64,
}

impl Capsule {
    /// Smallest capsule of this construction containing the cylinder with end-face centres
    /// `a`, `b` and radius `r`, grown by [`LINK_MARGIN`] (see the module documentation).
    pub fn enclosing_cylinder(a: Point3<f64>, b: Point3<f64>, r: f64) -> Capsule {
        let axis = b - a;
        let h = 0.5 * axis.norm();
        let e = h.min(0.5 * r);
        let dir = if h > 0.0 {
            axis / (2.0 * h)
        } else {
            Vector3::zeros()
        };
        Capsule {
            a: a + e * dir,
            b: b - e * dir,
            radius: (r * r + e * e).sqrt() + LINK_MARGIN,
        }
    }

    /// A tube of radius `r` along `a`–`b` whose ends are buried in housings, grown by
    /// [`LINK_MARGIN`].
    pub fn tube(a: Point3<f64>, b: Point3<f64>, r: f64) -> Capsule {
        Capsule {
            a,
            b,
            radius: r + LINK_MARGIN,
        }
    }

    /// Distance from `p` to the capsule's segment (m).
    pub fn segment_distance(&self, p: &Point3<f64>) -> f64 {
        let ab = self.b - self.a;
        let len2 = ab.norm_squared();
        let t = if len2 > 0.0 {
            ((p - self.a).dot(&ab) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (p - (self.a + t * ab)).norm()
    }

    /// True when `p` lies inside (or on) the capsule.
    pub fn contains(&self, p: &Point3<f64>) -> bool {
        self.segment_distance(p) <= self.radius
    }
}

/// A collision primitive in the frame of the link that carries it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Primitive {
    /// A capsule (a sphere when both ends coincide).
    Capsule(Capsule),
    /// A box with its centre and axes at `pose` in the owning frame.
    Cuboid {
        /// Pose of the box centre in the owning frame.
        pose: Isometry3<f64>,
        /// Half side lengths (m).
        half_extents: Vector3<f64>,
    },
}

impl Primitive {
    /// An axis-aligned box spanning `[lo, hi]` in the owning frame.
    pub fn aabb(lo: Vector3<f64>, hi: Vector3<f64>) -> Primitive {
        let c = 0.5 * (lo + hi);
        Primitive::Cuboid {
            pose: Isometry3::from_parts(Translation3::from(c), UnitQuaternion::identity()),
            half_extents: 0.5 * (hi - lo),
        }
    }

    /// Largest distance from the owning frame's origin to a point of the primitive (m).
    pub fn max_origin_distance(&self) -> f64 {
        match self {
            Primitive::Capsule(c) => c.a.coords.norm().max(c.b.coords.norm()) + c.radius,
            Primitive::Cuboid { pose, half_extents } => {
                pose.translation.vector.norm() + half_extents.norm()
            }
        }
    }
}

/// One named collision shape attached to a DH frame.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkShape {
    /// Shape name, e.g. "upper_arm_tube" or "gripper_body".
    pub name: &'static str,
    /// Index into [`crate::UrKinematics::fk_frames`] (0 = base … 6 = flange/wrist_3).
    pub frame: usize,
    /// The shape, in that frame.
    pub primitive: Primitive,
}

/// Conservative collision model of an arm.
#[derive(Clone, Debug)]
pub struct ArmGeometry {
    /// Link shapes; `frame` indexes `fk_frames`.
    pub links: Vec<LinkShape>,
    /// Pairs `(i, j)`, `i < j`, of indices into `links` that must not touch.
    pub self_collision_pairs: Vec<(usize, usize)>,
}

impl ArmGeometry {
    /// Index of the shape called `name`, if any.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.name == name)
    }
}

/// Housing scale of `model` relative to the UR5e (see the module documentation).
pub fn housing_scale(model: UrModel) -> f64 {
    let dh = model.dh();
    (dh.d4 + dh.d5 + dh.d6) / UR5E_WRIST_SUM
}

fn p(x: f64, y: f64, z: f64) -> Point3<f64> {
    Point3::new(x, y, z)
}

/// Conservative link shapes of `model` and the shape pairs checked for self-collision.
///
/// Self-collision pairs: every pair of shapes on links two or more joints apart, except
/// pairs whose distance no joint motion can change or that the mechanism keeps apart:
/// wrist_1 vs wrist_3 (wrist_3 is a solid of revolution about z5, which only turns about
/// z4 at a fixed offset from wrist_1) and the base vs the upper arm's shoulder housing (a
/// solid of revolution about the shoulder-lift axis, at a fixed height above the base).
pub fn arm_geometry(model: UrModel) -> ArmGeometry {
    let dh = model.dh();
    let k = housing_scale(model);
    let (a2, a3, d4, d5, d6) = (-dh.a2, -dh.a3, dh.d4, dh.d5, dh.d6); // |a2|, |a3| > 0
    let cyl = |frame, name, a, b, r| LinkShape {
        name,
        frame,
        primitive: Primitive::Capsule(Capsule::enclosing_cylinder(a, b, r)),
    };
    let tube = |frame, name, a, b, r| LinkShape {
        name,
        frame,
        primitive: Primitive::Capsule(Capsule::tube(a, b, r)),
    };
    let m = LINK_MARGIN;
    let base_r = 0.0755 * k + m;
    let links = vec![
        // Base: Ø151 mm foot whose top is 64 mm below the shoulder axis (UR5e: z 0…0.099),
        // as a box from 2 mm above the mounting plane (so the mounting surface itself does
        // not register) to the top plus margin.
        LinkShape {
            name: "base",
            frame: 0,
            primitive: Primitive::aabb(
                Vector3::new(-base_r, -base_r, 0.002),
                Vector3::new(base_r, base_r, dh.d1 - 0.064 * k + m),
            ),
        },
        // Shoulder (frame 1 at the shoulder-lift axis; y = up, z = towards the upper arm).
        cyl(
            1,
            "shoulder_pan",
            p(0.0, -0.064 * k, 0.0),
            p(0.0, 0.072 * k, 0.0),
            0.060 * k,
        ),
        cyl(
            1,
            "shoulder_lift",
            p(0.0, 0.0, -0.060 * k),
            p(0.0, 0.0, 0.074 * k),
            0.060 * k,
        ),
        // Upper arm (frame 2 at the elbow axis; the shoulder axis is at x = |a2|).
        cyl(
            2,
            "upper_arm_shoulder",
            p(a2, 0.0, 0.060 * k),
            p(a2, 0.0, 0.216 * k),
            0.060 * k,
        ),
        tube(
            2,
            "upper_arm_tube",
            p(a2, 0.0, 0.138 * k),
            p(0.0, 0.0, 0.138 * k),
            0.050 * k,
        ),
        cyl(
            2,
            "upper_arm_elbow",
            p(0.0, 0.0, 0.060 * k),
            p(0.0, 0.0, 0.216 * k),
            0.060 * k,
        ),
        // Forearm (frame 3 at the wrist-1 axis; the elbow axis is at x = |a3|).
        cyl(
            3,
            "forearm_elbow",
            p(a3, 0.0, -0.050 * k),
            p(a3, 0.0, 0.060 * k),
            0.058 * k,
        ),
        tube(
            3,
            "forearm_tube",
            p(a3, 0.0, 0.007 * k),
            p(0.0, 0.0, 0.007 * k),
            0.040 * k,
        ),
        cyl(
            3,
            "forearm_wrist",
            p(0.0, 0.0, -0.050 * k),
            p(0.0, 0.0, 0.060 * k),
            0.040 * k,
        ),
        // Wrist 1 (frame 4 on the wrist-2 axis; y = −(wrist-1 axis offset), z = wrist-2 axis).
        cyl(
            4,
            "wrist_1_joint",
            p(0.0, -(d4 - 0.060 * k), 0.0),
            p(0.0, 0.0, 0.0),
            0.040 * k,
        ),
        cyl(
            4,
            "wrist_1_housing",
            p(0.0, 0.0, -0.056 * k),
            p(0.0, 0.0, d5 - 0.046 * k),
            0.040 * k,
        ),
        // Wrist 2 (frame 5 at o5; z = wrist-3 axis, y back towards wrist 1).
        cyl(
            5,
            "wrist_2_housing",
            p(0.0, 0.0, -0.056 * k),
            p(0.0, 0.0, d6 - 0.046 * k),
            0.040 * k,
        ),
        cyl(
            5,
            "wrist_2_joint",
            p(0.0, 0.0, 0.0),
            p(0.0, d5 - 0.054 * k, 0.0),
            0.040 * k,
        ),
        // Wrist 3 (frame 6 = flange; the disc between the wrist-2 housing and the flange face).
        cyl(
            6,
            "wrist_3_flange",
            p(0.0, 0.0, -0.046 * k),
            p(0.0, 0.0, 0.0),
            0.044 * k,
        ),
    ];
    let excluded = |a: &LinkShape, b: &LinkShape| {
        let frames = (a.frame.min(b.frame), a.frame.max(b.frame));
        frames == (4, 6)
            || (a.name == "base" && b.name == "upper_arm_shoulder")
            || (b.name == "base" && a.name == "upper_arm_shoulder")
    };
    let mut self_collision_pairs = Vec::new();
    for i in 0..links.len() {
        for j in i + 1..links.len() {
            if links[i].frame.abs_diff(links[j].frame) >= 2 && !excluded(&links[i], &links[j]) {
                self_collision_pairs.push((i, j));
            }
        }
    }
    ArmGeometry {
        links,
        self_collision_pairs,
    }
}

/// For edge-validation resolution: for each joint i, an upper bound on the distance from
/// joint axis i to any point of the arm links beyond it plus the gripper (m), open or
/// closed. Moving joint i by Δ rad moves any point by at most `radius_i·|Δ|`, so
/// `Σ radius_i·|Δq_i|` bounds any point's displacement.
///
/// Bound: joint i's axis passes through the origin of DH frame i−1; a point of a shape in
/// frame f ≥ i is within `Σ_{j=i..f} √(a_j² + d_j²)` (origin-to-origin link offsets) plus
/// the shape's largest distance from its own frame origin.
pub fn joint_sweep_radii(model: UrModel, gripper: &Gripper2F85) -> Joints {
    let dh = model.dh();
    let geometry = arm_geometry(model);
    let offset: [f64; 6] = std::array::from_fn(|j| {
        let (d, a, _) = dh.row(j);
        a.hypot(d)
    });
    let mut reach_in_frame = [0.0f64; 7];
    for shape in &geometry.links {
        let r = shape.primitive.max_origin_distance();
        reach_in_frame[shape.frame] = reach_in_frame[shape.frame].max(r);
    }
    for state in [GripperState::Open, GripperState::Closed] {
        for shape in gripper.shapes(state) {
            let r = shape.primitive.max_origin_distance();
            reach_in_frame[6] = reach_in_frame[6].max(r);
        }
    }
    let r6 = reach_in_frame[6]
        .max(gripper.precision_point_z.abs())
        .max(gripper.power_point_z.abs());
    reach_in_frame[6] = r6;
    std::array::from_fn(|i| {
        // Joint i (0-based) moves frames i+1..=6; its axis passes through frame i's origin.
        (i + 1..=6)
            .map(|f| offset[i..f].iter().sum::<f64>() + reach_in_frame[f])
            .fold(0.0, f64::max)
    })
}
