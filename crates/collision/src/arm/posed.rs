//! An arm posed at a configuration: its shapes placed in the world frame from their local
//! primitives, frame by frame, only where a query asks for them.

use std::cell::Cell;

use nalgebra::{Isometry3, Point3};
use pregrasp_robot::{GripperState, Primitive};

use crate::shape::{Bounded, Placed};
use crate::tight::{Lookup, Part};

use super::{ShapeSet, MAX_ARM_SHAPES, MAX_GRIPPER_SHAPES};

/// An arm link's primitive ready to be posed: in its frame, a rounded cylinder already as its
/// inset core, with the bounding sphere's radius (the same in every pose) grown by the exact
/// pieces' `slack`, which the sphere must hold too.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Local {
    pub(super) shape: Placed,
    pub(super) radius: f64,
    pub(super) slack: f64,
}

impl Local {
    pub(super) fn new(prim: &Primitive, slack: f64) -> Self {
        let b = Bounded::new(place(&Isometry3::identity(), prim));
        Local {
            shape: b.shape,
            radius: b.radius + slack,
            slack,
        }
    }

    /// The primitive in the world, its frame at `t`.
    #[inline]
    pub(super) fn place(&self, t: &Isometry3<f64>) -> Bounded {
        let (shape, center) = match self.shape {
            Placed::Capsule { a, b, radius } => {
                let (a, b) = (t * a, t * b);
                (Placed::Capsule { a, b, radius }, nalgebra::center(&a, &b))
            }
            Placed::Cylinder {
                a,
                b,
                radius,
                border,
            } => {
                let (a, b) = (t * a, t * b);
                let shape = Placed::Cylinder {
                    a,
                    b,
                    radius,
                    border,
                };
                (shape, nalgebra::center(&a, &b))
            }
            Placed::Cuboid { pose, half } => {
                let pose = t * pose;
                let center = nalgebra::Point3::from(pose.translation.vector);
                (Placed::Cuboid { pose, half }, center)
            }
        };
        Bounded {
            shape,
            center,
            radius: self.radius,
            slack: self.slack,
        }
    }
}

/// A primitive of frame `t` placed in the world.
#[inline]
pub(super) fn place(t: &Isometry3<f64>, prim: &Primitive) -> Placed {
    match prim {
        Primitive::Capsule(c) => Placed::Capsule {
            a: t * c.a,
            b: t * c.b,
            radius: c.radius,
        },
        Primitive::Cylinder(c) => {
            let (a, b, radius) = c.inset();
            Placed::Cylinder {
                a: t * a,
                b: t * b,
                radius,
                border: c.border,
            }
        }
        Primitive::Cuboid { pose, half_extents } => Placed::Cuboid {
            pose: t * pose,
            half: *half_extents,
        },
    }
}

/// An arm's primitives placed in the world at one configuration (fixed-size buffer).
#[derive(Clone, Debug)]
pub(crate) struct PosedArm {
    pub(super) shapes: [Bounded; MAX_ARM_SHAPES],
    pub(super) len: usize,
    /// The first `links` shapes are the arm's links, the rest its gripper's.
    pub(super) links: usize,
    /// Per DH frame, a sphere holding its link shapes.
    pub(super) frame_spheres: [Bounded; 7],
    /// The DH frames 0..=6 in the world.
    pub(super) frames: [Isometry3<f64>; 7],
    /// Per gripper shape, the frame its pieces are given in, in the world (valid where the
    /// gripper's shapes are placed).
    pub(super) gripper_frames: [Isometry3<f64>; MAX_GRIPPER_SHAPES],
    /// Whether `gripper_frames` are placed for the current pose.
    pub(super) gripper_frames_placed: bool,
    /// A sphere holding the whole gripper.
    pub(super) gripper: Bounded,
    /// The gripper's state the shapes are placed for.
    pub(super) gripper_state: GripperState,
    /// Bit `k`: shape `k` is placed (a query about a few pairs places only their shapes).
    pub(super) placed: u64,
    /// [`PosedArm::bounds`] once asked, until a shape is placed again: the arm that stands
    /// still through a motion is asked at every check of the other.
    pub(super) bounds: Cell<Option<(Point3<f64>, Point3<f64>)>>,
}

impl PosedArm {
    /// An arm with no shapes (a buffer to pose into). Each use is a buffer of its own, its
    /// bounds cache empty: the `Cell` is meant to be copied out of the constant.
    #[allow(clippy::declare_interior_mutable_const)]
    pub const EMPTY: PosedArm = PosedArm {
        shapes: [Bounded::EMPTY; MAX_ARM_SHAPES],
        len: 0,
        links: 0,
        frame_spheres: [Bounded::EMPTY; 7],
        frames: [IDENTITY; 7],
        gripper_frames: [IDENTITY; MAX_GRIPPER_SHAPES],
        gripper_frames_placed: false,
        gripper: Bounded::EMPTY,
        gripper_state: GripperState::Open,
        placed: 0,
        bounds: Cell::new(None),
    };
}

pub(super) const IDENTITY: Isometry3<f64> = Isometry3 {
    rotation: nalgebra::UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(
        1.0, 0.0, 0.0, 0.0,
    )),
    translation: nalgebra::Translation3::new(0.0, 0.0, 0.0),
};

impl PosedArm {
    #[inline]
    pub fn shapes(&self) -> &[Bounded] {
        &self.shapes[..self.len]
    }

    /// Shape `k` as a solid for the pair tests: its primitive and, for an arm link that has
    /// them, the way to its exact pieces (looked up only when a test needs them).
    #[inline]
    pub(crate) fn part<'a>(&'a self, set: &'a ShapeSet, k: usize) -> Part<'a> {
        Part {
            bounded: &self.shapes[k],
            lookup: Some(Lookup {
                tight: &set.tight,
                parts: &set.parts,
                frames: &self.frames,
                gripper_tight: &set.gripper_tight,
                gripper_frames: &self.gripper_frames,
                k,
            }),
        }
    }

    /// Index range of the gripper's shapes in [`shapes`](Self::shapes).
    #[inline]
    pub fn gripper_range(&self) -> std::ops::Range<usize> {
        self.links..self.len
    }

    /// A sphere holding every gripper shape.
    #[inline]
    pub fn gripper_sphere(&self) -> &Bounded {
        &self.gripper
    }

    /// The sphere holding the link shapes of DH frame `f`.
    #[inline]
    pub fn frame_sphere(&self, f: usize) -> &Bounded {
        &self.frame_spheres[f]
    }

    /// The sphere of shape group `g` (DH frames 0..=6, 7 = the gripper).
    #[inline]
    pub fn group_sphere(&self, g: usize) -> &Bounded {
        if g < 7 {
            &self.frame_spheres[g]
        } else {
            &self.gripper
        }
    }

    /// DH frame `f` (0..=6) in the world.
    #[inline]
    pub fn frame(&self, f: usize) -> &Isometry3<f64> {
        &self.frames[f]
    }

    /// Flange pose in the world (DH frame 6).
    #[inline]
    pub fn flange(&self) -> &Isometry3<f64> {
        &self.frames[6]
    }

    /// Axis-aligned box around the whole arm: the union of the parts' bounding-sphere boxes.
    pub fn bounds(&self) -> (Point3<f64>, Point3<f64>) {
        if let Some(b) = self.bounds.get() {
            return b;
        }
        let mut lo = Point3::from([f64::INFINITY; 3]);
        let mut hi = Point3::from([f64::NEG_INFINITY; 3]);
        for s in self.shapes() {
            let r = nalgebra::Vector3::repeat(s.radius);
            lo = lo.inf(&(s.center - r));
            hi = hi.sup(&(s.center + r));
        }
        self.bounds.set(Some((lo, hi)));
        (lo, hi)
    }
}
