//! One arm of the world: kinematics, base placement, gripper, and its collision primitives
//! cached in their DH link frames, ready to be posed at a configuration.

use nalgebra::Isometry3;
use pregrasp_robot::{
    arm_geometry, Gripper2F85, GripperState, Joints, LinkShape, Primitive, UrKinematics, UrModel,
};

use crate::error::CollisionError;
use crate::shape::{Bounded, Placed};

/// Most primitives (arm links + gripper parts) one arm may have; the posed arm lives in a
/// fixed-size buffer so that a collision check never touches the heap.
pub const MAX_ARM_SHAPES: usize = 24;

/// The primitives of an arm with its gripper in one gripper state (links first, then gripper).
#[derive(Clone, Debug)]
pub(crate) struct ShapeSet {
    /// `(DH frame index 0..=6, primitive in that frame)`.
    pub parts: Vec<(usize, Primitive)>,
    /// `"<arm>/<link>"` for every part.
    pub names: Vec<String>,
    /// Whether the part belongs to the gripper (may touch a grasped part).
    pub is_gripper: Vec<bool>,
    /// Pairs of `parts` that must not touch (link self-collision pairs and gripper vs the
    /// links it must not touch), in a fixed order.
    pub self_pairs: Vec<(u8, u8)>,
}

/// An arm in the world: a UR model at `base` with a Robotiq 2F-85 on its flange.
///
/// Frames: `base` maps the arm's controller base frame into the world; link primitives live
/// in the DH frames of [`UrKinematics::fk_frames`] and gripper primitives in the flange frame.
#[derive(Clone, Debug)]
pub struct ArmModel {
    /// Name used in contact reports (`"left"` → `"left/forearm"`).
    pub name: String,
    /// Kinematics of the arm (base frame).
    pub kin: UrKinematics,
    /// Arm base frame in the world.
    pub base: Isometry3<f64>,
    /// The gripper on the flange.
    pub gripper: Gripper2F85,
    /// Shapes for `[Open, Closed]`.
    sets: [ShapeSet; 2],
}

impl ArmModel {
    /// Builds the arm and caches its link and gripper primitives.
    ///
    /// # Panics
    /// If the robot model has more than [`MAX_ARM_SHAPES`] primitives (a programming error in
    /// the built-in geometry); [`ArmModel::try_new`] reports it instead.
    pub fn new(name: &str, model: UrModel, base: Isometry3<f64>, gripper: Gripper2F85) -> Self {
        match Self::try_new(name, model, base, gripper) {
            Ok(arm) => arm,
            Err(e) => panic!("{e}"),
        }
    }

    /// Builds the arm, reporting an over-large geometry as an error.
    pub fn try_new(
        name: &str,
        model: UrModel,
        base: Isometry3<f64>,
        gripper: Gripper2F85,
    ) -> Result<Self, CollisionError> {
        let geometry = arm_geometry(model);
        let forbidden = Gripper2F85::forbidden_arm_links(&geometry);
        let make = |state: GripperState| -> Result<ShapeSet, CollisionError> {
            let grip: Vec<LinkShape> = gripper.shapes(state);
            let n_links = geometry.links.len();
            let count = n_links + grip.len();
            if count > MAX_ARM_SHAPES {
                return Err(CollisionError::TooManyShapes {
                    arm: name.to_string(),
                    count,
                    max: MAX_ARM_SHAPES,
                });
            }
            let all = geometry.links.iter().chain(grip.iter());
            let parts = all.clone().map(|l| (l.frame, l.primitive)).collect();
            let names = all.map(|l| format!("{name}/{}", l.name)).collect();
            let is_gripper = (0..count).map(|i| i >= n_links).collect();
            let mut self_pairs: Vec<(u8, u8)> = geometry
                .self_collision_pairs
                .iter()
                .map(|&(i, j)| (i as u8, j as u8))
                .collect();
            for g in 0..grip.len() {
                for &l in &forbidden {
                    self_pairs.push((l as u8, (n_links + g) as u8));
                }
            }
            Ok(ShapeSet {
                parts,
                names,
                is_gripper,
                self_pairs,
            })
        };
        let sets = [make(GripperState::Open)?, make(GripperState::Closed)?];
        Ok(ArmModel {
            name: name.to_string(),
            kin: UrKinematics::new(model),
            base,
            gripper,
            sets,
        })
    }

    /// The arm model.
    pub fn model(&self) -> UrModel {
        self.kin.model()
    }

    /// Flange pose in the world: `base · fk(q)`.
    pub fn flange_world(&self, q: &Joints) -> Isometry3<f64> {
        self.base * self.kin.fk(q)
    }

    /// Names of the primitives (`"<arm>/<link>"`) in a gripper state, links first.
    pub fn shape_names(&self, state: GripperState) -> &[String] {
        &self.sets[state_index(state)].names
    }

    pub(crate) fn set(&self, state: GripperState) -> &ShapeSet {
        &self.sets[state_index(state)]
    }

    /// Every primitive placed in the world at `q`.
    pub(crate) fn pose(&self, q: &Joints, state: GripperState) -> PosedArm {
        let set = self.set(state);
        let local = self.kin.fk_frames(q);
        let mut frames = [Isometry3::identity(); 7];
        for (f, l) in frames.iter_mut().zip(local.iter()) {
            *f = self.base * l;
        }
        let mut posed = PosedArm {
            shapes: [Bounded::EMPTY; MAX_ARM_SHAPES],
            len: set.parts.len(),
            flange: frames[6],
        };
        for (slot, (frame, prim)) in posed.shapes.iter_mut().zip(set.parts.iter()) {
            let t = &frames[*frame];
            let placed = match prim {
                Primitive::Capsule(c) => Placed::Capsule {
                    a: t * c.a,
                    b: t * c.b,
                    radius: c.radius,
                },
                Primitive::Cuboid { pose, half_extents } => Placed::Cuboid {
                    pose: t * pose,
                    half: *half_extents,
                },
            };
            *slot = Bounded::new(placed);
        }
        posed
    }

    /// Every primitive of the arm placed in the world at `q` (for viewers and debugging):
    /// `(name, primitive)`.
    pub fn placed_shapes(&self, q: &Joints, state: GripperState) -> Vec<(String, Placed)> {
        let posed = self.pose(q, state);
        let set = self.set(state);
        posed
            .shapes()
            .iter()
            .zip(set.names.iter())
            .map(|(b, n)| (n.clone(), b.shape))
            .collect()
    }

    /// Whether primitive `i` is rigidly attached to the base (DH frame 0): its pose never
    /// depends on `q`, so it is mounted, not moving.
    pub(crate) fn is_base_part(&self, state: GripperState, i: usize) -> bool {
        self.set(state).parts[i].0 == 0
    }
}

#[inline]
fn state_index(state: GripperState) -> usize {
    match state {
        GripperState::Open => 0,
        GripperState::Closed => 1,
    }
}

/// An arm's primitives placed in the world at one configuration (stack buffer).
#[derive(Clone, Debug)]
pub(crate) struct PosedArm {
    shapes: [Bounded; MAX_ARM_SHAPES],
    len: usize,
    flange: Isometry3<f64>,
}

impl PosedArm {
    #[inline]
    pub fn shapes(&self) -> &[Bounded] {
        &self.shapes[..self.len]
    }

    /// Flange pose in the world.
    #[inline]
    pub fn flange(&self) -> &Isometry3<f64> {
        &self.flange
    }

    /// Axis-aligned bounding box of the whole arm (union of the parts' boxes).
    pub fn bounds(&self) -> (nalgebra::Point3<f64>, nalgebra::Point3<f64>) {
        let mut lo = nalgebra::Point3::from([f64::INFINITY; 3]);
        let mut hi = nalgebra::Point3::from([f64::NEG_INFINITY; 3]);
        for s in self.shapes() {
            let (a, b) = s.aabb();
            lo = lo.inf(&a);
            hi = hi.sup(&b);
        }
        (lo, hi)
    }
}
